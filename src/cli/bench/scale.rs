//! `raygraph bench scale`: speed, build time and GPU memory against unique triangles
//! (`raygraph::bench::scale`).

use super::output::{run_info, with_progress, write_partial, write_results};
use crate::cli::args::{GpuArgs, TimingArgs};
use anyhow::Result;
use raygraph::bench::scale::{self as scale_bench, ScaleConfig};
use std::path::PathBuf;

/// The arguments of `raygraph bench scale`.
#[derive(clap::Args)]
pub(crate) struct ScaleArgs {
    /// Seconds on a CPU: two small steps at a small size (CI).
    #[arg(long)]
    quick: bool,
    /// Comma-separated steps `scene:N` (the scene copied NxNxN)
    /// [default: organic:2,organic:3,atrium:1,atrium:2,atrium:3,atrium:4,atrium:5].
    #[arg(long, value_delimiter = ',')]
    steps: Option<Vec<String>>,
    #[command(flatten)]
    timing: TimingArgs,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/scale")]
    out: PathBuf,
}

/// `raygraph bench scale`.
pub(crate) fn run(args: ScaleArgs) -> Result<()> {
    let gpu = args.gpu.open_gpu()?;
    let mut cfg = ScaleConfig::full(args.timing.config(args.quick, args.gpu.backends(&gpu)));
    if args.quick {
        cfg.steps = vec![("box".into(), 1), ("organic".into(), 2)];
    }
    if let Some(list) = &args.steps {
        cfg.steps = ScaleConfig::parse_steps(list).map_err(anyhow::Error::msg)?;
    }
    let info = run_info(&gpu, cfg.rays.size);
    let out = &args.out;
    let files = |rows: &[_], skipped: &[String]| [("scale.md", scale_bench::markdown(&info, rows, skipped)), ("scale.csv", scale_bench::csv(&info, rows))];
    let (rows, skipped) = with_progress(|progress| scale_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows, &[]))))?;
    write_results(out, &files(&rows, &skipped))
}
