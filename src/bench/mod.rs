//! The experiments: `raygraph bench rays` (the paper's Table 3), `bench build` (Figure 9),
//! `bench track` (Figures 10 and 11), `bench anim` (animated scenes: acceleration-structure updates and GigaRays/s under the cache's policies), `bench depth` (reflection bounces), `bench error` (AO
//! error against rays and time), `bench modes` (the three modes against each other) `bench roofline` (bytes per ray, CPU-counted) and `bench scale` (speed, build time and memory against unique triangles, 10^4 to 3x10^7). Each bench writes a results folder with CSV and markdown whose
//! header names the adapter, driver, back-end, resolution and git revision.

pub mod anim;
pub mod build;
pub mod conformance;
pub mod depth;
pub mod error;
pub mod filters;
pub mod lights;
pub mod modes;
pub mod plot;
pub mod rays;
pub mod repeat;
pub mod roofline;
pub mod scale;
pub mod track;
pub mod truth;

use std::path::{Path, PathBuf};

/// The header every results file starts with.
#[derive(Debug, Clone)]
pub struct RunInfo {
    /// The command line that produced the results.
    pub(crate) command: String,
    /// The adapter ([`crate::runtime::Gpu::describe`]).
    pub(crate) adapter: String,
    /// Frame width.
    pub(crate) width: u32,
    /// Frame height.
    pub(crate) height: u32,
    /// The git revision the binary was built from.
    pub(crate) revision: String,
    /// When the run started.
    pub(crate) date: String,
}

impl RunInfo {
    /// The header of a run of `command` on `gpu` at `size`.
    pub fn new(command: &str, gpu: &crate::runtime::Gpu, size: (u32, u32)) -> Self {
        let revision = env!("RAYGRAPH_REVISION").to_string();
        let date = crate::util::utc_timestamp();
        RunInfo { command: command.to_string(), adapter: gpu.describe(), width: size.0, height: size.1, revision, date }
    }

    /// Markdown lines for the top of a results file.
    pub fn markdown(&self) -> String {
        format!(
            "- command: `{}`\n- adapter: {}\n- resolution: {}x{}\n- revision: {}\n- date: {}\n",
            self.command, self.adapter, self.width, self.height, self.revision, self.date
        )
    }

    /// `#`-comment lines for the top of a CSV file.
    pub(crate) fn csv_comment(&self) -> String {
        self.markdown().lines().map(|l| format!("# {}\n", l.trim_start_matches("- "))).collect()
    }
}

/// GigaRays per second of `rays` traced in `gpu_ms` milliseconds.
pub(crate) fn grays_per_s(rays: f64, gpu_ms: f64) -> f64 {
    rays / (gpu_ms * 1e-3) / 1e9
}

/// The GPU ms of a frame spent in the passes of `nodes` (its wall time where passes are not
/// timed).
pub(crate) fn nodes_ms(exec: &crate::runtime::Executor, frame: &crate::runtime::profiler::FrameTimings, nodes: &[&str]) -> f64 {
    let passes = &exec.plan().passes;
    match &frame.gpu_ms {
        Some(ms) => passes.iter().zip(ms).filter(|(p, _)| nodes.contains(&p.node.as_str())).map(|(_, t)| t).sum(),
        None => frame.frame_ms,
    }
}

/// `dir`, created if needed.
pub fn results_dir(dir: &Path) -> std::io::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    Ok(dir.to_path_buf())
}

/// Renders untimed frames until the frame time has settled (at least `warmup`; see
/// [`crate::runtime::warm_up`]), then `frames` timed ones with the camera `camera_at(i)`.
pub(crate) fn timed_frames(
    gpu: &crate::runtime::Gpu,
    exec: &mut crate::runtime::Executor,
    scene: &crate::scene::Scene,
    warmup: u32,
    frames: u32,
    camera_at: impl Fn(u32) -> crate::scene::Camera,
) -> Result<Vec<crate::runtime::profiler::FrameTimings>, crate::error::RuntimeError> {
    crate::runtime::warm_up::WarmUp::for_gpu(gpu, warmup).run(gpu, exec, scene, &camera_at(0))?;
    (0..frames.max(1)).map(|i| exec.render(gpu, &camera_at(i), scene)).collect()
}

/// A frame's GPU milliseconds: the sum over its passes (its wall time without timestamps).
pub use crate::runtime::warm_up::gpu_ms as frame_gpu_ms;
