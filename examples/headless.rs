//! Renders the default scene headless with a built-in graph and saves the frame as a PNG:
//! `cargo run --example headless -- out.png [raster|hybrid|full-rt]`. Runs from any directory:
//! the graph, layers and shaders are built into the library.

use anyhow::{bail, Context};
use raygraph::graph::{self, Mode, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::LoadOptions;
use std::path::{Path, PathBuf};

pub const SIZE: (u32, u32) = (320, 180);

fn main() -> anyhow::Result<()> {
    run(std::env::args().skip(1))
}

/// Renders and saves the frame; `args` are the command line's, without the program name.
pub fn run(mut args: impl Iterator<Item = String>) -> anyhow::Result<()> {
    let Some(out) = args.next().map(PathBuf::from) else { bail!("usage: headless OUT.png [raster|hybrid|full-rt]") };
    let mode = match args.next().as_deref() {
        None | Some("raster") => Mode::Raster,
        Some("hybrid") => Mode::Hybrid,
        Some("full-rt") => Mode::FullRt,
        Some(other) => bail!("unknown mode `{other}`: use raster, hybrid or full-rt"),
    };
    let image = render(mode)?;
    image.save(&out).with_context(|| format!("cannot write {}", out.display()))?;
    println!("wrote {} ({}x{}, {} graph)", out.display(), image.width(), image.height(), mode.label());
    Ok(())
}

/// One frame of the default scene through `mode`'s built-in graph, read back from the GPU.
fn render(mode: Mode) -> anyhow::Result<image::RgbaImage> {
    let gpu = Gpu::new()?;
    let graph_file = Path::new(mode.graph());
    let plan = graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), SIZE, &gpu.compile_options())?;
    let options = LoadOptions { textures: plan.scene_usage().textures, ..LoadOptions::default() };
    let (scene, _report) = raygraph::scene::open("default", &options)?;
    let mut exec = Executor::new(&gpu, plan, &scene)?;
    exec.render(&gpu, scene.camera(), &scene)?;
    Ok(exec.read_output(&gpu)?)
}
