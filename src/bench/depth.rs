//! `raygraph bench depth`: reflection bounce count 1..8 against rays/s (the recursion
//! experiment the paper promised): the hybrid graph with every surface reflective
//! (`max_roughness` 1), shadows and AO on, on each back-end; the reflection pass's rays per
//! pixel and GigaRays/s from its own counters and GPU time.

use super::RunInfo;
use crate::backend::Backend;
use crate::graph::compile::compile_with;
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::profiler::median;
use crate::runtime::{Executor, Gpu};
use crate::scene::LoadOptions;
use std::fmt::Write;
use std::path::PathBuf;

/// Settings of `raygraph bench depth` (reflection bounces against rays/s).
#[derive(Debug, Clone)]
pub struct DepthConfig {
    /// Built-in scene name or glTF path.
    pub scene: String,
    /// Frame size.
    pub size: (u32, u32),
    /// The most reflection bounces measured.
    pub max_bounces: i64,
    /// Timed frames per measurement.
    pub frames: u32,
    /// The back-ends measured.
    pub backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

/// One bounce count on one back-end.
#[derive(Debug, Clone)]
pub struct DepthRow {
    /// The back-end.
    pub(crate) backend: Backend,
    /// Reflection bounces.
    pub(crate) bounces: i64,
    /// GPU milliseconds of the reflection pass.
    pub(crate) reflection_ms: f64,
    /// Reflection rays per pixel.
    pub(crate) rays_per_pixel: f64,
    /// GigaRays per second of the reflection pass.
    pub(crate) grays_per_s: f64,
    /// GPU milliseconds of the frame.
    pub(crate) frame_ms: f64,
}

/// `on_rows` sees the rows finished so far after each one (to keep the results folder current).
pub fn run(
    gpu: &Gpu,
    cfg: &DepthConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[DepthRow]),
) -> Result<Vec<DepthRow>, crate::error::RuntimeError> {
    let (scene, _) = crate::scene::open(&cfg.scene, &LoadOptions::default())?;
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let graph = cfg.root.join("graph/hybrid.ron");
    let pixels = cfg.size.0 as f64 * cfg.size.1 as f64;
    let total = cfg.backends.len() * cfg.max_bounces as usize;
    let mut rows = Vec::new();
    for &backend in &cfg.backends {
        for bounces in 1..=cfg.max_bounces {
            let mut options = gpu.compile_options_for(backend);
            options.params.insert(("reflection".into(), "bounces".into()), ParamValue::Int(bounces));
            options.params.insert(("reflection".into(), "max_roughness".into()), ParamValue::Float(1.0));
            let plan = compile_with(&graph, &project, cfg.size, &options)?;
            let pass = plan
                .passes
                .iter()
                .position(|p| p.name == "reflection/reflection")
                .ok_or_else(|| crate::error::RuntimeError::Gpu("graph/hybrid.ron has no reflection pass".into()))?;
            let mut exec = Executor::new(gpu, plan, &scene)?;
            let frames = super::timed_frames(gpu, &mut exec, &scene, 1, cfg.frames, |_| *scene.camera())?;
            let mut ms: Vec<f64> = frames.iter().map(|f| f.gpu_ms.as_ref().map(|v| v[pass]).unwrap_or(f.frame_ms)).collect();
            let mut rays: Vec<f64> = frames.iter().map(|f| f.pass_rays[pass].map(|r| r.traced()).unwrap_or(0) as f64).collect();
            let mut frame_ms: Vec<f64> = frames.iter().map(super::frame_gpu_ms).collect();
            let (ms, rays) = (median(&mut ms), median(&mut rays));
            rows.push(DepthRow {
                backend,
                bounces,
                reflection_ms: ms,
                rays_per_pixel: rays / pixels,
                grays_per_s: super::grays_per_s(rays, ms),
                frame_ms: median(&mut frame_ms),
            });
            on_rows(&rows);
            progress(rows.len(), total, &format!("{backend}: {bounces} bounces"));
        }
    }
    Ok(rows)
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[DepthRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("backend,bounces,reflection_ms,rays_per_pixel,grays_per_s,frame_ms\n");
    for r in rows {
        let _ = writeln!(s, "{},{},{:.4},{:.3},{:.5},{:.4}", r.backend, r.bounces, r.reflection_ms, r.rays_per_pixel, r.grays_per_s, r.frame_ms);
    }
    s
}

/// The rows as a markdown table, with the run's header.
pub fn markdown(info: &RunInfo, rows: &[DepthRow]) -> String {
    let mut s = format!("# bench depth\n\n{}\n", info.markdown());
    s.push_str("| back-end | bounces | reflection ms | reflection rays/pixel | GigaRays/s | frame ms |\n| --- | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(s, "| {} | {} | {:.3} | {:.2} | {:.3} | {:.3} |", r.backend, r.bounces, r.reflection_ms, r.rays_per_pixel, r.grays_per_s, r.frame_ms);
    }
    s
}

/// `depth.png`: reflection GigaRays/s and rays per pixel against the bounce count.
pub fn plots(dir: &std::path::Path, rows: &[DepthRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut backends: Vec<Backend> = Vec::new();
    for r in rows {
        if !backends.contains(&r.backend) {
            backends.push(r.backend);
        }
    }
    let mut series = Vec::new();
    for b in &backends {
        let sel: Vec<&DepthRow> = rows.iter().filter(|r| r.backend == *b).collect();
        series.push(Series { name: format!("{b}: GigaRays/s"), points: sel.iter().map(|r| (r.bounces as f64, r.grays_per_s)).collect() });
        series.push(Series { name: format!("{b}: rays/pixel"), points: sel.iter().map(|r| (r.bounces as f64, r.rays_per_pixel)).collect() });
    }
    let path = dir.join("depth.png");
    LinePlot { title: "Reflection bounces", x_label: "bounces", y_label: "GigaRays/s and rays/pixel", log_x: false, log_y: true, x_labels: None }
        .write(&path, &series)?;
    Ok(vec![path])
}
