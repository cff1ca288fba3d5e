//! `raygraph bench build`: the paper's Figure 9, BLAS and TLAS build times
//! (`raygraph::bench::build`), with the CPU builders, the refits and the GPU builder.

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::GpuArgs;
use anyhow::Result;
use raygraph::backend::Backend;
use raygraph::bench::build::{self as build_bench, BuildBenchConfig};
use raygraph::bench::RunInfo;
use raygraph::runtime::Gpu;
use std::path::{Path, PathBuf};

/// The arguments of `raygraph bench build`.
#[derive(clap::Args)]
pub(crate) struct BuildArgs {
    #[arg(long)]
    quick: bool,
    #[arg(long, value_delimiter = ',')]
    scenes: Option<Vec<String>>,
    /// Largest duplication factor N.
    #[arg(long)]
    max_factor: Option<u32>,
    /// Skip duplications with more triangles than this.
    #[arg(long)]
    max_triangles: Option<usize>,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/build")]
    out: PathBuf,
}

/// `raygraph bench build`: the build times per builder, then the CPU builds and, on the
/// compute back-end, the refits and the GPU builds.
pub(crate) fn run(args: BuildArgs) -> Result<()> {
    let gpu = args.gpu.open_gpu()?;
    let backends = args.gpu.backends(&gpu);
    let root = PathBuf::from(".");
    let mut cfg = if args.quick { BuildBenchConfig::quick(&root, backends) } else { BuildBenchConfig::paper(&root, backends) };
    if let Some(s) = args.scenes {
        cfg.scenes = s;
    }
    cfg.max_factor = args.max_factor.unwrap_or(cfg.max_factor);
    cfg.max_triangles = args.max_triangles.unwrap_or(cfg.max_triangles);
    let info = run_info(&gpu, cfg.rays);
    let out = &args.out;
    let files = |rows: &[_], skipped: &[String]| [("build.csv", build_bench::csv(&info, rows)), ("build.md", build_bench::markdown(&info, rows, skipped))];
    let (rows, skipped) = with_progress(|progress| build_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows, &[]))))?;
    write_results(out, &files(&rows, &skipped))?;
    write_plots(build_bench::plots(out, &rows))?;
    let cpu_builds = build_bench::run_cpu_builds(&cfg, if args.quick { 2 } else { 9 })?;
    write_results(
        out,
        &[("cpu_build.csv", build_bench::cpu_build_csv(&info, &cpu_builds)), ("cpu_build.md", build_bench::cpu_build_markdown(&info, &cpu_builds))],
    )?;
    if cfg.backends.contains(&Backend::Compute) {
        run_compute_builds(&gpu, &cfg, &info, args.quick, out)?;
    }
    Ok(())
}

/// The refits and the GPU builds of the compute back-end.
fn run_compute_builds(gpu: &Gpu, cfg: &BuildBenchConfig, info: &RunInfo, quick: bool, out: &Path) -> Result<()> {
    let refit = build_bench::run_refit(gpu, cfg, if quick { 3 } else { 20 })?;
    write_results(out, &[("refit.csv", build_bench::refit_csv(info, &refit)), ("refit.md", build_bench::refit_markdown(info, &refit))])?;
    let gpu_builds = build_bench::run_gpu_builds(gpu, cfg, if quick { 2 } else { 10 })?;
    write_results(
        out,
        &[("gpu_build.csv", build_bench::gpu_build_csv(info, &gpu_builds)), ("gpu_build.md", build_bench::gpu_build_markdown(info, &gpu_builds))],
    )
}
