//! `raygraph bench modes`: the three modes on the same scenes, their images and the differences
//! between every pair (`raygraph::bench::modes`).

use super::output::{run_info, write_results};
use crate::cli::args::{ensure_size_in_range, GpuArgs};
use anyhow::{Context, Result};
use raygraph::bench::modes;
use raygraph::scene::Scene;
use std::path::{Path, PathBuf};

/// The arguments of `raygraph bench modes`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help("The traversal back-end of the hybrid and full-RT modes (default: the start-up choice)")))]
pub(crate) struct ModesArgs {
    /// Comma-separated scenes (built-in names or glTF files), each optionally `NAME=SCENE`
    /// to name its images.
    #[arg(long, default_value = "default")]
    scenes: String,
    #[arg(long, default_value_t = 320)]
    width: u32,
    #[arg(long, default_value_t = 240)]
    height: u32,
    #[command(flatten)]
    gpu: GpuArgs,
    #[arg(long, default_value = "bench-results/modes")]
    out: PathBuf,
}

/// `raygraph bench modes`.
pub(crate) fn run(args: ModesArgs) -> Result<()> {
    let size = (args.width, args.height);
    ensure_size_in_range(args.width, args.height)?;
    let gpu = args.gpu.open_gpu()?;
    let backend = args.gpu.backend.unwrap_or(gpu.selection().backend);
    let loaded = load_scenes(&args.scenes)?;
    let out = &args.out;
    let dir = raygraph::bench::results_dir(out).with_context(|| format!("could not create {}", out.display()))?;
    let rows = modes::run(&gpu, Path::new("."), &loaded, backend, size, &dir)?;
    let info = run_info(&gpu, size);
    write_results(out, &[("modes.md", modes::markdown(&info, backend, &rows))])
}

/// The scenes of `--scenes`, each with the name of its images: `NAME=SCENE` names them, a bare
/// scene is named by its file stem.
pub(crate) fn load_scenes(list: &str) -> Result<Vec<(String, Scene)>> {
    let mut loaded = Vec::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (name, spec) = match item.split_once('=') {
            Some((name, spec)) => (name.to_string(), spec),
            None => (Path::new(item).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| item.to_string()), item),
        };
        let (scene, _) = raygraph::scene::open(spec, &Default::default()).with_context(|| format!("cannot open scene {spec}"))?;
        loaded.push((name, scene));
    }
    Ok(loaded)
}
