//! `raygraph bench track`: the paper's Figures 10 and 11. A recorded camera track
//! (`assets/tracks/*.ron`) played frame by frame through the raster, hybrid and full-RT graphs
//! on every back-end; per frame: GPU milliseconds, FPS, rays and GigaRays/s.

use super::RunInfo;
use crate::backend::Backend;
use crate::graph::compile::compile_with;
use crate::graph::Project;
use crate::runtime::{Executor, Gpu};
use crate::scene::track::Track;
use crate::scene::LoadOptions;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Settings of `raygraph bench track` (Figures 10 and 11).
#[derive(Debug, Clone)]
pub struct TrackConfig {
    /// Built-in scene name or glTF path.
    pub scene: String,
    /// The camera track played.
    pub track: PathBuf,
    /// Frame size.
    pub size: (u32, u32),
    /// Play every `stride`-th frame of the track.
    pub stride: u32,
    /// The back-ends measured (trace modes).
    pub backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

/// One frame of one mode.
#[derive(Debug, Clone)]
pub struct TrackRow {
    /// The mode's name.
    pub(crate) mode: &'static str,
    /// The back-end (`None` for raster).
    pub(crate) backend: Option<Backend>,
    /// Frame index in the track.
    pub(crate) frame: u32,
    /// GPU milliseconds.
    pub(crate) gpu_ms: f64,
    /// Frames per second.
    pub(crate) fps: f64,
    /// Rays traced.
    pub(crate) rays: u64,
    /// GigaRays per second.
    pub(crate) grays_per_s: f64,
}

/// The modes played: name and graph file.
pub(crate) const MODES: [(&str, &str); 3] = [("raster", "graph/raster.ron"), ("hybrid", "graph/hybrid.ron"), ("full-rt", "graph/full_rt.ron")];

/// `on_rows` sees the rows finished so far after each mode (to keep the results folder current).
pub fn run(
    gpu: &Gpu,
    cfg: &TrackConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[TrackRow]),
) -> Result<Vec<TrackRow>, crate::error::RuntimeError> {
    let track = Track::load(&cfg.track)?;
    let (scene, _) = crate::scene::open(&cfg.scene, &LoadOptions::default())?;
    let bounds = scene.bounds();
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let frames: Vec<u32> = (0..track.frame_count()).step_by(cfg.stride.max(1) as usize).collect();
    // Raster runs once (it traces nothing); the ray-traced modes once per back-end.
    let mut runs: Vec<(&'static str, &str, Option<Backend>)> = vec![("raster", MODES[0].1, None)];
    for &b in &cfg.backends {
        runs.push(("hybrid", MODES[1].1, Some(b)));
        runs.push(("full-rt", MODES[2].1, Some(b)));
    }
    let mut rows = Vec::new();
    for (k, (mode, graph, backend)) in runs.iter().enumerate() {
        let options = gpu.compile_options_for(backend.unwrap_or(gpu.selection().backend));
        let plan = compile_with(&cfg.root.join(graph), &project, cfg.size, &options)?;
        let mut exec = Executor::new(gpu, plan, &scene)?;
        let timings = super::timed_frames(gpu, &mut exec, &scene, 1, frames.len() as u32, |i| {
            track.camera_at_frame(frames[i as usize], scene.camera()).fit_clip_planes(bounds)
        })?;
        for (f, t) in frames.iter().zip(&timings) {
            let ms = super::frame_gpu_ms(t);
            let rays = t.rays.map(|r| r.traced()).unwrap_or(0);
            rows.push(TrackRow { mode, backend: *backend, frame: *f, gpu_ms: ms, fps: 1000.0 / ms, rays, grays_per_s: super::grays_per_s(rays as f64, ms) });
        }
        on_rows(&rows);
        progress(k + 1, runs.len(), mode);
    }
    Ok(rows)
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[TrackRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("mode,backend,frame,gpu_ms,fps,rays,grays_per_s\n");
    for r in rows {
        let _ =
            writeln!(s, "{},{},{},{:.4},{:.3},{},{:.5}", r.mode, r.backend.map(|b| b.name()).unwrap_or(""), r.frame, r.gpu_ms, r.fps, r.rays, r.grays_per_s);
    }
    s
}

/// Per mode and back-end: median, min and max FPS over the track, median GigaRays/s.
pub fn markdown(info: &RunInfo, track: &Path, rows: &[TrackRow]) -> String {
    let mut s = format!("# bench track\n\n{}- track: `{}`\n\n", info.markdown(), track.display());
    s.push_str("| mode | back-end | frames | median FPS | min FPS | max FPS | median GigaRays/s |\n| --- | --- | ---: | ---: | ---: | ---: | ---: |\n");
    let mut keys: Vec<(&str, Option<Backend>)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.mode, r.backend)) {
            keys.push((r.mode, r.backend));
        }
    }
    for (mode, backend) in keys {
        let sel: Vec<&TrackRow> = rows.iter().filter(|r| r.mode == mode && r.backend == backend).collect();
        let mut fps: Vec<f64> = sel.iter().map(|r| r.fps).collect();
        let mut gr: Vec<f64> = sel.iter().map(|r| r.grays_per_s).collect();
        let (min, max) = fps.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        let _ = writeln!(
            s,
            "| {mode} | {} | {} | {:.1} | {min:.1} | {max:.1} | {:.3} |",
            backend.map(|b| b.name()).unwrap_or("—"),
            sel.len(),
            crate::runtime::profiler::median(&mut fps),
            crate::runtime::profiler::median(&mut gr)
        );
    }
    s
}

/// `track_fps.png` and `track_grays.png`: per frame, per mode and back-end.
pub fn plots(dir: &Path, rows: &[TrackRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut keys: Vec<(&str, Option<Backend>)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.mode, r.backend)) {
            keys.push((r.mode, r.backend));
        }
    }
    let series = |f: &dyn Fn(&TrackRow) -> f64, traced_only: bool| -> Vec<Series> {
        keys.iter()
            .filter(|(_, b)| !traced_only || b.is_some())
            .map(|(m, b)| Series {
                name: b.map(|b| format!("{m}, {b}")).unwrap_or_else(|| m.to_string()),
                points: rows.iter().filter(|r| r.mode == *m && r.backend == *b).map(|r| (r.frame as f64, f(r))).collect(),
            })
            .collect()
    };
    let fps = dir.join("track_fps.png");
    LinePlot { title: "Frame rate along the track (Figure 10)", x_label: "frame", y_label: "FPS", log_x: false, log_y: false, x_labels: None }
        .write(&fps, &series(&|r| r.fps, false))?;
    let gr = dir.join("track_grays.png");
    LinePlot { title: "GigaRays/s along the track (Figure 11)", x_label: "frame", y_label: "GigaRays/s", log_x: false, log_y: false, x_labels: None }
        .write(&gr, &series(&|r| r.grays_per_s, true))?;
    Ok(vec![fps, gr])
}
