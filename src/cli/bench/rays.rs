//! `raygraph bench rays`: the paper's Table 3 (`raygraph::bench::rays`).

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::{GpuArgs, LayerChoice, TimingArgs};
use anyhow::Result;
use raygraph::bench::rays as rays_bench;
use std::path::PathBuf;

/// The arguments of `raygraph bench rays`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help("Only this back-end (default: every back-end the adapter has)")))]
pub(crate) struct RaysArgs {
    /// Seconds on a CPU instead of the paper's size (CI).
    #[arg(long)]
    quick: bool,
    /// Comma-separated scenes (built-in names or glTF files).
    #[arg(long, value_delimiter = ',')]
    scenes: Option<Vec<String>>,
    #[command(flatten)]
    timing: TimingArgs,
    /// AO rays per pixel of the scene workload.
    #[arg(long)]
    ao_rays: Option<i64>,
    /// AO ray length of the scene workload, as a fraction of the scene's bounding radius
    /// [default: 0.05]
    #[arg(long)]
    ao_length: Option<f64>,
    /// Primary rays per pixel of the Miss and Stress tests.
    #[arg(long)]
    primary_rays: Option<i64>,
    /// Comma-separated fractions of the frame: each scene also measured with its camera moved
    /// along its view axis until it covers that fraction (rows "SCENE at 2%").
    #[arg(long, value_delimiter = ',')]
    coverage: Vec<f64>,
    #[command(flatten)]
    gpu: GpuArgs,
    #[command(flatten)]
    layer_choice: LayerChoice,
    /// Results folder.
    #[arg(long, default_value = "bench-results/rays")]
    out: PathBuf,
}

/// `raygraph bench rays`.
pub(crate) fn run(args: RaysArgs) -> Result<()> {
    let gpu = args.gpu.open_gpu()?;
    let mut cfg = args.timing.config(args.quick, args.gpu.backends(&gpu));
    if let Some(s) = args.scenes {
        cfg.scenes = s;
    }
    cfg.ao_rays = args.ao_rays.unwrap_or(cfg.ao_rays);
    cfg.ao_length = args.ao_length.unwrap_or(cfg.ao_length);
    cfg.primary_rays = args.primary_rays.unwrap_or(cfg.primary_rays);
    if let Some(bad) = args.coverage.iter().find(|c| !(**c > 0.0 && **c <= 1.0)) {
        anyhow::bail!("--coverage {bad}: give fractions of the frame in (0, 1]");
    }
    cfg.coverages = args.coverage;
    cfg.layers = args.layer_choice.substitutions();
    let info = run_info(&gpu, cfg.size);
    let out = &args.out;
    // The markdown first: a run interrupted between the two writes leaves the CSV (what
    // scripts read) at most one row behind it, never ahead.
    let files = |rows: &[_]| {
        [
            ("rays.md", rays_bench::markdown(&info, &cfg, rows)),
            ("rays_passes.csv", rays_bench::passes_csv(&info, rows)),
            ("rays.csv", rays_bench::csv(&info, &cfg, rows)),
        ]
    };
    let rows = with_progress(|progress| rays_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows))))?;
    write_results(out, &files(&rows))?;
    write_plots(rays_bench::plots(out, &rows))
}
