//! `raygraph view`: the live viewer of `raygraph::viewer`.

use super::args::{ensure_size_in_range, EnvArgs, GltfSceneArg, GpuArgs};
use anyhow::Result;
use raygraph::graph::Mode;
use raygraph::viewer::ViewerOptions;
use std::path::PathBuf;

/// The arguments of `raygraph view`.
#[derive(clap::Args)]
pub(crate) struct ViewArgs {
    /// A built-in scene or a glTF file.
    #[arg(default_value = "default")]
    scene: String,
    /// A graph file (default: the --mode's).
    #[arg(long)]
    graph: Option<PathBuf>,
    #[arg(long, default_value = "hybrid")]
    mode: Mode,
    #[command(flatten)]
    gpu: GpuArgs,
    /// Render size; the window opens at this size.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// A named camera preset of the scene.
    #[arg(long)]
    camera: Option<String>,
    /// Seed of the generated atrium.
    #[arg(long, default_value_t = raygraph::scene::procedural::ATRIUM_DEFAULT_SEED)]
    seed: u64,
    #[command(flatten)]
    gltf: GltfSceneArg,
    #[command(flatten)]
    env: EnvArgs,
    /// Stop after this many frames.
    #[arg(long)]
    frames: Option<u64>,
    /// Write the window (frame and overlay) to this PNG after the last frame (needs --frames).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// A RON file of timed actions (see `raygraph::viewer::script`).
    #[arg(long)]
    script: Option<PathBuf>,
    /// Print every frame's number.
    #[arg(long)]
    verbose: bool,
    /// The clip that plays (glTF animations), by name or index, or `all` (every clip at
    /// once) [default: the first].
    #[arg(long, value_name = "NAME|INDEX|all")]
    animation: Option<String>,
    /// Seconds into the clip at the start.
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0)]
    time: f32,
}

/// `raygraph view`: the arguments checked and handed to the viewer.
pub(crate) fn run(args: ViewArgs) -> Result<()> {
    let time = args.time;
    anyhow::ensure!(time.is_finite(), "--time {time}: give a finite number of seconds");
    ensure_size_in_range(args.width, args.height)?;
    let opts = ViewerOptions {
        scene: args.scene,
        graph: args.graph,
        mode: args.mode,
        backend: args.gpu.backend,
        gpu_timeout: args.gpu.deadline.duration()?,
        size: (args.width, args.height),
        camera: args.camera,
        seed: args.seed,
        gltf_scene: args.gltf.gltf_scene,
        frames: args.frames,
        screenshot: args.screenshot,
        script: args.script,
        verbose: args.verbose,
        animation: args.animation,
        time,
        environment: args.env.load()?,
    };
    raygraph::viewer::run(opts).map_err(anyhow::Error::msg)
}
