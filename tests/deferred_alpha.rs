//! The compute back-end's deferred alpha tests (`RAYGRAPH_DEFERRED_ALPHA`, the pipeline constant
//! TRACE_DEFERRED_ALPHA of `shaders/trace/compute.wgsl`) change no bit: the pine's alpha-tested
//! and BLEND foliage under AO and shadow rays (`graph/ao.ron` without its `blend` node: both are
//! transmittance rays), and
//! the default scene's MASK-free any-hit rays, rendered with 1, 3 and 8 tests deferred against
//! none. One test in this binary: the variable is read when the passes are built.

mod common;

use common::{ao_graph_without_blend, gpu};
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::Scene;

const SIZE: (u32, u32) = (48, 36);

/// The bits of the AO and shadow outputs after a frame of `graph/ao.ron` (without its `blend`
/// node) on the compute back-end.
fn render(gpu: &Gpu, scene: &Scene) -> Vec<u32> {
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    let (path, project) = ao_graph_without_blend();
    let plan = compile_with(&path, &project, SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    ["ao.ao", "ao.partial", "shadow.direct"].iter().flat_map(|name| common::channel(gpu, &exec, name)).flat_map(|t| t.map(f32::to_bits)).collect()
}

#[test]
fn deferred_alpha_tests_change_no_bit() {
    let gpu = gpu();
    let pine = common::open("assets/gltf/smallpine/scene.gltf");
    let default_scene = raygraph::scene::builtin::default_scene();
    for (what, scene) in [("pine", &pine), ("default scene", &default_scene)] {
        std::env::remove_var("RAYGRAPH_DEFERRED_ALPHA");
        let at_once = render(&gpu, scene);
        for deferred in ["1", "3", "8"] {
            std::env::set_var("RAYGRAPH_DEFERRED_ALPHA", deferred);
            let later = render(&gpu, scene);
            std::env::remove_var("RAYGRAPH_DEFERRED_ALPHA");
            let differing = at_once.iter().zip(&later).filter(|(a, b)| a != b).count();
            assert_eq!((later.len(), differing), (at_once.len(), 0), "{what}: {deferred} alpha tests deferred change {differing} values");
        }
    }
}
