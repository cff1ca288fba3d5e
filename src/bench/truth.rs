//! `raygraph bench truth`: every mode against the path-traced reference (`graph/reference.ron`)
//! on the same scene, camera and back-end: relMSE on the linear HDR image the tone map reads
//! (premultiplied radiance; [`REL_MSE_EPSILON`]), the ꟻLIP mean of the tone-mapped images, and
//! the mode's GPU and wall ms per frame; plus the path tracer itself at the GPU time of each
//! mode (equal time: as many paths a pixel as fit, one frame, other random numbers than the
//! reference's). The modes render `mode_frames` frames of a still camera first, so the filters
//! of `hybrid_denoised` have converged as they do at rest. Images and ꟻLIP error maps are
//! written beside the results (ACCURACY.md, "Modes against ground truth").

use crate::backend::Backend;
use crate::bench::RunInfo;
use crate::error::RuntimeError;
use crate::graph::compile::{compile_with, CompileOptions};
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::{Executor, Gpu};
use crate::scene::{Camera, Scene};
use std::path::{Path, PathBuf};

/// The modes compared: name and graph file (relative to the project root); each graph's
/// `hdr_output` is the linear image compared.
pub const TRUTH_MODES: [(&str, &str); 4] =
    [("raster", "graph/raster.ron"), ("hybrid", "graph/hybrid.ron"), ("hybrid_denoised", "graph/hybrid_denoised.ron"), ("full_rt", "graph/full_rt.ron")];
/// The reference graph.
pub const REFERENCE_GRAPH: &str = "graph/reference.ron";
/// relMSE = mean over pixels and channels of (test - reference)^2 / (reference^2 + epsilon).
pub const REL_MSE_EPSILON: f64 = 0.01;
/// The share of the largest pixels the trimmed relMSE leaves out.
pub const TRIMMED_SHARE: f64 = 0.001;

/// What `bench truth` runs.
#[derive(Debug, Clone)]
pub struct TruthConfig {
    /// The project root (graph, layers and shaders).
    pub root: PathBuf,
    /// Width and height of every image.
    pub size: (u32, u32),
    /// The back-end of every ray-traced graph.
    pub backend: Backend,
    /// Paths a pixel and frame of the reference.
    pub reference_samples: u32,
    /// Timed frames of the reference (its warm-up frames add to its paths too).
    pub reference_frames: u32,
    /// Timed frames of each mode, after its warm-up, all with the camera still.
    pub mode_frames: u32,
    /// Untimed frames before the timed ones (at least; see `runtime::warm_up`).
    pub warmup: u32,
    /// Besides each scene's own camera, views that see the scene cover these fractions of the
    /// frame (its camera moved along its view axis, as `bench rays --coverage`).
    pub coverages: Vec<f64>,
}

/// One mode (or the path tracer at a mode's time) against the reference.
#[derive(Debug, Clone)]
pub struct TruthRow {
    /// The scene's name.
    pub scene: String,
    /// The mode, or `path tracer at <mode>'s time`.
    pub mode: String,
    /// GPU ms per frame (median of the timed frames).
    pub gpu_ms: f64,
    /// Wall ms per frame (median).
    pub wall_ms: f64,
    /// relMSE of the HDR image against the reference's.
    pub rel_mse: f64,
    /// The same without the 0.1% largest pixels ([`trimmed_rel_mse`]).
    pub trimmed_rel_mse: f64,
    /// ꟻLIP mean of the tone-mapped image against the reference's.
    pub flip: f32,
    /// Paths a pixel, for the path tracer's rows.
    pub paths: Option<u32>,
}

/// A rendered image: its HDR texels, its tone-mapped output and the medians of its frames.
pub(crate) struct Rendered {
    pub(crate) hdr: Vec<[f32; 4]>,
    pub(crate) ldr: image::RgbaImage,
    pub(crate) gpu_ms: f64,
    pub(crate) wall_ms: f64,
}

/// `graph` (relative to the project root) compiled with `params` for `cfg`'s size and back-end,
/// ready for `scene`.
pub(crate) fn executor(gpu: &Gpu, cfg: &TruthConfig, scene: &Scene, graph: &str, params: &[(&str, &str, ParamValue)]) -> Result<Executor, RuntimeError> {
    let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(cfg.backend) };
    for (node, param, value) in params {
        options.params.insert((node.to_string(), param.to_string()), value.clone());
    }
    let path = cfg.root.join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), cfg.size, &options)?;
    Executor::new(gpu, plan, scene)
}

/// Renders `graph` with `params` on `scene` (warm-up, then `frames` timed frames) and reads its
/// HDR output (`hdr_output`) and its output.
pub(crate) fn render(
    gpu: &Gpu,
    cfg: &TruthConfig,
    view: &(Scene, Camera),
    graph: &str,
    params: &[(&str, &str, ParamValue)],
    frames: u32,
) -> Result<Rendered, RuntimeError> {
    let (scene, camera) = view;
    let mut exec = executor(gpu, cfg, scene, graph, params)?;
    let resource = exec
        .plan()
        .hdr_output()
        .ok_or_else(|| RuntimeError::Gpu(format!("{}: the graph names no `hdr_output` (its linear HDR image)", cfg.root.join(graph).display())))?;
    let timed = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, frames, |_| *camera)?;
    let mut gpu_ms: Vec<f64> = timed.iter().map(super::frame_gpu_ms).collect();
    let mut wall_ms: Vec<f64> = timed.iter().map(|f| f.frame_ms).collect();
    let (_, _, hdr) = exec.read_texture_f32(gpu, resource)?;
    let ldr = exec.read_output(gpu)?;
    Ok(Rendered { hdr, ldr, gpu_ms: crate::runtime::profiler::median(&mut gpu_ms), wall_ms: crate::runtime::profiler::median(&mut wall_ms) })
}

/// Each pixel's relMSE of `test` against `reference` (the mean over its RGB channels).
fn pixel_rel_mse(reference: &[[f32; 4]], test: &[[f32; 4]]) -> Vec<f64> {
    let channel = |r: f64, t: f64| (t - r) * (t - r) / (r * r + REL_MSE_EPSILON);
    reference.iter().zip(test).map(|(r, t)| (0..3).map(|c| channel(r[c] as f64, t[c] as f64)).sum::<f64>() / 3.0).collect()
}

/// relMSE of `test` against `reference` over the RGB channels of every pixel.
pub fn rel_mse(reference: &[[f32; 4]], test: &[[f32; 4]]) -> f64 {
    let pixels = pixel_rel_mse(reference, test);
    pixels.iter().sum::<f64>() / pixels.len().max(1) as f64
}

/// relMSE without the [`TRIMMED_SHARE`] largest pixels: single paths of huge weight
/// (fireflies: the sun reflected by a metal onto a diffuse surface, which next-event estimation
/// from the metal finds only rarely) dominate the plain mean of a few paths a pixel.
pub fn trimmed_rel_mse(reference: &[[f32; 4]], test: &[[f32; 4]]) -> f64 {
    let mut pixels = pixel_rel_mse(reference, test);
    pixels.sort_by(|a, b| a.total_cmp(b));
    let kept = pixels.len() - (pixels.len() as f64 * TRIMMED_SHARE).ceil() as usize;
    pixels[..kept].iter().sum::<f64>() / kept.max(1) as f64
}

/// The ꟻLIP error map of `test` against `reference` (nv-flip's default viewing conditions).
fn flip_map(reference: &image::RgbaImage, test: &image::RgbaImage) -> nv_flip::FlipImageFloat {
    let rgb = |img: &image::RgbaImage| img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect::<Vec<u8>>();
    let (w, h) = reference.dimensions();
    nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference)),
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(test)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
}

/// Compares `test` with the reference, writes its image and its ꟻLIP map (magma) into `out`
/// as `{stem}.png` and `{stem}_flip.png`, and gives its row.
pub(crate) fn judge(reference: &Rendered, test: &Rendered, scene: &str, mode: String, paths: Option<u32>, out: &Path) -> Result<TruthRow, RuntimeError> {
    let stem = format!("{scene}_{}", mode.replace(' ', "_").replace('\'', ""));
    let map = flip_map(&reference.ldr, &test.ldr);
    let flip = nv_flip::FlipPool::from_image(&map).mean();
    let colored = map.apply_color_lut(&nv_flip::magma_lut());
    let (w, h) = reference.ldr.dimensions();
    let rgba: Vec<u8> = colored.to_vec().chunks(3).flat_map(|c| [c[0], c[1], c[2], 255]).collect();
    let image = image::RgbaImage::from_raw(w, h, rgba).ok_or_else(|| RuntimeError::Gpu("ꟻLIP map of the wrong size".into()))?;
    crate::runtime::exec::write_png(&out.join(format!("{stem}_flip.png")), &image)?;
    crate::runtime::exec::write_png(&out.join(format!("{stem}.png")), &test.ldr)?;
    let (rel_mse, trimmed_rel_mse) = (rel_mse(&reference.hdr, &test.hdr), trimmed_rel_mse(&reference.hdr, &test.hdr));
    Ok(TruthRow { scene: scene.into(), mode, gpu_ms: test.gpu_ms, wall_ms: test.wall_ms, rel_mse, trimmed_rel_mse, flip, paths })
}

/// Every scene from its own camera and at every coverage of `cfg`, named for results.
fn views(gpu: &Gpu, cfg: &TruthConfig, scenes: &[(String, Scene)]) -> Result<Vec<(String, (Scene, Camera))>, RuntimeError> {
    let mut out = Vec::new();
    for (name, scene) in scenes {
        out.push((name.clone(), (scene.clone(), *scene.camera())));
        for &coverage in &cfg.coverages {
            let camera = super::rays::coverage_camera(gpu, &cfg.root, scene, coverage)?;
            out.push((format!("{name}_at_{:.0}%", coverage * 100.0), (scene.clone(), camera)));
        }
    }
    Ok(out)
}

/// Every mode of every view against its reference; `on_row` sees the rows after each one.
pub fn run(gpu: &Gpu, cfg: &TruthConfig, scenes: &[(String, Scene)], out: &Path, mut on_row: impl FnMut(&[TruthRow])) -> Result<Vec<TruthRow>, RuntimeError> {
    let mut rows = Vec::new();
    let samples = cfg.reference_samples.max(1);
    for (name, scene) in &views(gpu, cfg, scenes)? {
        let reference = render(gpu, cfg, scene, REFERENCE_GRAPH, &[("path", "samples", ParamValue::Int(samples as i64))], cfg.reference_frames)?;
        crate::runtime::exec::write_png(&out.join(format!("{name}_reference.png")), &reference.ldr)?;
        let ms_per_path = reference.gpu_ms / samples as f64;
        for (mode, graph) in TRUTH_MODES {
            let test = render(gpu, cfg, scene, graph, &[], cfg.mode_frames)?;
            rows.push(judge(&reference, &test, name, mode.into(), None, out)?);
            on_row(&rows);
            // The path tracer in the mode's GPU time: one frame of that many paths a pixel.
            let paths = ((test.gpu_ms / ms_per_path).floor() as u32).max(1);
            let params =
                [("path", "samples", ParamValue::Int(paths as i64)), ("path", "seed", ParamValue::Int(1)), ("accumulate", "max_frames", ParamValue::Int(1))];
            let equal = render(gpu, cfg, scene, REFERENCE_GRAPH, &params, cfg.mode_frames)?;
            rows.push(judge(&reference, &equal, name, format!("path tracer at {mode}'s time"), Some(paths), out)?);
            on_row(&rows);
        }
    }
    Ok(rows)
}

/// The results as CSV.
pub fn csv(info: &RunInfo, rows: &[TruthRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,mode,gpu_ms,wall_ms,rel_mse,trimmed_rel_mse,flip,paths_per_pixel\n");
    for r in rows {
        let paths = r.paths.map_or(String::new(), |p| p.to_string());
        s.push_str(&format!("{},{},{:.3},{:.3},{:.6},{:.6},{:.5},{paths}\n", r.scene, r.mode, r.gpu_ms, r.wall_ms, r.rel_mse, r.trimmed_rel_mse, r.flip));
    }
    s
}

/// The results as markdown: the run's header and one table.
pub fn markdown(info: &RunInfo, cfg: &TruthConfig, rows: &[TruthRow]) -> String {
    let mut s = format!(
        "# bench truth\n\n{}- back-end: {}\n- reference: `{REFERENCE_GRAPH}`, {} paths a pixel and frame, {} frames at least\n\nrelMSE (linear HDR, epsilon {REL_MSE_EPSILON}; trimmed: without the 0.1% largest pixels) and ꟻLIP mean (tone-mapped) against the reference; GPU and wall ms per frame (medians).\n\n| scene | mode | GPU ms | wall ms | relMSE | trimmed relMSE | ꟻLIP | paths/px |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n",
        info.markdown(),
        cfg.backend,
        cfg.reference_samples,
        cfg.reference_frames
    );
    for r in rows {
        let paths = r.paths.map_or(String::new(), |p| p.to_string());
        s.push_str(&format!(
            "| {} | {} | {:.3} | {:.3} | {:.5} | {:.5} | {:.4} | {paths} |\n",
            r.scene, r.mode, r.gpu_ms, r.wall_ms, r.rel_mse, r.trimmed_rel_mse, r.flip
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rel_mse_is_zero_for_the_reference_itself_and_follows_its_formula() {
        let reference = vec![[1.0, 0.0, 0.5, 1.0]; 4];
        assert_eq!(rel_mse(&reference, &reference), 0.0);
        let doubled: Vec<[f32; 4]> = reference.iter().map(|t| [2.0 * t[0], 2.0 * t[1], 2.0 * t[2], t[3]]).collect();
        // Per pixel: 1 / (1 + 0.01), 0, 0.25 / (0.25 + 0.01); alpha is not compared.
        let expected = (1.0 / 1.01 + 0.25 / 0.26) / 3.0;
        assert!((rel_mse(&reference, &doubled) - expected).abs() < 1e-12);
    }

    #[test]
    fn the_trimmed_rel_mse_leaves_out_the_largest_pixel_in_a_thousand() {
        let reference = vec![[1.0, 1.0, 1.0, 1.0]; 1000];
        let mut test = reference.clone();
        test[17] = [101.0, 101.0, 101.0, 1.0];
        test[18] = [2.0, 2.0, 2.0, 1.0];
        // One firefly of relMSE 10000 / 1.01 against one pixel of 1 / 1.01.
        assert!((rel_mse(&reference, &test) - 10001.0 / 1.01 / 1000.0).abs() < 1e-9);
        assert!((trimmed_rel_mse(&reference, &test) - 1.0 / 1.01 / 999.0).abs() < 1e-12);
    }
}
