//! `raygraph selftest`: the correctness suites of `raygraph::selftest`, a line per suite and
//! back-end on stdout and, with `--out`, a log file.

use super::args::Deadline;
use anyhow::{Context, Result};
use raygraph::backend::Backend;
use raygraph::runtime::Gpu;
use raygraph::selftest::{self, SelftestConfig};
use std::path::{Path, PathBuf};

/// The arguments of `raygraph selftest`.
#[derive(clap::Args)]
pub(crate) struct SelftestArgs {
    /// Only this suite: hard-cases, agreement or reference-channels (repeatable; default:
    /// all).
    #[arg(long, value_parser = ["hard-cases", "agreement", "reference-channels"])]
    suite: Vec<String>,
    /// Only this back-end (repeatable; default: every back-end, those the adapter lacks
    /// reported as not applicable).
    #[arg(long)]
    backend: Vec<Backend>,
    /// Write the adapter, revision, date, every line and what each case measured to
    /// DIR/selftest.log.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Also print what each case measured.
    #[arg(long)]
    verbose: bool,
    /// The shaders folder of the hard-cases and agreement tracers (files missing there are the
    /// built-in copies; reference-channels renders the built-in graph, layers and shaders).
    #[arg(long, default_value = "shaders")]
    shaders: PathBuf,
    #[command(flatten)]
    deadline: Deadline,
}

/// `raygraph selftest`.
pub(crate) fn run(args: SelftestArgs) -> Result<()> {
    let cfg = SelftestConfig { shaders: args.shaders, backends: args.backend, suites: args.suite };
    run_selftest(&args.deadline.open_gpu(None)?, &cfg, args.out.as_deref(), args.verbose)
}

/// Every suite's line on stdout and, with `out`, in DIR/selftest.log; an error unless all passed.
fn run_selftest(gpu: &Gpu, cfg: &SelftestConfig, out: Option<&Path>, verbose: bool) -> Result<()> {
    println!("adapter: {}", gpu.describe());
    let results = selftest::run(gpu, cfg, |r| {
        println!("{}", r.line());
        if verbose {
            r.notes.iter().for_each(|n| println!("    {n}"));
        }
    });
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join("selftest.log");
        raygraph::util::write_atomic(&path, selftest::log_text(gpu, &results, true).as_bytes()).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    let verdict = selftest::verdict(&results);
    if verdict.starts_with("ok") {
        println!("{verdict}");
        Ok(())
    } else {
        anyhow::bail!("{verdict}")
    }
}
