//! What the benches show and write: the progress bar, the run's description, the results files
//! (rewritten as rows finish) and the plots.

use crate::cli::LOG_TARGET;
use anyhow::{Context, Result};
use raygraph::bench::RunInfo;
use raygraph::runtime::Gpu;
use std::path::{Path, PathBuf};

/// Runs a bench behind a progress bar; the bench reports (done, total, label).
pub(crate) fn with_progress<T>(run: impl FnOnce(&mut dyn FnMut(usize, usize, &str)) -> T) -> T {
    let bar = indicatif::ProgressBar::new(1);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} [{elapsed}]").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut update = |done: usize, total: usize, label: &str| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(label.to_string());
    };
    let out = run(&mut update);
    bar.finish_and_clear();
    out
}

/// The run's description in a bench's results: this command line, `gpu`'s adapter and `size`.
pub(crate) fn run_info(gpu: &Gpu, size: (u32, u32)) -> RunInfo {
    RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), gpu, size)
}

/// Reports the plots a bench wrote.
pub(crate) fn write_plots(result: std::result::Result<Vec<PathBuf>, String>) -> Result<()> {
    for p in result.map_err(anyhow::Error::msg)? {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Rewrites a bench's files in `dir` with the rows finished so far, atomically: a run that is
/// interrupted (Ctrl-C, a lost device) leaves those rows and never a half-written file. A
/// failure is a warning here; the final write reports it as an error.
pub(crate) fn write_partial(dir: &Path, files: &[(&str, String)]) {
    let written = raygraph::bench::results_dir(dir)
        .and_then(|dir| files.iter().try_for_each(|(name, text)| raygraph::util::write_atomic(&dir.join(name), text.as_bytes())));
    if let Err(e) = written {
        log::warn!(target: LOG_TARGET, "could not update the results in {}: {e}", dir.display());
    }
}

/// Writes a bench's files into `dir` atomically, prints the markdown (the `.md` file).
pub(crate) fn write_results(dir: &Path, files: &[(&str, String)]) -> Result<()> {
    let dir = raygraph::bench::results_dir(dir).with_context(|| format!("could not create {}", dir.display()))?;
    for (name, text) in files {
        raygraph::util::write_atomic(&dir.join(name), text.as_bytes()).with_context(|| format!("could not write {}", dir.join(name).display()))?;
    }
    for (_, text) in files.iter().filter(|(name, _)| name.ends_with(".md")) {
        print!("{text}");
    }
    println!("wrote {}", files.iter().map(|(n, _)| dir.join(n).display().to_string()).collect::<Vec<_>>().join(", "));
    Ok(())
}
