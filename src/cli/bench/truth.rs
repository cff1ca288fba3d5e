//! `raygraph bench truth`: every mode against the path-traced reference
//! (`raygraph::bench::truth`).

use super::output::{run_info, write_partial, write_results};
use crate::cli::args::{ensure_size_in_range, GpuArgs};
use anyhow::{Context, Result};
use raygraph::bench::truth::{self, TruthConfig};
use std::path::{Path, PathBuf};

/// The arguments of `raygraph bench truth`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help("The traversal back-end of every ray-traced graph (default: the start-up choice)")))]
pub(crate) struct TruthArgs {
    /// Comma-separated scenes (built-in names or glTF files), each optionally `NAME=SCENE`
    /// to name its images.
    #[arg(long, default_value = "atrium")]
    scenes: String,
    #[arg(long, default_value_t = 1280)]
    width: u32,
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Paths a pixel and frame of the reference.
    #[arg(long, default_value_t = 16)]
    reference_samples: u32,
    /// Frames of the reference (at least: its warm-up frames add to them).
    #[arg(long, default_value_t = 256)]
    reference_frames: u32,
    /// Timed frames of each mode, after its warm-up, with the camera still.
    #[arg(long, default_value_t = 64)]
    mode_frames: u32,
    /// Untimed frames before the timed ones (at least: the warm-up runs until frame times settle).
    #[arg(long, default_value_t = 16)]
    warmup: u32,
    /// Comma-separated fractions of the frame: besides each scene's own camera, a view that
    /// sees it cover that much (e.g. 0.02,0.05,0.1).
    #[arg(long, value_delimiter = ',')]
    coverage: Vec<f64>,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/truth")]
    out: PathBuf,
}

/// `raygraph bench truth`.
pub(crate) fn run(args: TruthArgs) -> Result<()> {
    ensure_size_in_range(args.width, args.height)?;
    let gpu = args.gpu.open_gpu()?;
    let cfg = TruthConfig {
        root: PathBuf::from("."),
        size: (args.width, args.height),
        backend: args.gpu.backend.unwrap_or(gpu.selection().backend),
        reference_samples: args.reference_samples,
        reference_frames: args.reference_frames,
        mode_frames: args.mode_frames,
        warmup: args.warmup,
        coverages: args.coverage,
    };
    let scenes = super::modes::load_scenes(&args.scenes)?;
    let out = &args.out;
    let dir = raygraph::bench::results_dir(out).with_context(|| format!("could not create {}", out.display()))?;
    let info = run_info(&gpu, cfg.size);
    let rows = truth::run(&gpu, &cfg, &scenes, &dir, |rows| {
        write_partial(Path::new(out), &[("truth.md", truth::markdown(&info, &cfg, rows)), ("truth.csv", truth::csv(&info, rows))])
    })?;
    write_results(out, &[("truth.md", truth::markdown(&info, &cfg, &rows)), ("truth.csv", truth::csv(&info, &rows))])
}
