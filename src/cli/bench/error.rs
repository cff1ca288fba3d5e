//! `raygraph bench error`: the filtered effects against their references
//! (`raygraph::bench::filters`), then ambient occlusion against its closed form, the hybrid
//! mode's error and the shadow maps' (`raygraph::bench::error`).

use super::output::{run_info, with_progress, write_partial, write_plots, write_results};
use crate::cli::args::{backends, Deadline};
use anyhow::{Context, Result};
use raygraph::backend::Backend;
use raygraph::bench::error::{self as error_bench, ErrorConfig};
use raygraph::bench::filters::{self, FiltersConfig};
use raygraph::runtime::Gpu;
use std::path::{Path, PathBuf};

/// The arguments of `raygraph bench error`.
#[derive(clap::Args)]
pub(crate) struct ErrorArgs {
    #[arg(long)]
    quick: bool,
    #[arg(long)]
    backend: Option<Backend>,
    /// Run only the part on the filtered effects.
    #[arg(long)]
    filters_only: bool,
    #[command(flatten)]
    filter_args: FilterArgs,
    #[command(flatten)]
    deadline: Deadline,
    #[arg(long, default_value = "bench-results/error")]
    out: PathBuf,
}

/// What `bench error`'s part on the filtered effects runs, instead of its configuration's.
#[derive(clap::Args)]
struct FilterArgs {
    /// A scene of the filter part (built-in name or glTF file); repeat for more.
    #[arg(long = "filter-scene")]
    scenes: Vec<String>,
    /// The filter part's frame width.
    #[arg(long)]
    filter_width: Option<u32>,
    /// The filter part's frame height.
    #[arg(long)]
    filter_height: Option<u32>,
    /// The filter part's ray counts, comma separated.
    #[arg(long, value_delimiter = ',')]
    filter_rays: Vec<i64>,
    /// Frames accumulated into the filter part's references.
    #[arg(long)]
    reference_frames: Option<u32>,
    /// Frames of the filter part's turn.
    #[arg(long)]
    turn_frames: Option<u32>,
}

impl FilterArgs {
    /// `cfg` with what was given.
    fn apply(&self, mut cfg: FiltersConfig) -> FiltersConfig {
        if !self.scenes.is_empty() {
            cfg.scenes = self.scenes.clone();
        }
        if !self.filter_rays.is_empty() {
            cfg.rays = self.filter_rays.clone();
        }
        cfg.size = (self.filter_width.unwrap_or(cfg.size.0), self.filter_height.unwrap_or(cfg.size.1));
        cfg.reference_frames = self.reference_frames.unwrap_or(cfg.reference_frames);
        cfg.turn_frames = self.turn_frames.unwrap_or(cfg.turn_frames);
        cfg
    }
}

/// `raygraph bench error`: the filter part on the first back-end, and unless
/// `--filters-only`, the parts on ambient occlusion, the hybrid mode and the shadow maps.
pub(crate) fn run(args: ErrorArgs) -> Result<()> {
    let gpu = args.deadline.open_gpu(args.backend)?;
    println!("adapter: {}", gpu.describe());
    let backends = backends(args.backend, &gpu);
    let (quick, out) = (args.quick, &args.out);
    run_filters(&gpu, quick, &args.filter_args, *backends.first().context("no back-end")?, out)?;
    if args.filters_only {
        return Ok(());
    }
    let root = PathBuf::from(".");
    let cfg = if quick { ErrorConfig::quick(&root, backends) } else { ErrorConfig::full(&root, backends) };
    let info = run_info(&gpu, cfg.size);
    let files = |rows: &[_]| [("error.csv", error_bench::csv(&info, rows)), ("error.md", error_bench::markdown(&info, rows))];
    let rows = with_progress(|progress| error_bench::run(&gpu, &cfg, progress, |rows| write_partial(out, &files(rows))))?;
    write_results(out, &files(&rows))?;
    write_plots(error_bench::plots(out, &rows))?;
    run_hybrid(&gpu, &cfg, quick, out)?;
    run_shadow_maps(&gpu, &cfg, quick, out)
}

/// The part on the filtered effects (`raygraph::bench::filters`).
fn run_filters(gpu: &Gpu, quick: bool, args: &FilterArgs, backend: Backend, out: &Path) -> Result<()> {
    let root = PathBuf::from(".");
    let cfg = args.apply(if quick { FiltersConfig::quick(&root, backend) } else { FiltersConfig::full(&root, backend) });
    let info = run_info(gpu, cfg.size);
    let files = |rows: &[_], track: &[_]| {
        [
            ("filters.md", filters::markdown(&info, &cfg, rows, track)),
            ("filters_track.csv", filters::track_csv(&info, track)),
            ("filters.csv", filters::csv(&info, rows)),
        ]
    };
    let (rows, track) = with_progress(|progress| filters::run(gpu, &cfg, progress, |rows, track| write_partial(out, &files(rows, track))))?;
    write_results(out, &files(&rows, &track))
}

/// The hybrid mode's error on the built-in scenes.
fn run_hybrid(gpu: &Gpu, cfg: &ErrorConfig, quick: bool, out: &Path) -> Result<()> {
    let (scenes, size): (&[&str], _) = if quick { (&["default"], (96, 54)) } else { (&["default", "atrium"], (1280, 720)) };
    let hybrid = error_bench::run_hybrid(gpu, cfg, scenes, size)?;
    let info = run_info(gpu, size);
    write_results(out, &[("hybrid.csv", error_bench::hybrid_csv(&info, &hybrid)), ("hybrid.md", error_bench::hybrid_markdown(&info, &hybrid))])
}

/// The shadow maps against the ray-traced shadows.
fn run_shadow_maps(gpu: &Gpu, cfg: &ErrorConfig, quick: bool, out: &Path) -> Result<()> {
    let sweep = if quick { error_bench::ShadowMapSweep::quick() } else { error_bench::ShadowMapSweep::full() };
    // The ray-traced truth is the same on every back-end (tests/reference_channels.rs):
    // the first one traces it.
    let backend = *cfg.backends.first().context("no back-end to trace the shadow rays with")?;
    let shadow_maps = error_bench::run_shadow_maps(gpu, cfg, &sweep, backend)?;
    let info = run_info(gpu, sweep.size);
    write_results(
        out,
        &[("shadow_maps.csv", error_bench::shadow_map_csv(&info, &shadow_maps)), ("shadow_maps.md", error_bench::shadow_map_markdown(&info, &shadow_maps))],
    )?;
    write_plots(error_bench::shadow_map_plot(out, &shadow_maps))
}
