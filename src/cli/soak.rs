//! `raygraph soak`: the long run of `raygraph::soak`, its lines on stdout and, with `--log`, in
//! a log file.

use super::args::Deadline;
use anyhow::{Context, Result};
use raygraph::backend::Backend;
use raygraph::runtime::Gpu;
use raygraph::soak::{self, Check, SoakConfig, SoakReport};
use std::path::{Path, PathBuf};

/// The arguments of `raygraph soak`.
#[derive(clap::Args)]
pub(crate) struct SoakArgs {
    #[arg(long, default_value = "default")]
    scene: String,
    #[arg(long, default_value_t = 10_000)]
    frames: u32,
    /// Frames per cycle of changes; the checks run at the end of each cycle.
    #[arg(long, default_value_t = 500)]
    cycle: u32,
    #[arg(long, default_value_t = 64)]
    width: u32,
    #[arg(long, default_value_t = 64)]
    height: u32,
    /// Allowed growth of the resident set over the first check, in MiB.
    #[arg(long, default_value_t = 32.0)]
    rss_tolerance: f64,
    #[arg(long)]
    backend: Option<Backend>,
    /// Also write the adapter, the per-check lines and the verdict to this file (rewritten
    /// after every check, so an interrupted run keeps what it checked).
    #[arg(long)]
    log: Option<PathBuf>,
    #[command(flatten)]
    deadline: Deadline,
}

/// `raygraph soak`: the run, its lines on stdout and, with `--log`, in the log file.
pub(crate) fn run(args: SoakArgs) -> Result<()> {
    let gpu = args.deadline.open_gpu(args.backend)?;
    let mut cfg = SoakConfig::new(Path::new("."), args.frames, args.cycle, (args.width, args.height));
    cfg.scene = args.scene;
    cfg.rss_tolerance_mib = args.rss_tolerance;
    cfg.backend = args.backend;
    run_soak(&gpu, &cfg, args.log.as_deref())
}

/// The soak run on `gpu`: every line printed and, with `log`, rewritten into that file after
/// every check and at the end.
fn run_soak(gpu: &Gpu, cfg: &SoakConfig, log: Option<&Path>) -> Result<()> {
    let mut lines = vec![
        format!("adapter: {}", gpu.describe()),
        format!("back-end: {}", cfg.backend.unwrap_or(gpu.selection().backend)),
        cfg.describe(),
        Check::log_header(),
    ];
    let write_log = |lines: &[String]| -> Result<()> {
        match log {
            Some(path) => raygraph::util::write_atomic(path, (lines.join("\n") + "\n").as_bytes()).with_context(|| format!("writing {}", path.display())),
            None => Ok(()),
        }
    };
    lines.iter().for_each(|l| println!("{l}"));
    let mut log_error = None;
    let report = soak::run(gpu, cfg, |c, _| {
        let line = c.log_line();
        println!("{line}");
        lines.push(line);
        if let Err(e) = write_log(&lines) {
            log_error.get_or_insert(e);
        }
    })?;
    if let Some(e) = log_error {
        return Err(e);
    }
    let summary = summary(&report);
    summary.iter().for_each(|l| println!("{l}"));
    lines.extend(summary);
    write_log(&lines)?;
    if !report.failures.is_empty() {
        anyhow::bail!("soak failed: {} failed checks (listed above)", report.failures.len());
    }
    Ok(())
}

/// The closing lines of a soak run: what changed, the first shader error, and the verdict.
fn summary(report: &SoakReport) -> Vec<String> {
    let mut summary = vec![format!(
        "{} frames: {} with instances moving, {} meshes added and {} removed, {} graph swaps, {} shader errors caught and {} fixed",
        report.frames, report.moved_frames, report.meshes_added, report.meshes_removed, report.graph_swaps, report.shader_errors, report.shader_fixes
    )];
    if let Some(e) = &report.shader_error_example {
        summary.push(format!("first shader error, as reported:\n{e}"));
    }
    if report.failures.is_empty() {
        summary.push(format!("ok: memory and live GPU objects flat, image finite, over {} checks", report.checks.len()));
    } else {
        summary.push(format!("soak failed:\n  {}", report.failures.join("\n  ")));
    }
    summary
}
