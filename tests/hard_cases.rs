//! The numerically hard cases (`raygraph::selftest::hard_cases`, the code `raygraph selftest`
//! runs), each on every traversal back-end and layout (`compute` with two levels, `compute` with
//! the merged layout, `ray-query`, `rt-pipeline` with both layouts): lavapipe must run every
//! one, so a back-end it lacks fails here instead of being skipped. The single-sided case also
//! runs on the CPU mirror of the `compute` traversal.

mod common;

use raygraph::selftest::hard_cases;
use raygraph::selftest::{Case, Target, VARIANTS};

/// Runs the case named `name` on every back-end and layout, printing what it measured; every
/// variant must be available (lavapipe >= 24.1 has ray queries and ray-tracing pipelines).
fn on_every_back_end(name: &str) {
    let gpu = common::gpu();
    let case: Case = hard_cases::CASES.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no hard case {name}")).1;
    let shaders = common::repo().join("shaders");
    let mut failures = Vec::new();
    for variant in VARIANTS {
        let target = Target { gpu: &gpu, variant, shaders: &shaders };
        assert_eq!(target.not_applicable(), None, "CI must test every back-end ({})", variant.name);
        let mut notes = Vec::new();
        let result = target.run_case(case, &mut notes);
        notes.iter().for_each(|n| println!("{n}"));
        if let Err(e) = result {
            failures.push(format!("{}: {e}", variant.name));
        }
    }
    assert!(failures.is_empty(), "{name}:\n{}", failures.join("\n"));
}

#[test]
fn a_closed_perturbed_mesh_hit_from_inside_at_vertices_and_edges_never_lets_a_ray_escape() {
    on_every_back_end("closed perturbed mesh hit from inside");
}

#[test]
fn rays_exactly_along_a_shared_edge_hit_exactly_once() {
    on_every_back_end("rays along a shared edge");
}

#[test]
fn grazing_rays_down_to_1e_minus_7_rad_hit_where_they_should() {
    on_every_back_end("grazing rays");
}

#[test]
fn degenerate_triangles_are_never_hit() {
    on_every_back_end("degenerate triangles");
}

#[test]
fn non_finite_vertices_and_rays_are_dropped_alike_by_every_back_end() {
    on_every_back_end("non-finite vertices and rays");
}

#[test]
fn axis_parallel_rays_starting_on_a_box_face_hit_the_opposite_face() {
    on_every_back_end("axis-parallel rays from a box face");
}

#[test]
fn a_lit_plane_never_shadows_itself_at_any_scale_or_distance() {
    on_every_back_end("lit plane at any scale or distance");
}

#[test]
fn coplanar_overlapping_quads_are_hit_once() {
    on_every_back_end("coplanar overlapping quads");
}

#[test]
fn a_thin_ao_occluder_occludes_every_ray_down_to_1e_minus_3_r() {
    on_every_back_end("thin AO occluder");
}

#[test]
fn a_wall_1e_minus_4_thick_leaks_no_light() {
    on_every_back_end("wall 1e-4 thick");
}

#[test]
fn a_camera_inside_a_closed_box_sees_only_back_faces() {
    on_every_back_end("camera inside a closed box");
}

#[test]
fn a_ray_spawned_from_a_hit_never_rehits_its_own_triangle() {
    on_every_back_end("rays spawned from hits");
}

#[test]
fn single_sided_occluders_with_and_without_back_face_culling() {
    on_every_back_end("single-sided occluders and back-face culling");
}

/// The single-sided case on the CPU mirror of the `compute` traversal.
#[test]
fn single_sided_occluders_on_the_cpu_mirror() {
    let mut notes = Vec::new();
    let result = hard_cases::single_sided_occluders_on_the_cpu(&mut notes);
    notes.iter().for_each(|n| println!("{n}"));
    result.unwrap();
}
