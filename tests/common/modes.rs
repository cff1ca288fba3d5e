//! The three modes' graphs rendered with every technique-specific effect switched off
//! (tests/real_assets.rs, tests/mode_agreement.rs), and the path-traced reference accumulated.

use raygraph::backend::Backend;
use raygraph::graph::compile::compile_with;
use raygraph::graph::desc::ParamValue;
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::Scene;

/// One frame of the repository's `graph` (`graph/raster.ron`: the shadow map's switch
/// `forward.shadows` off; the others: the `shadow`, `ao` and `reflection` nodes off), without
/// texture reuse so that every channel can be read back.
pub fn render_without_effects(gpu: &Gpu, graph: &str, backend: Backend, scene: &Scene, size: (u32, u32)) -> Executor {
    let mut options = raygraph::graph::compile::CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    if graph.ends_with("raster.ron") {
        options.params.insert(("forward".into(), "shadows".into()), ParamValue::Bool(false));
    } else {
        for node in ["shadow", "ao", "reflection"] {
            options.enabled.insert(node.into(), false);
        }
    }
    let path = super::repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), size, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    exec
}

/// One frame of the repository's `graph` for `scene` from its own camera on `backend`, without
/// texture reuse so that every channel can be read back (`common::channel`).
pub fn render_graph(gpu: &Gpu, graph: &str, backend: Backend, scene: &Scene, size: (u32, u32)) -> Executor {
    let options = raygraph::graph::compile::CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    let path = super::repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), size, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    exec
}

/// The path tracer's (`graph/reference.ron`) accumulated radiance of `scene` on `backend` after
/// `frames` frames of `samples` paths a pixel.
pub fn path_traced(gpu: &Gpu, backend: Backend, scene: &Scene, size: (u32, u32), samples: u32, frames: u32) -> Vec<[f32; 4]> {
    let p = super::TempProject::with_repo_files();
    let graph = std::fs::read_to_string(super::repo().join("graph/reference.ron")).unwrap();
    let graph = graph.replace(r#""path": Layer(layer: "rt_path","#, &format!(r#""path": Layer(layer: "rt_path", params: {{"samples": {samples}}},"#));
    let path = p.write("graph/reference.ron", &graph);
    let plan = raygraph::graph::compile::compile_with(&path, &p.project(), size, &gpu.compile_options_for(backend)).unwrap_or_else(|e| panic!("{e}"));
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    for _ in 0..frames {
        exec.render(gpu, scene.camera(), scene).unwrap();
    }
    super::channel(gpu, &exec, "accumulate.color")
}
