//! `raygraph bench modes`: the three modes (Rasterization, Hybrid, Full RT) on the same scene,
//! camera and back-end, with their technique-specific effects on and off, as images side by side
//! and as the ꟻLIP mean and RMSE between every pair. "Effects off" is the raster graph with its
//! shadow maps switched off (`forward.shadows`) and the other two with their `shadow`, `ao`
//! and `reflection` nodes switched off: the three then shade the same inputs with one function
//! and differ only in how they find them (ACCURACY.md, "Real assets").

use crate::backend::Backend;
use crate::bench::RunInfo;
use crate::error::RuntimeError;
use crate::graph::compile::{compile_with, CompileOptions};
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::{Executor, Gpu};
use crate::scene::Scene;
use std::path::Path;

/// The modes' graph files, relative to the project root, and their names in results.
pub const MODES: [(&str, &str); 3] = [("raster", "graph/raster.ron"), ("hybrid", "graph/hybrid.ron"), ("full_rt", "graph/full_rt.ron")];

/// One frame of `graph` on `scene` at `size` through `backend`, with the graph's
/// technique-specific effects switched off where `effects` is false.
pub(crate) fn render_mode(
    gpu: &Gpu,
    root: &Path,
    graph: &str,
    backend: Backend,
    scene: &Scene,
    size: (u32, u32),
    effects: bool,
) -> Result<image::RgbaImage, RuntimeError> {
    let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    if !effects {
        if graph.ends_with("raster.ron") {
            options.params.insert(("forward".into(), "shadows".into()), ParamValue::Bool(false));
        } else {
            for node in ["shadow", "ao", "reflection"] {
                options.enabled.insert(node.into(), false);
            }
        }
    }
    let path = root.join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), size, &options)?;
    let mut exec = Executor::new(gpu, plan, scene)?;
    exec.render(gpu, scene.camera(), scene)?;
    exec.read_output(gpu)
}

/// The ꟻLIP mean of `test` against `reference` (nv-flip's default viewing conditions).
pub fn flip_mean(reference: &image::RgbaImage, test: &image::RgbaImage) -> f32 {
    let rgb = |img: &image::RgbaImage| img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect::<Vec<u8>>();
    let (w, h) = reference.dimensions();
    let map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference)),
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(test)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&map).mean()
}

/// The RMSE over the RGB channels of two images, in 8-bit values over 255.
pub fn rmse(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    let sum: f64 = a.pixels().zip(b.pixels()).flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f64 - q[c] as f64) / 255.0)).map(|d| d * d).sum();
    (sum / (3.0 * (a.width() * a.height()) as f64)).sqrt()
}

/// One scene with the effects on or off: the pairs' (ꟻLIP mean, RMSE).
#[derive(Debug, Clone)]
pub struct ModesRow {
    /// The scene's name.
    pub scene: String,
    /// Effects on.
    pub effects: bool,
    /// raster against hybrid, hybrid against full RT, raster against full RT.
    pub pairs: [(f32, f64); 3],
}

/// Renders every mode of every scene with the effects on and off, writes the images into
/// `out` as `{scene}_{mode}.png` and `{scene}_{mode}_off.png`, and compares them.
pub fn run(gpu: &Gpu, root: &Path, scenes: &[(String, Scene)], backend: Backend, size: (u32, u32), out: &Path) -> Result<Vec<ModesRow>, RuntimeError> {
    let mut rows = Vec::new();
    for (name, scene) in scenes {
        for effects in [true, false] {
            let mut images = Vec::new();
            for (mode, graph) in MODES {
                let img = render_mode(gpu, root, graph, backend, scene, size, effects)?;
                let suffix = if effects { "" } else { "_off" };
                crate::runtime::exec::write_png(&out.join(format!("{name}_{mode}{suffix}.png")), &img)?;
                images.push(img);
            }
            let pair = |a: usize, b: usize| (flip_mean(&images[a], &images[b]), rmse(&images[a], &images[b]));
            rows.push(ModesRow { scene: name.clone(), effects, pairs: [pair(0, 1), pair(1, 2), pair(0, 2)] });
        }
    }
    Ok(rows)
}

/// The results as markdown: the run's header, the table of ꟻLIP mean / RMSE per pair.
pub fn markdown(info: &RunInfo, backend: Backend, rows: &[ModesRow]) -> String {
    let mut s = format!(
        "# bench modes\n\n{}- back-end: {backend}\n\nꟻLIP mean / RMSE (8-bit values over 255) between the modes' images; \"off\": shadow maps, ray-traced shadows, AO and reflections switched off.\n\n| scene | effects | raster / hybrid | hybrid / full RT | raster / full RT |\n| --- | --- | --- | --- | --- |\n",
        info.markdown()
    );
    for r in rows {
        let cells: Vec<String> = r.pairs.iter().map(|(f, e)| format!("{f:.4} / {e:.4}")).collect();
        s.push_str(&format!("| {} | {} | {} |\n", r.scene, if r.effects { "on" } else { "off" }, cells.join(" | ")));
    }
    s
}
