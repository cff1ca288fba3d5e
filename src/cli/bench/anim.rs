//! `raygraph bench anim`: animated scenes under each policy of the acceleration-structure
//! cache (`raygraph::bench::anim`).

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::{FrameSize, GpuArgs};
use anyhow::Result;
use raygraph::accel::deform::RefitPolicy;
use raygraph::backend::Backend;
use raygraph::bench::anim::{self as anim_bench, AnimConfig};
use std::path::PathBuf;

/// The arguments of `raygraph bench anim`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help("Traversal back-end [default: compute]")))]
pub(crate) struct AnimArgs {
    /// Seconds on a CPU instead of the full run (CI): 96x54, 24 frames, the small files.
    #[arg(long)]
    quick: bool,
    /// Animated scenes, comma-separated: built-in names or glTF files.
    #[arg(long, value_delimiter = ',', default_value = "organic-skinned,atrium-moving")]
    scenes: Vec<String>,
    /// Frames per scene and policy.
    #[arg(long, default_value_t = 240)]
    frames: u32,
    /// Frames per second of the clip's clock.
    #[arg(long, default_value_t = 60.0)]
    fps: f32,
    /// The SAH growths at which the auto policy is run (comma-separated), besides the cost
    /// policy, always refit and always rebuild [default: the cache's threshold].
    #[arg(long, value_delimiter = ',')]
    max_growth: Vec<f64>,
    #[command(flatten)]
    size: FrameSize,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/anim")]
    out: PathBuf,
}

/// `raygraph bench anim`, on the compute back-end unless another is asked for.
pub(crate) fn run(args: AnimArgs) -> Result<()> {
    let backend = args.gpu.backend.unwrap_or(Backend::Compute);
    let gpu = args.gpu.deadline.open_gpu(Some(backend))?;
    println!("adapter: {}", gpu.describe());
    let quick = args.quick;
    let scenes = if quick { ["skinned_cylinder", "spinner"].map(|n| format!("assets/gltf/animated/{n}.gltf")).to_vec() } else { args.scenes };
    let cfg = AnimConfig {
        scenes,
        size: args.size.or(if quick { (96, 54) } else { (1920, 1080) }),
        frames: if quick { 24 } else { args.frames.max(1) },
        fps: args.fps,
        backend,
        policies: policies(&args.max_growth),
        root: PathBuf::from("."),
    };
    anyhow::ensure!(cfg.fps.is_finite() && cfg.fps > 0.0, "--fps {}: give a positive number", cfg.fps);
    anyhow::ensure!(args.max_growth.iter().all(|g| g.is_finite() && *g >= 1.0), "--max-growth: give growths of at least 1");
    let info = run_info(&gpu, cfg.size);
    let out = &args.out;
    let files = |rows: &[_]| [("anim.csv", anim_bench::csv(&info, rows)), ("anim.md", anim_bench::markdown(&info, rows))];
    let rows = with_progress(|progress| anim_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows))))?;
    write_results(out, &files(&rows))?;
    write_plots(anim_bench::plots(out, &rows))
}

/// The policies a run compares: the auto policy at each of `max_growth` (the default one when
/// none is given), then the cost policy, always refit and always rebuild.
fn policies(max_growth: &[f64]) -> Vec<RefitPolicy> {
    let auto = if max_growth.is_empty() { vec![RefitPolicy::default()] } else { max_growth.iter().map(|&g| RefitPolicy::Auto { max_growth: g }).collect() };
    auto.into_iter().chain([RefitPolicy::Cost, RefitPolicy::AlwaysRefit, RefitPolicy::AlwaysRebuild]).collect()
}
