//! `raygraph bench lights`: every light, resampling and ReSTIR DI against the path-traced
//! reference (`raygraph::bench::lights`).

use super::output::{run_info, write_partial, write_results};
use crate::cli::args::{ensure_size_in_range, EnvArgs, GpuArgs};
use anyhow::{Context, Result};
use raygraph::bench::lights::{self, LightsConfig};
use raygraph::bench::truth::TruthConfig;
use std::path::{Path, PathBuf};

/// The arguments of `raygraph bench lights`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help("The traversal back-end of every ray-traced graph (default: the start-up choice)")))]
pub(crate) struct LightsArgs {
    /// Comma-separated scenes (built-in names or glTF files), each optionally `NAME=SCENE`
    /// to name its images.
    #[arg(long, default_value = "atrium-lights")]
    scenes: String,
    #[arg(long, default_value_t = 1280)]
    width: u32,
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Paths a pixel and frame of the reference.
    #[arg(long, default_value_t = 16)]
    reference_samples: u32,
    /// Frames of the reference (at least: its warm-up frames add to them).
    #[arg(long, default_value_t = 64)]
    reference_frames: u32,
    /// Candidates of the reference's light picking at each vertex (0: every light).
    #[arg(long, default_value_t = 8)]
    reference_candidates: u32,
    /// Comma-separated M of the resampling rows (one light picked from M a pixel).
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16,32,64")]
    candidates: Vec<u32>,
    /// Timed frames of each estimator, after its warm-up, with the camera still.
    #[arg(long, default_value_t = 64)]
    frames: u32,
    /// Untimed frames before the timed ones (at least: the warm-up runs until frame times settle).
    #[arg(long, default_value_t = 16)]
    warmup: u32,
    /// Frames of the camera track for flicker.
    #[arg(long, default_value_t = 32)]
    track_frames: u32,
    /// How far the camera moves towards its target a frame of the track (a fraction of their
    /// distance).
    #[arg(long, default_value_t = 0.002)]
    track_step: f32,
    #[command(flatten)]
    env: EnvArgs,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/lights")]
    out: PathBuf,
}

/// `raygraph bench lights`.
pub(crate) fn run(args: LightsArgs) -> Result<()> {
    ensure_size_in_range(args.width, args.height)?;
    let gpu = args.gpu.open_gpu()?;
    let truth = TruthConfig {
        root: PathBuf::from("."),
        size: (args.width, args.height),
        backend: args.gpu.backend.unwrap_or(gpu.selection().backend),
        reference_samples: args.reference_samples,
        reference_frames: args.reference_frames,
        mode_frames: args.frames,
        warmup: args.warmup,
        coverages: Vec::new(),
    };
    let cfg = LightsConfig {
        truth,
        reference_candidates: args.reference_candidates,
        candidates: args.candidates,
        track_frames: args.track_frames,
        track_step: args.track_step,
    };
    let mut scenes = super::modes::load_scenes(&args.scenes)?;
    for (_, scene) in &mut scenes {
        args.env.apply(scene)?;
    }
    let out = &args.out;
    let dir = raygraph::bench::results_dir(out).with_context(|| format!("could not create {}", out.display()))?;
    let info = run_info(&gpu, cfg.truth.size);
    let rows = lights::run(&gpu, &cfg, &scenes, &dir, |rows| {
        write_partial(Path::new(out), &[("lights.md", lights::markdown(&info, &cfg, rows)), ("lights.csv", lights::csv(&info, rows))])
    })?;
    write_results(out, &[("lights.md", lights::markdown(&info, &cfg, &rows)), ("lights.csv", lights::csv(&info, &rows))])
}
