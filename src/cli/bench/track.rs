//! `raygraph bench track`: the paper's Figures 10 and 11, a camera track through the three
//! modes (`raygraph::bench::track`).

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::{FrameSize, GpuArgs};
use anyhow::Result;
use raygraph::bench::track::{self as track_bench, TrackConfig};
use std::path::PathBuf;

/// The arguments of `raygraph bench track`.
#[derive(clap::Args)]
pub(crate) struct TrackArgs {
    #[arg(long)]
    quick: bool,
    #[arg(long, default_value = "atrium")]
    scene: String,
    #[arg(long, default_value = "assets/tracks/atrium.ron")]
    track: PathBuf,
    #[command(flatten)]
    size: FrameSize,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/track")]
    out: PathBuf,
}

/// `raygraph bench track`.
pub(crate) fn run(args: TrackArgs) -> Result<()> {
    let gpu = args.gpu.open_gpu()?;
    let cfg = TrackConfig {
        scene: args.scene,
        track: args.track.clone(),
        size: args.size.or(if args.quick { (48, 27) } else { (2560, 1440) }),
        stride: if args.quick { 60 } else { 1 },
        backends: args.gpu.backends(&gpu),
        root: PathBuf::from("."),
    };
    let info = run_info(&gpu, cfg.size);
    let out = &args.out;
    let files = |rows: &[_]| [("track.csv", track_bench::csv(&info, rows)), ("track.md", track_bench::markdown(&info, &args.track, rows))];
    let rows = with_progress(|progress| track_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows))))?;
    write_results(out, &files(&rows))?;
    write_plots(track_bench::plots(out, &rows))
}
