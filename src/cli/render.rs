//! `raygraph render`: a scene rendered headless through a graph, the image written (a PNG of
//! the tone-mapped frame, or an OpenEXR of the graph's linear HDR output) and the per-pass
//! timings printed.

use super::args::{DuplicateArgs, EnvArgs, GltfSceneArg, GpuArgs, LayerChoice};
use super::LOG_TARGET;
use anyhow::{Context, Result};
use raygraph::graph::compile::{self, CompileOptions};
use raygraph::graph::{desc::PassKind, Mode, Plan, Project};
use raygraph::runtime::profiler::{pass_table, FrameTimings};
use raygraph::runtime::{exec::write_exr, exec::write_png, gpu::Gpu, warm_up::WarmUp, Executor};
use raygraph::scene::{self, track::Track, Camera, LoadOptions, Scene};
use std::path::{Path, PathBuf};

/// The arguments of `raygraph render`.
#[derive(clap::Args)]
#[command(mut_arg("backend", |a| a.help(
    "Traversal back-end: ray-query, compute or rt-pipeline (default: ray-query where the adapter supports it, else compute; rt-pipeline only when asked for)"
)))]
pub(crate) struct RenderArgs {
    /// Graph description file.
    #[arg(long, default_value = "graph/raster.ron", conflicts_with = "mode")]
    graph: PathBuf,
    /// The paper's modes, a shortcut for their graphs: raster (graph/raster.ron), hybrid
    /// (graph/hybrid.ron), full-rt (graph/full_rt.ron).
    #[arg(long)]
    mode: Option<Mode>,
    /// A built-in scene (default, box, organic, atrium, organic-skinned, atrium-moving, cornell,
    /// atrium-lights) or a .gltf/.glb file.
    #[arg(long, default_value = "default")]
    scene: String,
    #[command(flatten)]
    copies: DuplicateArgs,
    #[command(flatten)]
    env: EnvArgs,
    #[command(flatten)]
    gpu: GpuArgs,
    #[command(flatten)]
    view: CameraArgs,
    /// Frame width in pixels, up to the adapter's largest 2D texture.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Frame height in pixels [default: the width over the camera's aspect ratio (a glTF
    /// camera's `aspectRatio`, or xmag/ymag), else 720]
    #[arg(long)]
    height: Option<u32>,
    /// Output image; its extension picks the format: .png, the tone-mapped (display-referred)
    /// frame, or .exr, the linear, scene-referred radiance of the graph's `hdr_output` (RGBA
    /// float32, alpha premultiplied: 0 where nothing was drawn, without the tone map's sky).
    #[arg(long, default_value = "out.png")]
    out: PathBuf,
    /// Frames to time (after untimed frames until the frame time settles); the table shows medians.
    #[arg(long, default_value_t = 10)]
    frames: u32,
    /// Also write the per-pass statistics (mean, median, min, max) as CSV, markdown and a
    /// Chrome trace (open in Perfetto) into this folder.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Also write what the driver compiled each trace kernel into (registers, instructions,
    /// spills: whatever the driver reports through VK_KHR_pipeline_executable_properties) as
    /// markdown to this file. The compute back-end's kernels, where the device takes them as
    /// SPIR-V.
    #[arg(long, value_name = "FILE")]
    kernel_stats: Option<PathBuf>,
    /// Layers directory (default: `layers/` beside the graph's directory).
    #[arg(long)]
    layers: Option<PathBuf>,
    /// Shaders directory (default: `shaders/` beside the graph's directory).
    #[arg(long)]
    shaders: Option<PathBuf>,
    /// Switch a layer node of the graph off (repeatable): its passes are culled, and the
    /// nodes that read it get what its layer's `bypass` passes through (a filter's input),
    /// else their input's fallback.
    #[arg(long, value_name = "NODE")]
    off: Vec<String>,
    #[command(flatten)]
    layer_choice: LayerChoice,
}

/// Where the camera is.
#[derive(clap::Args)]
struct CameraArgs {
    #[command(flatten)]
    gltf: GltfSceneArg,
    /// A named camera preset of the scene (see `raygraph scene info`).
    #[arg(long, conflicts_with = "track")]
    camera: Option<String>,
    /// A camera track file (RON); the camera is the track's at --track-frame.
    #[arg(long)]
    track: Option<PathBuf>,
    /// Frame index on the track.
    #[arg(long, default_value_t = 0, requires = "track")]
    track_frame: u32,
    /// Seed of the generated atrium.
    #[arg(long, default_value_t = raygraph::scene::procedural::ATRIUM_DEFAULT_SEED)]
    seed: u64,
    /// Seconds into the scene's animation (glTF clips; a clip loops over its length). With
    /// --track the default is the track's time at --track-frame [default: the rest pose].
    #[arg(long, value_name = "SECONDS")]
    time: Option<f32>,
    /// The clip that plays, by name or index, or `all` (every clip at once, as glTF viewers
    /// play them) [default: the first].
    #[arg(long, value_name = "NAME|INDEX|all")]
    animation: Option<String>,
}

impl CameraArgs {
    /// Poses `scene` as asked and returns the camera: the preset asked for, else the track's
    /// at its frame, else the scene's.
    fn place(&self, scene: &mut Scene) -> Result<Camera> {
        let track = self.track.as_deref().map(Track::load).transpose()?;
        self.pose(scene, track.as_ref())?;
        Ok(match (&self.camera, &track) {
            (Some(name), _) => scene.preset(name).map_err(anyhow::Error::msg)?,
            (None, Some(track)) => track.camera_at_frame(self.track_frame, scene.camera()).fit_clip_planes(scene.bounds()),
            (None, None) => *scene.camera(),
        })
    }

    /// Poses `scene` at the asked time of the asked clip (nothing asked: left at rest); the
    /// track's time when a track gives the camera and no time is given.
    fn pose(&self, scene: &mut Scene, track: Option<&Track>) -> Result<()> {
        use raygraph::scene::animation::ClipChoice;
        let time = self.time.or_else(|| track.map(|t| self.track_frame as f32 / t.fps)).or(self.animation.as_ref().map(|_| 0.0));
        if self.time.is_some_and(|t| !t.is_finite()) {
            anyhow::bail!("--time {}: give a finite number of seconds", self.time.unwrap_or_default());
        }
        let choice = self.animation.as_deref().map(|a| a.parse::<ClipChoice>().unwrap_or_default()).unwrap_or_default();
        let Some(rig) = scene.rig().cloned() else {
            anyhow::ensure!(self.animation.is_none(), "--animation {}: scene `{}` has no animations", self.animation.as_deref().unwrap_or(""), scene.name());
            if self.time.is_some() {
                eprintln!("note: scene `{}` has no animations; --time changes nothing", scene.name());
            }
            return Ok(());
        };
        let clip = rig.clip(&choice).map_err(|e| anyhow::anyhow!("--animation: scene `{}`: {e}", scene.name()))?;
        if let Some(t) = time.filter(|_| clip.is_playing()) {
            scene.pose_for_gpu(clip, t);
            println!("animation `{}` at {t:.3} s", rig.describe(clip));
        }
        Ok(())
    }
}

/// The graph a render compiles: its file, where its layers and shaders are, the nodes
/// switched off and the layers substituted.
struct GraphChoice {
    file: PathBuf,
    project: Project,
    off: Vec<String>,
    layers: std::collections::BTreeMap<String, String>,
}

impl GraphChoice {
    /// The graph of `--mode`, else `--graph`, with its layers and shaders beside it unless
    /// given.
    fn new(args: &RenderArgs) -> GraphChoice {
        let file = args.mode.map(|m| PathBuf::from(m.graph())).unwrap_or_else(|| args.graph.clone());
        let mut project = Project::beside_graph(&file);
        if let Some(l) = &args.layers {
            project.layers_dir = l.clone();
        }
        if let Some(s) = &args.shaders {
            project.shaders_dir = s.clone();
        }
        GraphChoice { file, project, off: args.off.clone(), layers: args.layer_choice.substitutions() }
    }

    /// The plan at `size`, compiled with `options`, the nodes switched off and the layers
    /// substituted.
    fn compile(&self, size: (u32, u32), mut options: CompileOptions) -> Result<Plan> {
        options.enabled.extend(self.off.iter().map(|node| (node.clone(), false)));
        options.layers.extend(self.layers.clone());
        Ok(compile::compile_with(&self.file, &self.project, size, &options)?)
    }
}

/// `raygraph render`: checks the graph, opens the GPU, loads and places the scene, renders the
/// frames, writes the PNG and prints what was measured.
pub(crate) fn run(args: RenderArgs) -> Result<()> {
    let graph = GraphChoice::new(&args);
    let width = args.width;
    // Until the camera is known (it may set the aspect ratio).
    let mut height = args.height.unwrap_or(720);
    anyhow::ensure!(width > 0 && height > 0, "--width and --height must be at least 1");
    anyhow::ensure!(args.copies.duplicate >= 1, "--duplicate must be at least 1");
    let format = OutputFormat::of(&args.out)?;
    // Graph errors are reported before a device is opened.
    format.check_graph(&graph.file, &graph.compile((width, height), Default::default())?)?;
    let mut gpu = args.gpu.open_gpu()?;
    if args.kernel_stats.is_some() {
        gpu.record_trace_kernels();
    }
    let largest = gpu.device().limits().max_texture_dimension_2d;
    anyhow::ensure!(
        width <= largest && height <= largest,
        "--width {width} --height {height}: this adapter's largest 2D texture is {largest} pixels on a side"
    );
    let mut plan = graph.compile((width, height), gpu.compile_options())?;
    if plan.passes().iter().any(|p| p.kind == PassKind::Trace) {
        println!("back-end: {}", gpu.describe_backend());
    }
    let mut scene = load_scene(&args, &plan)?;
    let camera = args.view.place(&mut scene)?;
    let sized = output_height(width, args.height, &camera);
    if sized != height {
        height = sized;
        anyhow::ensure!(
            height <= largest,
            "--width {width}: the camera's aspect ratio asks for a height of {height} pixels, past this adapter's largest 2D texture ({largest})"
        );
        plan = graph.compile((width, height), gpu.compile_options())?;
    }
    let mut exec = Executor::new(&gpu, plan, &scene)?;
    // Warm-up: pipeline compilation, first use, and the GPU's clocks back up.
    WarmUp::for_gpu(&gpu, 1).run(&gpu, &mut exec, &scene, &camera)?;
    let mut timings = Vec::new();
    for _ in 0..args.frames.max(1) {
        timings.push(exec.render(&gpu, &camera, &scene)?);
    }
    format.write(&args.out, &gpu, &exec)?;
    let rendered = Rendered { graph_file: &graph.file, scene: &scene.name(), size: (width, height), exec: &exec, timings: &timings };
    rendered.print(args.report.as_deref())?;
    println!("wrote {}", args.out.display());
    if let Some(path) = &args.kernel_stats {
        write_kernel_stats(path, &gpu)?;
    }
    Ok(())
}

/// `--kernel-stats FILE`: the driver's statistics for each trace kernel the executor made, as
/// markdown, one table per kernel.
fn write_kernel_stats(path: &Path, gpu: &Gpu) -> Result<()> {
    let kernels = gpu.recorded_trace_kernels();
    anyhow::ensure!(
        !kernels.is_empty(),
        "--kernel-stats: no trace kernel was written as SPIR-V (the compute back-end's, on a device that takes SPIR-V; the traversal stack: {})",
        if gpu.traversal_stack_cleared() { "cleared, so the modules were compiled from WGSL" } else { "not cleared" }
    );
    let adapter = gpu.adapter().get_info().name;
    let stats = raygraph::runtime::kernel_stats::kernel_statistics(&adapter, &kernels).map_err(|e| anyhow::anyhow!("--kernel-stats: {e}"))?;
    let mut md = format!("# Trace kernels as compiled by the driver\n\n- adapter: {adapter}\n- kernels: {}\n", kernels.len());
    for s in &stats {
        md += &format!("\n## {} ({})\n\n| statistic | value |\n| --- | ---: |\n", s.label, s.executable);
        for (name, value) in &s.statistics {
            md += &format!("| {name} | {value} |\n");
        }
    }
    std::fs::write(path, md).with_context(|| format!("could not write {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The format of the `--out` image, by its extension.
#[derive(Clone, Copy, Debug, PartialEq)]
enum OutputFormat {
    /// The graph output (tone-mapped, 8-bit sRGB).
    Png,
    /// The graph's `hdr_output` (linear radiance, RGBA float32).
    Exr,
}

impl OutputFormat {
    /// `.png` or `.exr` (any case); any other extension is an error.
    fn of(path: &Path) -> Result<OutputFormat> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Ok(OutputFormat::Png),
            Some("exr") => Ok(OutputFormat::Exr),
            _ => anyhow::bail!("--out {}: the extension picks the format: .png (the tone-mapped frame) or .exr (the linear HDR image)", path.display()),
        }
    }

    /// An .exr needs the graph to name its linear HDR image (`hdr_output`), switched on.
    fn check_graph(self, graph_file: &Path, plan: &Plan) -> Result<()> {
        anyhow::ensure!(
            self != OutputFormat::Exr || plan.hdr_output().is_some(),
            "--out .exr: graph {} has no linear HDR output: it names none (`hdr_output: \"node.output\"`, \
             the tone map's input) or that node is switched off; add one to the graph file, or write a .png",
            graph_file.display()
        );
        Ok(())
    }

    /// Reads the image back from `exec` and writes it to `path` (atomically: an error leaves
    /// no partial file).
    fn write(self, path: &Path, gpu: &Gpu, exec: &Executor) -> Result<()> {
        match (self, exec.plan().hdr_output()) {
            (OutputFormat::Png, _) => write_png(path, &exec.read_output(gpu)?)?,
            (OutputFormat::Exr, Some(hdr)) => {
                let (width, height, texels) = exec.read_texture_f32(gpu, hdr)?;
                write_exr(path, width, height, &texels)?;
            }
            (OutputFormat::Exr, None) => anyhow::bail!("--out {}: the plan has no HDR output", path.display()),
        }
        Ok(())
    }
}

/// The scene of `--scene` with what the plan reads, its import notes logged, copied as asked.
fn load_scene(args: &RenderArgs, plan: &Plan) -> Result<Scene> {
    let spec = &args.scene;
    let options = LoadOptions { textures: plan.scene_usage().textures, seed: args.view.seed, gltf_scene: args.view.gltf.gltf_scene.clone() };
    let (mut scene, import) = scene::open(spec, &options)?;
    for note in import.notes() {
        log::warn!(target: LOG_TARGET, "{spec}: {note}"); // once per run; repairs and fallbacks were logged by the import
    }
    if args.copies.duplicate > 1 {
        scene = args.copies.apply(scene);
        let n = args.copies.duplicate;
        println!("scene duplicated {n}x{n}x{n}: {} triangles, {} meshes, {} instances", scene.triangle_count(), scene.meshes().len(), scene.instances().len());
    }
    args.env.apply(&mut scene)?;
    Ok(scene)
}

/// The output height of `render`: `asked` (`--height`), else the width over the camera's aspect
/// ratio, else 720. Given a height that does not match the camera's aspect ratio, the output
/// size wins (the vertical field of view is kept) and a warning says so.
fn output_height(width: u32, asked: Option<u32>, camera: &Camera) -> u32 {
    match (asked, camera.aspect_ratio) {
        (Some(h), Some(a)) => {
            if ((width as f32 / h as f32) / a - 1.0).abs() > 0.01 {
                log::warn!(target: LOG_TARGET, "the camera's aspect ratio {a:.4} is not the output's {width}x{h}: the output size wins (the vertical field of view is kept); leave out --height to take the camera's");
            }
            h
        }
        (Some(h), None) => h,
        (None, Some(a)) => ((width as f32 / a).round() as u32).max(1),
        (None, None) => 720,
    }
}

/// A finished render, for its printout.
struct Rendered<'a> {
    graph_file: &'a Path,
    scene: &'a str,
    size: (u32, u32),
    exec: &'a Executor,
    timings: &'a [FrameTimings],
}

impl Rendered<'_> {
    /// Prints the pass table, writes the report into `report` if given, and prints the culled
    /// passes, the acceleration structures, the rays and the transient memory.
    fn print(&self, report: Option<&Path>) -> Result<()> {
        let (width, height) = self.size;
        let (exec, timings) = (self.exec, self.timings);
        let names: Vec<(String, &'static str)> = exec.plan().passes().iter().map(|p| (p.name.clone(), p.kind.name())).collect();
        println!("graph {} on scene `{}` at {width}x{height}", self.graph_file.display(), self.scene);
        print!("{}", pass_table(&names, timings, width as u64 * height as u64));
        if let Some(dir) = report {
            let r = raygraph::runtime::report::Report::new(&names, width as u64 * height as u64, timings);
            for p in r.write_all(dir, "render").with_context(|| format!("could not write the report into {}", dir.display()))? {
                println!("wrote {}", p.display());
            }
        }
        println!("culled passes: {}", if exec.plan().culled().is_empty() { "none".into() } else { exec.plan().culled().join(", ") });
        if let Some(accel) = timings.first().and_then(|t| t.accel.as_ref()) {
            println!("acceleration structures, first timed frame: {}", accel.describe());
        }
        if let Some(rays) = timings.last().and_then(|t| t.rays) {
            println!(
                "rays per frame: {} traced ({} closest-hit, {} any-hit), {} hits, {} invalid",
                rays.traced(),
                rays.closest,
                rays.any,
                rays.hits,
                rays.invalid
            );
        }
        println!(
            "transient memory: {} with reuse, {} without",
            compile::fmt_bytes(exec.plan().bytes_with_reuse()),
            compile::fmt_bytes(exec.plan().bytes_without_reuse())
        );
        Ok(())
    }
}
