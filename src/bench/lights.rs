//! `raygraph bench lights`: the direct light of a scene of many lights by three estimators at
//! their own GPU time, against the path-traced reference (`graph/reference.ron`, its
//! next-event estimation of one light picked from `reference_candidates`): every light with
//! its own shadow ray (`graph/hybrid.ron`), one light picked by resampled importance sampling
//! from M candidates a pixel and frame with no reuse (the same graph, `light_candidates` = M,
//! for each M of the list: equal time is read off the rows), and ReSTIR DI
//! (`graph/hybrid_restir.ron`). Each row: GPU and wall ms per frame, relMSE and ꟻLIP against
//! the reference after `frames` frames of a still camera (what a user sees at rest), relMSE
//! against every light's image (the estimator's own error: the modes share everything else),
//! and flicker along a camera track (ACCURACY.md, "Many lights at equal time").

use super::truth::{executor, judge, render, Rendered, TruthConfig, REFERENCE_GRAPH};
use crate::bench::RunInfo;
use crate::error::RuntimeError;
use crate::graph::desc::ParamValue;
use crate::runtime::Gpu;
use crate::scene::{Camera, Scene};
use std::path::Path;

/// What `bench lights` runs.
#[derive(Debug, Clone)]
pub struct LightsConfig {
    /// Size, back-end, the reference's paths and frames, the estimators' frames and warm-up.
    pub truth: TruthConfig,
    /// Candidates of the reference's light picking (0: every light at every vertex).
    pub reference_candidates: u32,
    /// The M of the resampling rows.
    pub candidates: Vec<u32>,
    /// Frames of the camera track for flicker.
    pub track_frames: u32,
    /// How far the camera moves towards its target each frame of the track, as a fraction of
    /// the distance between them.
    pub track_step: f32,
}

/// One estimator on one scene.
#[derive(Debug, Clone)]
pub struct LightsRow {
    /// The scene's name.
    pub scene: String,
    /// `every light`, `resampling from m` or `ReSTIR DI`.
    pub estimator: String,
    /// GPU ms per frame (median of the timed frames).
    pub gpu_ms: f64,
    /// Wall ms per frame (median).
    pub wall_ms: f64,
    /// relMSE of the HDR image against the reference.
    pub rel_mse: f64,
    /// The same without the 0.1% largest pixels.
    pub trimmed_rel_mse: f64,
    /// ꟻLIP mean against the reference.
    pub flip: f32,
    /// relMSE of the HDR image against every light's.
    pub rel_mse_every_light: f64,
    /// [`flicker`] along the camera track.
    pub flicker: f64,
}

/// The estimators: name, graph and parameters.
fn estimators(candidates: &[u32]) -> Vec<(String, &'static str, Vec<(&'static str, &'static str, ParamValue)>)> {
    let mut out = vec![("every light".to_string(), "graph/hybrid.ron", Vec::new())];
    for &m in candidates {
        let params = vec![
            ("shadow", "light_candidates", ParamValue::Int(m as i64)),
            ("shadow", "per_frame", ParamValue::Bool(true)),
            ("reflection", "light_candidates", ParamValue::Int(8)),
            ("reflection", "per_frame", ParamValue::Bool(true)),
        ];
        out.push((format!("resampling from {m}"), "graph/hybrid.ron", params));
    }
    out.push(("ReSTIR DI".to_string(), "graph/hybrid_restir.ron", Vec::new()));
    out
}

/// The camera of frame `i` of the track: `camera` moved towards its target by `step` of their
/// distance a frame.
fn track_camera(camera: &Camera, step: f32, i: u32) -> Camera {
    let mut c = *camera;
    let offset = (camera.target - camera.position) * step * i as f32;
    c.position += offset;
    c.target += offset;
    c
}

/// Flicker: the mean over the track's consecutive frames of the mean absolute change of each
/// pixel's tone-mapped luminance, over the mean luminance. Every light's own figure is what the
/// camera's motion alone changes; an estimator's excess over it is its flicker.
fn flicker(gpu: &Gpu, cfg: &LightsConfig, view: &(Scene, Camera), graph: &str, params: &[(&str, &str, ParamValue)]) -> Result<f64, RuntimeError> {
    let (scene, camera) = view;
    let mut exec = executor(gpu, &cfg.truth, scene, graph, params)?;
    crate::runtime::warm_up::WarmUp::for_gpu(gpu, cfg.truth.warmup).run(gpu, &mut exec, scene, camera)?;
    let luminance =
        |img: &image::RgbaImage| -> Vec<f64> { img.pixels().map(|p| crate::util::luminance([p[0] as f32, p[1] as f32, p[2] as f32]) as f64 / 255.0).collect() };
    let mut previous: Option<Vec<f64>> = None;
    let mut changes = Vec::new();
    for i in 0..cfg.track_frames.max(2) {
        exec.render(gpu, &track_camera(camera, cfg.track_step, i), scene)?;
        let now = luminance(&exec.read_output(gpu)?);
        if let Some(before) = &previous {
            let mean = now.iter().sum::<f64>() / now.len() as f64;
            let change = now.iter().zip(before).map(|(a, b)| (a - b).abs()).sum::<f64>() / now.len() as f64;
            changes.push(change / mean.max(1e-9));
        }
        previous = Some(now);
    }
    Ok(changes.iter().sum::<f64>() / changes.len() as f64)
}

/// Every estimator on every scene (its own camera); `on_row` sees the rows after each one.
pub fn run(
    gpu: &Gpu,
    cfg: &LightsConfig,
    scenes: &[(String, Scene)],
    out: &Path,
    mut on_row: impl FnMut(&[LightsRow]),
) -> Result<Vec<LightsRow>, RuntimeError> {
    let mut rows = Vec::new();
    let t = &cfg.truth;
    for (name, scene) in scenes {
        let view = (scene.clone(), *scene.camera());
        let reference_params = [
            ("path", "samples", ParamValue::Int(t.reference_samples.max(1) as i64)),
            ("path", "light_candidates", ParamValue::Int(cfg.reference_candidates as i64)),
        ];
        let reference = render(gpu, t, &view, REFERENCE_GRAPH, &reference_params, t.reference_frames)?;
        crate::runtime::exec::write_png(&out.join(format!("{name}_reference.png")), &reference.ldr)?;
        let mut every: Option<Rendered> = None;
        for (estimator, graph, params) in estimators(&cfg.candidates) {
            let image = render(gpu, t, &view, graph, &params, t.mode_frames)?;
            let judged = judge(&reference, &image, name, estimator.clone(), None, out)?;
            let rel_mse_every_light = every.as_ref().map_or(0.0, |e| super::truth::rel_mse(&e.hdr, &image.hdr));
            let flicker = flicker(gpu, cfg, &view, graph, &params)?;
            rows.push(LightsRow {
                scene: name.clone(),
                estimator,
                gpu_ms: judged.gpu_ms,
                wall_ms: judged.wall_ms,
                rel_mse: judged.rel_mse,
                trimmed_rel_mse: judged.trimmed_rel_mse,
                flip: judged.flip,
                rel_mse_every_light,
                flicker,
            });
            every.get_or_insert(image);
            on_row(&rows);
        }
    }
    Ok(rows)
}

/// The results as CSV.
pub fn csv(info: &RunInfo, rows: &[LightsRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,estimator,gpu_ms,wall_ms,rel_mse,trimmed_rel_mse,flip,rel_mse_every_light,flicker\n");
    for r in rows {
        s.push_str(&format!(
            "{},{},{:.3},{:.3},{:.6},{:.6},{:.5},{:.6},{:.5}\n",
            r.scene, r.estimator, r.gpu_ms, r.wall_ms, r.rel_mse, r.trimmed_rel_mse, r.flip, r.rel_mse_every_light, r.flicker
        ));
    }
    s
}

/// The results as markdown: the run's header, one table, and per scene the resampling row of
/// the largest M that takes no more GPU time than ReSTIR DI (equal time).
pub fn markdown(info: &RunInfo, cfg: &LightsConfig, rows: &[LightsRow]) -> String {
    let t = &cfg.truth;
    let mut s = format!(
        "# bench lights\n\n{}- back-end: {}\n- reference: `{REFERENCE_GRAPH}`, {} paths a pixel and frame, {} frames at least, next-event estimation of one light picked from {} candidates (0: every light)\n- estimators: {} frames of a still camera after the warm-up; flicker over {} frames of a camera moving {} of its distance to its target a frame\n\nrelMSE (linear HDR; trimmed: without the 0.1% largest pixels) and ꟻLIP mean (tone-mapped) against the reference; relMSE against every light's image; GPU and wall ms per frame (medians).\n\n| scene | estimator | GPU ms | wall ms | relMSE | trimmed relMSE | ꟻLIP | relMSE against every light | flicker |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
        info.markdown(),
        t.backend,
        t.reference_samples,
        t.reference_frames,
        cfg.reference_candidates,
        t.mode_frames,
        cfg.track_frames,
        cfg.track_step
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {:.3} | {:.3} | {:.5} | {:.5} | {:.4} | {:.5} | {:.5} |\n",
            r.scene, r.estimator, r.gpu_ms, r.wall_ms, r.rel_mse, r.trimmed_rel_mse, r.flip, r.rel_mse_every_light, r.flicker
        ));
    }
    for restir in rows.iter().filter(|r| r.estimator == "ReSTIR DI") {
        let equal = rows.iter().filter(|r| r.scene == restir.scene && r.estimator.starts_with("resampling") && r.gpu_ms <= restir.gpu_ms).last();
        s.push_str(&match equal {
            Some(e) => format!(
                "\n{}: at ReSTIR DI's {:.3} ms, {} ({:.3} ms): relMSE {:.5} against {:.5}, ꟻLIP {:.4} against {:.4}, flicker {:.5} against {:.5}.\n",
                restir.scene, restir.gpu_ms, e.estimator, e.gpu_ms, e.rel_mse, restir.rel_mse, e.flip, restir.flip, e.flicker, restir.flicker
            ),
            None => format!("\n{}: no resampling row took at most ReSTIR DI's {:.3} ms.\n", restir.scene, restir.gpu_ms),
        });
    }
    s
}
