//! The compute back-end's trace modules written without the traversal stack's clear
//! (`runtime::trace_spirv`) against the same modules compiled from WGSL, which clear it: the
//! same images, bit for bit, in full ray tracing and hybrid, on the built-in scenes and an
//! alpha-tested real asset (the alpha test compiled in); the same closest hits from the batch
//! tracer. On lavapipe (Vulkan, passthrough shaders) the path without the clear must be the one
//! in use, so CI exercises it.

mod common;

use raygraph::backend::Backend;
use raygraph::graph::compile::compile_with;
use raygraph::graph::Project;
use raygraph::runtime::batch::{BatchTracer, GpuRay};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::Scene;

const SIZE: (u32, u32) = (96, 64);

/// The tone-mapped output of one frame of `graph` on the compute back-end.
fn render(gpu: &Gpu, graph: &str, scene: &Scene) -> Vec<u8> {
    let options = gpu.compile_options_for(Backend::Compute);
    let path = common::repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    exec.read_output(gpu).unwrap().into_raw()
}

#[test]
fn images_without_the_stack_clear_equal_those_with_it() {
    let uncleared = common::gpu();
    assert!(
        !uncleared.traversal_stack_cleared() || std::env::var("RAYGRAPH_CLEARED_STACK").is_ok_and(|v| v == "1"),
        "a Vulkan device with passthrough shaders (lavapipe in CI) writes trace modules without the stack clear"
    );
    let mut cleared = common::gpu();
    cleared.clear_traversal_stack();
    assert!(cleared.traversal_stack_cleared());
    let scenes = [
        ("box", raygraph::scene::open("box", &Default::default()).unwrap().0),
        ("atrium", raygraph::scene::open("atrium", &Default::default()).unwrap().0),
        ("smallpine", common::open("assets/gltf/smallpine/scene.gltf")),
    ];
    for (name, scene) in &scenes {
        for graph in ["graph/full_rt.ron", "graph/hybrid.ron"] {
            let a = render(&uncleared, graph, scene);
            let b = render(&cleared, graph, scene);
            let lit = a.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
            assert!(lit > a.len() / 8, "{name} {graph}: a rendered image ({lit} lit pixels)");
            let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
            assert_eq!(differ, 0, "{name} {graph}: {differ} bytes differ between the modules with and without the stack clear");
        }
    }
}

#[test]
fn batch_hits_without_the_stack_clear_equal_those_with_it() {
    let uncleared = common::gpu();
    let mut cleared = common::gpu();
    cleared.clear_traversal_stack();
    let scene = raygraph::scene::open("organic", &Default::default()).unwrap().0;
    let bounds = scene.bounds();
    let (lo, hi) = (bounds.min, bounds.max);
    let centre = (lo + hi) * 0.5;
    // Rays from a sphere around the scene towards points inside its box.
    let rays: Vec<GpuRay> = (0..4096)
        .map(|i| {
            let f = i as f32;
            let dir_out = glam::Vec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.23).sin()).normalize_or(glam::Vec3::X);
            let origin = centre + dir_out * (hi - lo).length();
            let target = lo + (hi - lo) * glam::Vec3::new((f * 0.071).fract(), (f * 0.13).fract(), (f * 0.29).fract());
            GpuRay { origin: origin.to_array(), t_min: 0.0, dir: (target - origin).normalize().to_array(), t_max: f32::MAX }
        })
        .collect();
    let shaders = common::repo().join("shaders");
    let a = BatchTracer::new(&uncleared, Backend::Compute, &scene, &shaders).unwrap().closest(&uncleared, &rays).unwrap().0;
    let b = BatchTracer::new(&cleared, Backend::Compute, &scene, &shaders).unwrap().closest(&cleared, &rays).unwrap().0;
    let hits = a.iter().filter(|h| h.is_some()).count();
    assert!(hits > rays.len() / 4, "rays aimed into the scene hit it ({hits} of {})", rays.len());
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x.map(|h| (h.t.to_bits(), h.instance, h.primitive)), y.map(|h| (h.t.to_bits(), h.instance, h.primitive)), "ray {i}");
    }
}

/// `render --kernel-stats`: the executor keeps each trace module it wrote as SPIR-V (the words
/// given to wgpu, with their entry point and bind group layouts), and the driver's statistics
/// for them come back, or a clear error where the driver does not offer
/// VK_KHR_pipeline_executable_properties (lavapipe 25.0.7 does not).
#[test]
fn recorded_trace_kernels_are_the_modules_the_executor_wrote() {
    let mut gpu = common::gpu();
    if gpu.traversal_stack_cleared() {
        assert!(std::env::var("RAYGRAPH_CLEARED_STACK").is_ok_and(|v| v == "1"), "lavapipe takes SPIR-V");
        return;
    }
    gpu.record_trace_kernels();
    let scene = raygraph::scene::open("box", &Default::default()).unwrap().0;
    render(&gpu, "graph/full_rt.ron", &scene);
    let kernels = gpu.recorded_trace_kernels();
    assert!(!kernels.is_empty(), "the full-RT graph's trace passes were recorded");
    for k in &kernels {
        assert_eq!(k.words.first(), Some(&0x0723_0203), "{}: SPIR-V words", k.label);
        assert_eq!(k.entry, "cs_main", "{}", k.label);
        assert!(!k.groups.is_empty(), "{}: its bind group layouts", k.label);
    }
    assert!(kernels.iter().any(|k| k.label.contains("primary")), "the primary rays' kernel: {:?}", kernels.iter().map(|k| &k.label).collect::<Vec<_>>());
    let name = gpu.adapter().get_info().name;
    match raygraph::runtime::kernel_stats::kernel_statistics(&name, &kernels) {
        Ok(stats) => {
            assert!(stats.len() >= kernels.len(), "an executable per kernel");
            assert!(stats.iter().all(|s| !s.statistics.is_empty()), "statistics for each");
        }
        Err(e) => assert!(e.contains("VK_KHR_pipeline_executable_properties") && e.contains(&name), "a clear error: {e}"),
    }
}
