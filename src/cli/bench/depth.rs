//! `raygraph bench depth`: reflection bounces against rays per second
//! (`raygraph::bench::depth`).

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::{FrameSize, GpuArgs};
use anyhow::Result;
use raygraph::bench::depth::{self as depth_bench, DepthConfig};
use std::path::PathBuf;

/// The arguments of `raygraph bench depth`.
#[derive(clap::Args)]
pub(crate) struct DepthArgs {
    #[arg(long)]
    quick: bool,
    #[arg(long, default_value = "atrium")]
    scene: String,
    #[command(flatten)]
    size: FrameSize,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/depth")]
    out: PathBuf,
}

/// `raygraph bench depth`.
pub(crate) fn run(args: DepthArgs) -> Result<()> {
    let gpu = args.gpu.open_gpu()?;
    let (size, max_bounces, frames) = if args.quick { ((48, 27), 3, 1) } else { ((2560, 1440), 8, 5) };
    let cfg = DepthConfig { scene: args.scene, size: args.size.or(size), max_bounces, frames, backends: args.gpu.backends(&gpu), root: PathBuf::from(".") };
    let info = run_info(&gpu, cfg.size);
    let out = &args.out;
    let files = |rows: &[_]| [("depth.csv", depth_bench::csv(&info, rows)), ("depth.md", depth_bench::markdown(&info, rows))];
    let rows = with_progress(|progress| depth_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows))))?;
    write_results(out, &files(&rows))?;
    write_plots(depth_bench::plots(out, &rows))
}
