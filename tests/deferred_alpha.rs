//! The compute back-end's deferred alpha tests (`RAYGRAPH_DEFERRED_ALPHA`, the pipeline constant
//! TRACE_DEFERRED_ALPHA of `shaders/trace/compute.wgsl`) change no bit: AO and shadow rays
//! (`graph/ao.ron` without its `blend` node: both are transmittance rays) through the pine's
//! BLEND leaf cards, and through the same cards cut out (MASK), rendered with 1, 3 and 8 tests
//! deferred against none. One test in this binary: the variable is read when the passes are
//! built.

mod common;

use common::{ao_graph_without_blend, gpu};
use glam::Vec3;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{AlphaMode, Camera, Scene};

const SIZE: (u32, u32) = (48, 36);

/// The bits of the AO and shadow outputs after a frame of `graph/ao.ron` (without its `blend`
/// node) on the compute back-end from `camera`.
fn render(gpu: &Gpu, scene: &Scene, camera: &Camera) -> Vec<u32> {
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    let (path, project) = ao_graph_without_blend();
    let plan = compile_with(&path, &project, SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, camera, scene).unwrap();
    ["ao.ao", "ao/partial", "shadow.direct"].iter().flat_map(|name| common::channel(gpu, &exec, name)).flat_map(|t| t.map(f32::to_bits)).collect()
}

#[test]
fn deferred_alpha_tests_change_no_bit() {
    let gpu = gpu();
    let blend = common::open("assets/gltf/smallpine/scene.gltf");
    let mut cut_out = blend.clone();
    for m in cut_out.materials_mut().iter_mut().filter(|m| m.alpha_mode == AlphaMode::Blend) {
        m.alpha_mode = AlphaMode::Mask(0.5);
    }
    // Close on the trunk (the BLEND cards are not in the G-buffer), and the whole cut-out tree.
    let trunk = Camera::look(Vec3::new(0.0, 12.0, 25.0), Vec3::new(0.0, 12.0, 0.0), 35.0, 0.1, 500.0);
    for (what, scene, camera) in [("BLEND cards", &blend, trunk), ("cut-out cards", &cut_out, *cut_out.camera())] {
        std::env::remove_var("RAYGRAPH_DEFERRED_ALPHA");
        let at_once = render(&gpu, scene, &camera);
        // Some AO value below one: the cards occlude, so the alpha tests decided something.
        let ao_texels = (SIZE.0 * SIZE.1 * 4) as usize;
        assert!(at_once[..ao_texels].iter().step_by(4).any(|&v| f32::from_bits(v) < 1.0), "{what}: nothing occluded");
        for deferred in ["1", "3", "8"] {
            std::env::set_var("RAYGRAPH_DEFERRED_ALPHA", deferred);
            let later = render(&gpu, scene, &camera);
            std::env::remove_var("RAYGRAPH_DEFERRED_ALPHA");
            let differing = at_once.iter().zip(&later).filter(|(a, b)| a != b).count();
            assert_eq!((later.len(), differing), (at_once.len(), 0), "{what}: {deferred} alpha tests deferred change {differing} values");
        }
    }
}
