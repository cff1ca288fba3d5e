//! A performance regression check without a GPU: the work per ray of Table 3's tests and of
//! the real assets' scene workload on the `compute` back-end's merged layout, counted by the CPU
//! mirror of its traversal (`bench roofline`: interior nodes, leaves, triangle tests and
//! instances per ray, and the bytes the WGSL loads for them), against the committed baseline
//! `tests/baselines/traversal_work.csv`. A tree or traversal change that adds more than
//! [`MORE_WORK_ALLOWED`] of work to any row fails with the counts printed; less work passes and
//! is printed. The baseline moves only with a reason: `RAYGRAPH_WORK_BASELINE_REASON="why"`
//! rewrites it with the reason in its header and prints the old and new counts.
//!
//! The counts are deterministic (the CPU builder and the rays are; the test checks one scene
//! twice), so the allowance is for floating-point differences between machines, not noise.

mod common;

use raygraph::bench::roofline::{self, RooflineRow};
use raygraph::scene::{open, LoadOptions, Scene};

/// Every `STRIDE`-th pixel of 2560x1440 in each direction, `AO_RAYS` AO rays per hit.
const STRIDE: u32 = 32;
const AO_RAYS: u32 = 8;
/// More work than the baseline by this fraction fails a row.
const MORE_WORK_ALLOWED: f64 = 0.005;

fn scene(name: &str) -> Scene {
    let path = common::repo().join(name);
    let spec = if path.exists() { path.to_string_lossy().into_owned() } else { name.to_string() };
    open(&spec, &LoadOptions { textures: false, ..Default::default() }).unwrap().0
}

/// The rows: the scene workload on the built-in scenes and the real assets, and the primary
/// tests on the atrium.
fn rows() -> Vec<RooflineRow> {
    let bandwidth = roofline::H100_L1_BYTES_PER_S;
    let scenes = [
        ("box", "box"),
        ("organic", "organic"),
        ("atrium", "atrium"),
        ("helmet", "assets/gltf/DamagedHelmet/DamagedHelmet.glb"),
        ("pine", "assets/gltf/smallpine/scene.gltf"),
    ];
    let mut rows: Vec<RooflineRow> = scenes
        .iter()
        .map(|(label, name)| {
            let mut s = scene(name);
            s.set_name(*label);
            roofline::scene_workload(&s, STRIDE, AO_RAYS, bandwidth)
        })
        .collect();
    let atrium = scene("atrium");
    let miss = raygraph::bench::rays::miss_outside_camera(&atrium);
    rows.push(roofline::primary_workload("Miss (outside)", &atrium, &miss, STRIDE, bandwidth));
    for (test, preset) in [("Miss (inside)", raygraph::bench::rays::MISS_INSIDE_PRESET), ("Stress", raygraph::bench::rays::STRESS_PRESET)] {
        rows.push(roofline::primary_workload(test, &atrium, &atrium.preset(preset).unwrap(), STRIDE, bandwidth));
    }
    rows
}

/// A row as the baseline's CSV line: test, rays, interior, leaves, triangles, instances per ray,
/// bytes per ray.
fn line(r: &RooflineRow) -> String {
    format!("{},{},{:.4},{:.4},{:.4},{:.4},{:.2}", r.test, r.rays, r.per_ray[0], r.per_ray[1], r.per_ray[2], r.per_ray[3], r.bytes_per_ray)
}

fn values(line: &str) -> (String, Vec<f64>) {
    let mut cells = line.split(',');
    let test = cells.next().unwrap_or_default().to_string();
    (test, cells.map(|c| c.parse().unwrap()).collect())
}

#[test]
fn traversal_work_per_ray_is_no_more_than_the_baseline() {
    let baseline_path = common::repo().join("tests/baselines/traversal_work.csv");
    let measured: Vec<String> = rows().iter().map(line).collect();
    let again = roofline::scene_workload(&scene("organic"), STRIDE, AO_RAYS, roofline::H100_L1_BYTES_PER_S);
    assert_eq!(line(&again), measured[1], "the counts are deterministic");
    let header = "test,rays,interior_per_ray,leaves_per_ray,triangles_per_ray,instances_per_ray,bytes_per_ray";
    let old = std::fs::read_to_string(&baseline_path).unwrap_or_default();
    if let Ok(reason) = std::env::var("RAYGRAPH_WORK_BASELINE_REASON") {
        assert!(!reason.trim().is_empty(), "RAYGRAPH_WORK_BASELINE_REASON: say why the baseline moves");
        println!("old baseline:\n{old}\nnew counts:\n{}", measured.join("\n"));
        let text = format!("# stride {STRIDE}, {AO_RAYS} AO rays; moved because: {reason}\n{header}\n{}\n", measured.join("\n"));
        std::fs::write(&baseline_path, text).unwrap();
        return;
    }
    let base: Vec<(String, Vec<f64>)> = old.lines().filter(|l| !l.starts_with('#') && *l != header).map(values).collect();
    assert_eq!(base.len(), measured.len(), "one baseline row per test ({}):\n{old}", baseline_path.display());
    let mut more = Vec::new();
    for ((test, was), now) in base.iter().zip(measured.iter().map(|l| values(l))) {
        assert_eq!(test, &now.0, "the same tests in the same order");
        assert_eq!(was[0], now.1[0], "{test}: the same rays");
        for (k, name) in ["interior nodes", "leaves", "triangle tests", "instances", "bytes"].iter().enumerate() {
            let (w, n) = (was[k + 1], now.1[k + 1]);
            if n > w * (1.0 + MORE_WORK_ALLOWED) + 1e-4 {
                more.push(format!("{test}: {name} per ray {w} -> {n} (+{:.2}%)", 100.0 * (n / w.max(1e-9) - 1.0)));
            } else if n < w * (1.0 - MORE_WORK_ALLOWED) {
                println!("{test}: {name} per ray {w} -> {n}: less work; move the baseline with a reason");
            }
        }
    }
    assert!(more.is_empty(), "more work per ray than the baseline:\n{}", more.join("\n"));
}
