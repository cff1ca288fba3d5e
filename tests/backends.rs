//! Every traversal back-end against the f64 reference caster, the closed `organic` mesh from
//! inside and invalid rays (`raygraph::selftest::agreement`, the code `raygraph selftest` runs;
//! its module docs give the rays, tolerances and what may disagree), on `compute`, `ray-query`
//! and `rt-pipeline`: lavapipe must run every one. Also: the binding-size limit.

mod common;

use raygraph::scene::Scene;
use raygraph::selftest::agreement::{self, ReferenceScene};
use raygraph::selftest::{suite_variants, Case, Target};

fn scene(name: &str) -> Scene {
    agreement::scene(name).unwrap()
}

/// Runs `check` on every back-end's two-level layout (each must be available on lavapipe),
/// printing what it measured; fails with every back-end's reason.
fn on_every_back_end(check: impl Fn(&Target, &mut Vec<String>) -> Result<(), String>) {
    let gpu = common::gpu();
    let shaders = common::repo().join("shaders");
    let mut failures = Vec::new();
    for variant in suite_variants("agreement") {
        let target = Target { gpu: &gpu, variant, shaders: &shaders };
        assert_eq!(target.not_applicable(), None, "CI must test every back-end ({})", variant.name);
        let mut notes = Vec::new();
        let result = target.run_case_with(&check, &mut notes);
        notes.iter().for_each(|n| println!("{n}"));
        if let Err(e) = result {
            failures.push(format!("{}: {e}", variant.name));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_back_end_agrees_with_the_f64_reference() {
    let references: Vec<ReferenceScene> = agreement::SCENES.iter().map(|&(name, per_group)| ReferenceScene::new(name, per_group).unwrap()).collect();
    on_every_back_end(|target, notes| {
        let mut failures = Vec::new();
        for reference in &references {
            reference.compare(target, &mut failures, notes)?;
        }
        failures.iter().for_each(|f| println!("FAIL {f}"));
        if failures.is_empty() {
            Ok(())
        } else {
            Err(format!("{} rays disagree with the reference beyond the stated tolerances", failures.len()))
        }
    });
}

#[test]
fn no_ray_escapes_the_closed_organic_mesh_from_inside() {
    on_every_back_end(agreement::no_ray_escapes_the_closed_organic_mesh_from_inside as Case);
}

#[test]
fn invalid_rays_are_counted_and_miss_without_a_crash() {
    on_every_back_end(agreement::invalid_rays_are_counted_and_miss_without_a_crash as Case);
}

#[test]
fn a_scene_too_large_for_a_binding_is_refused_with_the_numbers() {
    let s = scene("organic");
    let flat = raygraph::accel::layout::GpuAccel::build(&s, &Default::default());
    let triangles = std::mem::size_of_val(flat.triangles.as_slice()) as u64;
    raygraph::accel::cache::check_fits("organic", &flat, triangles).unwrap();
    let err = raygraph::accel::cache::check_fits("organic", &flat, triangles - 1).unwrap_err().to_string();
    println!("{err}");
    assert!(err.contains(&triangles.to_string()) && err.contains(&(triangles - 1).to_string()) && err.contains("organic"), "{err}");
}
