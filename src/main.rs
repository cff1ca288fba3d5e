//! The `raygraph` command line: parses arguments and calls the library.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use raygraph::backend::Backend;
use raygraph::bench::rays::RaysConfig;
use raygraph::graph::{self, Mode, Project};
use raygraph::runtime::{exec::write_png, profiler::pass_table, Executor, Gpu};
use raygraph::scene::{self, track::Track, LoadOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "raygraph", version, about = "Render-graph framework for hybrid ray tracing on wgpu")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless, write a PNG and print per-pass timings.
    Render {
        /// Graph description file.
        #[arg(long, default_value = "graph/raster.ron", conflicts_with = "mode")]
        graph: PathBuf,
        /// The paper's modes, a shortcut for their graphs: raster (graph/raster.ron), hybrid
        /// (graph/hybrid.ron), full-rt (graph/full_rt.ron).
        #[arg(long)]
        mode: Option<Mode>,
        /// A built-in scene (default, box, organic, atrium) or a .gltf/.glb file.
        #[arg(long, default_value = "default")]
        scene: String,
        #[command(flatten)]
        copies: DuplicateArgs,
        /// Traversal back-end: ray-query, compute or rt-pipeline (default: ray-query where the
        /// adapter supports it, else compute; rt-pipeline only when asked for).
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[command(flatten)]
        view: ViewArgs,
        /// Frame width in pixels, up to the adapter's largest 2D texture.
        #[arg(long, default_value_t = 1280)]
        width: u32,
        /// Frame height in pixels [default: the width over the camera's aspect ratio (a glTF
        /// camera's `aspectRatio`, or xmag/ymag), else 720]
        #[arg(long)]
        height: Option<u32>,
        /// Output PNG.
        #[arg(long, default_value = "out.png")]
        out: PathBuf,
        /// Frames to time (after untimed frames until the frame time settles); the table shows medians.
        #[arg(long, default_value_t = 10)]
        frames: u32,
        /// Also write the per-pass statistics (mean, median, min, max) as CSV, markdown and a
        /// Chrome trace (open in Perfetto) into this folder.
        #[arg(long)]
        report: Option<PathBuf>,
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
    },
    /// Graph files: validate or draw.
    Graph {
        #[command(subcommand)]
        command: GraphCommand,
    },
    /// Scenes: statistics and export.
    Scene {
        #[command(subcommand)]
        command: SceneCommand,
    },
    /// A long headless run in which the scene, the graph and a shader change; checks that
    /// memory and live GPU objects stay flat and the image finite (RELIABILITY.md).
    Soak {
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
    },
    /// The correctness suites on this adapter, at the sizes the test suite uses: hard-cases
    /// (watertightness, grazing, degenerate and non-finite geometry, offsets, culling: 13 cases
    /// of up to about 16,000 rays each, on every back-end and layout), agreement (every
    /// back-end against the f64 reference caster: 1,600 rays on each of box, organic and
    /// default, 600 on atrium; the closed organic mesh from inside; invalid rays) and
    /// reference-channels (every ray-traced channel of the full ray-tracing graph against the
    /// f64 reference renderer at 64x48, 8 AO rays, on default and a small scene, on every
    /// back-end and layout). One line per suite and back-end: passed, FAILED or not applicable
    /// (a back-end the adapter lacks); exits non-zero on any failure. On 2-core lavapipe: about
    /// 10 s for hard-cases, 10 s for agreement, 70 s for reference-channels (most of it the
    /// CPU reference, which a GPU machine's cores share out); seconds of GPU time on a GPU.
    Selftest {
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
    },
    /// The experiments.
    Bench {
        #[command(subcommand)]
        command: BenchCommand,
    },
    /// The live viewer: a window with the running graph, the per-pass profiler overlay, the
    /// parameters panel and hot reload of graph, layer and WGSL files.
    View {
        /// A built-in scene or a glTF file.
        #[arg(default_value = "default")]
        scene: String,
        /// A graph file (default: the --mode's).
        #[arg(long)]
        graph: Option<PathBuf>,
        #[arg(long, default_value = "hybrid")]
        mode: Mode,
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
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
    },
}

#[derive(Subcommand)]
enum BenchCommand {
    /// The paper's Table 3: GigaRays/s of the scene workload (primary + 1 shadow + N AO rays per
    /// pixel) on each scene, and the Miss and Stress tests, for every back-end.
    Rays {
        /// Seconds on a CPU instead of the paper's size (CI).
        #[arg(long)]
        quick: bool,
        /// Comma-separated scenes (built-in names or glTF files).
        #[arg(long, value_delimiter = ',')]
        scenes: Option<Vec<String>>,
        #[command(flatten)]
        timing: TimingArgs,
        /// AO rays per pixel of the scene workload.
        #[arg(long)]
        ao_rays: Option<i64>,
        /// AO ray length of the scene workload, as a fraction of the scene's bounding radius
        /// [default: 0.05]
        #[arg(long)]
        ao_length: Option<f64>,
        /// Primary rays per pixel of the Miss and Stress tests.
        #[arg(long)]
        primary_rays: Option<i64>,
        /// Comma-separated fractions of the frame: each scene also measured with its camera moved
        /// along its view axis until it covers that fraction (rows "SCENE at 2%").
        #[arg(long, value_delimiter = ',')]
        coverage: Vec<f64>,
        /// Only this back-end (default: every back-end the adapter has).
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        /// Results folder.
        #[arg(long, default_value = "bench-results/rays")]
        out: PathBuf,
    },
    /// Speed, build time and GPU memory against unique triangles (10^4 to 3x10^7): each step a
    /// scene copied NxNxN without de-duplication, on every back-end (BENCHMARKS.md, "Scale").
    Scale {
        /// Seconds on a CPU: two small steps at a small size (CI).
        #[arg(long)]
        quick: bool,
        /// Comma-separated steps `scene:N` (the scene copied NxNxN)
        /// [default: organic:2,organic:3,atrium:1,atrium:2,atrium:3,atrium:4,atrium:5].
        #[arg(long, value_delimiter = ',')]
        steps: Option<Vec<String>>,
        #[command(flatten)]
        timing: TimingArgs,
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/scale")]
        out: PathBuf,
    },
    /// The paper's Figure 9: BLAS and TLAS build times against triangles, each scene copied
    /// N×N×N (one BLAS per copy), per builder, with SAH cost and the trace time of the result.
    Build {
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
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/build")]
        out: PathBuf,
    },
    /// The paper's Figures 10 and 11: a camera track through raster, hybrid and full RT; FPS
    /// and GigaRays/s per frame.
    Track {
        #[arg(long)]
        quick: bool,
        #[arg(long, default_value = "atrium")]
        scene: String,
        #[arg(long, default_value = "assets/tracks/atrium.ron")]
        track: PathBuf,
        #[arg(long)]
        width: Option<u32>,
        #[arg(long)]
        height: Option<u32>,
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/track")]
        out: PathBuf,
    },
    /// Animated scenes played through the paper's scene workload under each policy of the
    /// acceleration-structure cache (refit until the SAH cost grows past its threshold, always
    /// refit, always rebuild): per frame the update's GPU and CPU milliseconds, what it did, the
    /// SAH growth, and the trace passes' GigaRays/s.
    Anim {
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
        #[arg(long)]
        width: Option<u32>,
        #[arg(long)]
        height: Option<u32>,
        /// Traversal back-end [default: compute].
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/anim")]
        out: PathBuf,
    },
    /// Ambient occlusion against its closed form (floor under a parallel ceiling): error
    /// (RMSE, relMSE, bias, variance over seeds) against rays per pixel and GPU time, for white
    /// noise and the R2 sequence, with the fitted convergence slopes.
    /// Also AO, soft shadows, GI and glossy reflections of `graph/hybrid_denoised.ron`, noisy
    /// and filtered, against converged references (relMSE, ꟻLIP) and GPU time, with an
    /// equal-time table and a camera track for flicker and ghosting (`filters.md`).
    Error {
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
    },
    /// Bytes per ray of Table 3's tests on the compute back-end, counted by its CPU mirror, and
    /// the load-bound ceiling they give; with a `bench rays` CSV, achieved/ceiling (no GPU).
    Roofline {
        #[arg(long)]
        quick: bool,
        /// A `bench rays` results CSV whose compute rows give the achieved GigaRays/s.
        #[arg(long)]
        rays: Option<PathBuf>,
        /// Aggregate L1 bandwidth in bytes/s (default: the H100's).
        #[arg(long)]
        bandwidth: Option<f64>,
        #[arg(long, default_value = "bench-results/roofline")]
        out: PathBuf,
    },
    /// The three modes on the same scenes, camera and back-end, with their effects on and off:
    /// the images, and ꟻLIP mean and RMSE between every pair (ACCURACY.md, "Real assets").
    Modes {
        /// Comma-separated scenes (built-in names or glTF files), each optionally `NAME=SCENE`
        /// to name its images.
        #[arg(long, default_value = "default")]
        scenes: String,
        #[arg(long, default_value_t = 320)]
        width: u32,
        #[arg(long, default_value_t = 240)]
        height: u32,
        /// The traversal back-end of the hybrid and full-RT modes (default: the start-up choice).
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/modes")]
        out: PathBuf,
    },
    /// Reflection bounces 1..8 against rays/s.
    Depth {
        #[arg(long)]
        quick: bool,
        #[arg(long, default_value = "atrium")]
        scene: String,
        #[arg(long)]
        width: Option<u32>,
        #[arg(long)]
        height: Option<u32>,
        #[arg(long)]
        backend: Option<Backend>,
        #[command(flatten)]
        deadline: Deadline,
        #[arg(long, default_value = "bench-results/depth")]
        out: PathBuf,
    },
}

/// Runs a bench behind a progress bar; the bench reports (done, total, label).
fn with_progress<T>(run: impl FnOnce(&mut dyn FnMut(usize, usize, &str)) -> T) -> T {
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

/// `bench error`'s part on the filtered effects (`raygraph::bench::filters`).
fn bench_filters(gpu: &raygraph::runtime::Gpu, quick: bool, args: &FilterArgs, backend: Backend, out: &Path) -> Result<()> {
    use raygraph::bench::filters::{self, FiltersConfig};
    let root = PathBuf::from(".");
    let cfg = args.apply(if quick { FiltersConfig::quick(&root, backend) } else { FiltersConfig::full(&root, backend) });
    let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), gpu, cfg.size);
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

/// Reports the plots a bench wrote.
fn write_plots(result: std::result::Result<Vec<PathBuf>, String>) -> Result<()> {
    for p in result.map_err(anyhow::Error::msg)? {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Rewrites a bench's files in `dir` with the rows finished so far, atomically: a run that is
/// interrupted (Ctrl-C, a lost device) leaves those rows and never a half-written file. A
/// failure is a warning here; the final write reports it as an error.
fn write_partial(dir: &Path, files: &[(&str, String)]) {
    let written = raygraph::bench::results_dir(dir)
        .and_then(|dir| files.iter().try_for_each(|(name, text)| raygraph::util::write_atomic(&dir.join(name), text.as_bytes())));
    if let Err(e) = written {
        log::warn!("could not update the results in {}: {e}", dir.display());
    }
}

/// Writes a bench's files into `dir` atomically, prints the markdown (the `.md` file).
fn write_results(dir: &Path, files: &[(&str, String)]) -> Result<()> {
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

/// The GPU deadline of a command that renders.
#[derive(clap::Args)]
struct Deadline {
    /// Seconds one GPU submission may run; past it the run ends with an error naming the
    /// frame's passes, and nothing is written [default: 10, 120 on a software adapter such as
    /// lavapipe].
    #[arg(long, value_name = "SECONDS")]
    gpu_timeout: Option<f64>,
}

impl Deadline {
    /// The deadline asked for (`None`: the adapter's default).
    fn duration(&self) -> Result<Option<std::time::Duration>> {
        let Some(seconds) = self.gpu_timeout else { return Ok(None) };
        let d = std::time::Duration::try_from_secs_f64(seconds).ok().filter(|d| !d.is_zero());
        d.map(Some).with_context(|| format!("--gpu-timeout {seconds}: give a positive number of seconds"))
    }

    /// Opens the GPU with `backend` forced (or selected) and this deadline.
    fn open_gpu(&self, backend: Option<Backend>) -> Result<Gpu> {
        let timeout = self.duration()?;
        let mut gpu = Gpu::with_backend(backend)?;
        gpu.set_gpu_timeout(timeout.unwrap_or(gpu.gpu_timeout()));
        gpu.set_on_gpu_timeout(exit_after_gpu_timeout);
        Ok(gpu)
    }
}

/// Ends the process after a GPU timeout: the error, exit status 1, and nothing released on
/// the way out (releasing GPU objects the stuck work uses can block in the driver).
fn exit_after_gpu_timeout(e: &raygraph::error::RuntimeError) {
    eprintln!("{e}");
    std::process::exit(1);
}

/// Frame size and timed frames of the ray benches (`bench rays`, `bench scale`).
#[derive(clap::Args)]
struct TimingArgs {
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    #[arg(long)]
    frames: Option<u32>,
}

impl TimingArgs {
    /// `cfg` with the size and frame count given.
    fn apply(&self, mut cfg: RaysConfig) -> RaysConfig {
        cfg.size = (self.width.unwrap_or(cfg.size.0), self.height.unwrap_or(cfg.size.1));
        cfg.frames = self.frames.unwrap_or(cfg.frames);
        cfg
    }
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
    fn apply(&self, mut cfg: raygraph::bench::filters::FiltersConfig) -> raygraph::bench::filters::FiltersConfig {
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

/// Copies of the scene on a grid.
#[derive(clap::Args)]
struct DuplicateArgs {
    /// Copy the scene N×N×N times on a grid (the camera stays the scene's).
    #[arg(long, default_value_t = 1)]
    duplicate: u32,
    /// With --duplicate: give every copy its own meshes (unique triangles, nothing instanced).
    #[arg(long)]
    no_dedup: bool,
}

impl DuplicateArgs {
    /// `s` copied as asked (itself for one copy).
    fn apply(&self, s: scene::Scene) -> scene::Scene {
        if self.duplicate > 1 {
            raygraph::scene::duplicate::duplicate(&s, self.duplicate, !self.no_dedup)
        } else {
            s
        }
    }
}

/// Which scene of a glTF file is drawn.
#[derive(clap::Args)]
struct GltfSceneArg {
    /// The glTF file's scene to draw, by index or name (see `raygraph scene info`) [default:
    /// the file's `scene`].
    #[arg(long, value_name = "INDEX|NAME")]
    gltf_scene: Option<String>,
}

/// Where the camera is.
#[derive(clap::Args)]
struct ViewArgs {
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

impl ViewArgs {
    /// Poses `scene` at the asked time of the asked clip (nothing asked: left at rest); the
    /// track's time when a track gives the camera and no time is given.
    fn pose(&self, scene: &mut raygraph::scene::Scene, track: Option<&Track>) -> Result<()> {
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

#[derive(Subcommand)]
enum SceneCommand {
    /// Print triangles, meshes, instances, materials, alpha modes, textures, bounds, lights,
    /// camera presets, texture fallbacks and what the file uses that raygraph approximates or
    /// ignores.
    Info {
        /// A built-in scene name or a .gltf/.glb file.
        scene: String,
        #[command(flatten)]
        copies: DuplicateArgs,
        #[arg(long, default_value_t = raygraph::scene::procedural::ATRIUM_DEFAULT_SEED)]
        seed: u64,
        #[command(flatten)]
        gltf: GltfSceneArg,
    },
    /// Write a scene (built-in or loaded) as binary glTF.
    Export {
        scene: String,
        out: PathBuf,
        #[command(flatten)]
        copies: DuplicateArgs,
        #[arg(long, default_value_t = raygraph::scene::procedural::ATRIUM_DEFAULT_SEED)]
        seed: u64,
        #[command(flatten)]
        gltf: GltfSceneArg,
    },
    /// Write an orbit camera track around a scene (a starting point for recorded tracks).
    Orbit {
        scene: String,
        out: PathBuf,
        /// Length in seconds.
        #[arg(long, default_value_t = 10.0)]
        seconds: f32,
    },
}

#[derive(Subcommand)]
enum GraphCommand {
    /// Validate a graph file (and its layers and shaders) and print the plan.
    Check {
        file: PathBuf,
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
    },
    /// Write the compiled graph as Graphviz (to stdout, or --out).
    Dot {
        file: PathBuf,
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// The output height of `render`: `asked` (`--height`), else the width over the camera's aspect
/// ratio, else 720. Given a height that does not match the camera's aspect ratio, the output
/// size wins (the vertical field of view is kept) and a warning says so.
fn output_height(width: u32, asked: Option<u32>, camera: &raygraph::scene::Camera) -> u32 {
    match (asked, camera.aspect_ratio) {
        (Some(h), Some(a)) => {
            if ((width as f32 / h as f32) / a - 1.0).abs() > 0.01 {
                log::warn!("the camera's aspect ratio {a:.4} is not the output's {width}x{h}: the output size wins (the vertical field of view is kept); leave out --height to take the camera's");
            }
            h
        }
        (Some(h), None) => h,
        (None, Some(a)) => ((width as f32 / a).round() as u32).max(1),
        (None, None) => 720,
    }
}

fn project_for(graph: &Path, layers: Option<PathBuf>, shaders: Option<PathBuf>) -> Project {
    let mut p = Project::beside_graph(graph);
    if let Some(l) = layers {
        p.layers_dir = l;
    }
    if let Some(s) = shaders {
        p.shaders_dir = s;
    }
    p
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info,wgpu_core=warn,wgpu_hal=warn,naga=warn")).init();
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Graph { command: GraphCommand::Check { file, width, height } } => {
            let plan = graph::compile(&file, &Project::beside_graph(&file), (width, height))?;
            print!("{}", plan.report());
            println!("ok: {} is valid", file.display());
        }
        Command::Graph { command: GraphCommand::Dot { file, out } } => {
            let plan = graph::compile(&file, &Project::beside_graph(&file), (1280, 720))?;
            let dot = graph::dot::to_dot(&plan);
            match out {
                Some(path) => std::fs::write(&path, dot).with_context(|| format!("could not write {}", path.display()))?,
                None => print!("{dot}"),
            }
        }
        Command::Scene { command: SceneCommand::Info { scene, copies, seed, gltf } } => {
            let (s, report) = scene::open(&scene, &LoadOptions { textures: true, seed, gltf_scene: gltf.gltf_scene })?;
            let s = copies.apply(s);
            print!("{}", raygraph::scene::info::describe(&s, Some(&report)));
        }
        Command::Scene { command: SceneCommand::Export { scene, out, copies, seed, gltf } } => {
            let (s, _) = scene::open(&scene, &LoadOptions { textures: true, seed, gltf_scene: gltf.gltf_scene })?;
            let s = copies.apply(s);
            raygraph::scene::export::write_glb(&s, &out)?;
            println!("wrote {} ({} triangles, {} meshes, {} textures)", out.display(), s.triangle_count(), s.meshes().len(), s.textures().len());
        }
        Command::Scene { command: SceneCommand::Orbit { scene, out, seconds } } => {
            let (s, _) = scene::open(&scene, &LoadOptions { textures: false, ..Default::default() })?;
            let b = s.bounds();
            let radius = 0.5 * b.diagonal().max(1e-3);
            let track = Track::orbit(b.center(), radius * 1.6, radius * 0.5, seconds, 12, s.camera().fov_y.to_degrees());
            track.save(&out)?;
            println!("wrote {} ({} key-frames, {} frames at {} fps)", out.display(), track.keys.len(), track.frame_count(), track.fps);
        }
        Command::Selftest { suite, backend, out, verbose, shaders, deadline } => {
            let cfg = raygraph::selftest::SelftestConfig { shaders, backends: backend, suites: suite };
            run_selftest(&deadline.open_gpu(None)?, &cfg, out.as_deref(), verbose)?
        }
        Command::Soak { scene, frames, cycle, width, height, rss_tolerance, backend, log, deadline } => {
            let gpu = deadline.open_gpu(backend)?;
            let mut cfg = raygraph::soak::SoakConfig::new(Path::new("."), frames, cycle, (width, height));
            cfg.scene = scene;
            cfg.rss_tolerance_mib = rss_tolerance;
            cfg.backend = backend;
            run_soak(&gpu, &cfg, log.as_deref())?;
        }
        Command::Bench { command: BenchCommand::Rays { quick, scenes, timing, ao_rays, ao_length, primary_rays, coverage, backend, deadline, out } } => {
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let backends = match backend {
                Some(b) => vec![b],
                None => gpu.backends().to_vec(),
            };
            let root = PathBuf::from(".");
            let mut cfg = timing.apply(if quick { RaysConfig::quick(&root, backends) } else { RaysConfig::paper(&root, backends) });
            if let Some(s) = scenes {
                cfg.scenes = s;
            }
            cfg.ao_rays = ao_rays.unwrap_or(cfg.ao_rays);
            cfg.ao_length = ao_length.unwrap_or(cfg.ao_length);
            cfg.primary_rays = primary_rays.unwrap_or(cfg.primary_rays);
            if let Some(bad) = coverage.iter().find(|c| !(**c > 0.0 && **c <= 1.0)) {
                anyhow::bail!("--coverage {bad}: give fractions of the frame in (0, 1]");
            }
            cfg.coverages = coverage;
            let command = std::env::args().collect::<Vec<_>>().join(" ");
            let info = raygraph::bench::RunInfo::new(&command, &gpu, cfg.size);
            // The markdown first: a run interrupted between the two writes leaves the CSV (what
            // scripts read) at most one row behind it, never ahead.
            let files = |rows: &[_]| {
                [
                    ("rays.md", raygraph::bench::rays::markdown(&info, &cfg, rows)),
                    ("rays_passes.csv", raygraph::bench::rays::passes_csv(&info, rows)),
                    ("rays.csv", raygraph::bench::rays::csv(&info, &cfg, rows)),
                ]
            };
            let rows = with_progress(|progress| raygraph::bench::rays::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows))))?;
            write_results(&out, &files(&rows))?;
            write_plots(raygraph::bench::rays::plots(&out, &rows))?;
        }
        Command::Bench { command: BenchCommand::Scale { quick, steps, timing, backend, deadline, out } } => {
            use raygraph::bench::scale::{self as scale_bench, ScaleConfig};
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let backends = backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec());
            let root = PathBuf::from(".");
            let rays = timing.apply(if quick { RaysConfig::quick(&root, backends) } else { RaysConfig::paper(&root, backends) });
            let mut cfg = ScaleConfig::full(rays);
            if quick {
                cfg.steps = vec![("box".into(), 1), ("organic".into(), 2)];
            }
            if let Some(list) = steps {
                cfg.steps = ScaleConfig::parse_steps(&list).map_err(anyhow::Error::msg)?;
            }
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.rays.size);
            let files =
                |rows: &[_], skipped: &[String]| [("scale.md", scale_bench::markdown(&info, rows, skipped)), ("scale.csv", scale_bench::csv(&info, rows))];
            let (rows, skipped) = with_progress(|progress| scale_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows, &[]))))?;
            write_results(&out, &files(&rows, &skipped))?;
        }
        Command::Bench { command: BenchCommand::Build { quick, scenes, max_factor, max_triangles, backend, deadline, out } } => {
            use raygraph::bench::build::{self as build_bench, BuildBenchConfig};
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let backends = backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec());
            let root = PathBuf::from(".");
            let mut cfg = if quick { BuildBenchConfig::quick(&root, backends) } else { BuildBenchConfig::paper(&root, backends) };
            if let Some(s) = scenes {
                cfg.scenes = s;
            }
            cfg.max_factor = max_factor.unwrap_or(cfg.max_factor);
            cfg.max_triangles = max_triangles.unwrap_or(cfg.max_triangles);
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.rays);
            let files =
                |rows: &[_], skipped: &[String]| [("build.csv", build_bench::csv(&info, rows)), ("build.md", build_bench::markdown(&info, rows, skipped))];
            let (rows, skipped) = with_progress(|progress| build_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows, &[]))))?;
            write_results(&out, &files(&rows, &skipped))?;
            write_plots(build_bench::plots(&out, &rows))?;
            let cpu_builds = build_bench::run_cpu_builds(&cfg, if quick { 2 } else { 9 })?;
            write_results(
                &out,
                &[("cpu_build.csv", build_bench::cpu_build_csv(&info, &cpu_builds)), ("cpu_build.md", build_bench::cpu_build_markdown(&info, &cpu_builds))],
            )?;
            if cfg.backends.contains(&Backend::Compute) {
                let refit = build_bench::run_refit(&gpu, &cfg, if quick { 3 } else { 20 })?;
                write_results(&out, &[("refit.csv", build_bench::refit_csv(&info, &refit)), ("refit.md", build_bench::refit_markdown(&info, &refit))])?;
                let gpu_builds = build_bench::run_gpu_builds(&gpu, &cfg, if quick { 2 } else { 10 })?;
                write_results(
                    &out,
                    &[("gpu_build.csv", build_bench::gpu_build_csv(&info, &gpu_builds)), ("gpu_build.md", build_bench::gpu_build_markdown(&info, &gpu_builds))],
                )?;
            }
        }
        Command::Bench { command: BenchCommand::Track { quick, scene, track, width, height, backend, deadline, out } } => {
            use raygraph::bench::track::{self as track_bench, TrackConfig};
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let (w, h) = if quick { (48, 27) } else { (2560, 1440) };
            let cfg = TrackConfig {
                scene,
                track: track.clone(),
                size: (width.unwrap_or(w), height.unwrap_or(h)),
                stride: if quick { 60 } else { 1 },
                backends: backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec()),
                root: PathBuf::from("."),
            };
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.size);
            let files = |rows: &[_]| [("track.csv", track_bench::csv(&info, rows)), ("track.md", track_bench::markdown(&info, &track, rows))];
            let rows = with_progress(|progress| track_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows))))?;
            write_results(&out, &files(&rows))?;
            write_plots(track_bench::plots(&out, &rows))?;
        }
        Command::Bench { command: BenchCommand::Anim { quick, scenes, frames, fps, max_growth, width, height, backend, deadline, out } } => {
            use raygraph::accel::deform::RefitPolicy;
            use raygraph::bench::anim::{self as anim_bench, AnimConfig};
            let backend = backend.unwrap_or(Backend::Compute);
            let gpu = deadline.open_gpu(Some(backend))?;
            println!("adapter: {}", gpu.describe());
            let (w, h) = if quick { (96, 54) } else { (1920, 1080) };
            let scenes = if quick { ["skinned_cylinder", "spinner"].map(|n| format!("assets/gltf/animated/{n}.gltf")).to_vec() } else { scenes };
            let cfg = AnimConfig {
                scenes,
                size: (width.unwrap_or(w), height.unwrap_or(h)),
                frames: if quick { 24 } else { frames.max(1) },
                fps,
                backend,
                policies: if max_growth.is_empty() {
                    vec![RefitPolicy::default()]
                } else {
                    max_growth.iter().map(|&g| RefitPolicy::Auto { max_growth: g }).collect()
                }
                .into_iter()
                .chain([RefitPolicy::Cost, RefitPolicy::AlwaysRefit, RefitPolicy::AlwaysRebuild])
                .collect(),
                root: PathBuf::from("."),
            };
            anyhow::ensure!(cfg.fps.is_finite() && cfg.fps > 0.0, "--fps {}: give a positive number", cfg.fps);
            anyhow::ensure!(max_growth.iter().all(|g| g.is_finite() && *g >= 1.0), "--max-growth: give growths of at least 1");
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.size);
            let files = |rows: &[_]| [("anim.csv", anim_bench::csv(&info, rows)), ("anim.md", anim_bench::markdown(&info, rows))];
            let rows = with_progress(|progress| anim_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows))))?;
            write_results(&out, &files(&rows))?;
            write_plots(anim_bench::plots(&out, &rows))?;
        }
        Command::Bench { command: BenchCommand::Error { quick, backend, filters_only, filter_args, deadline, out } } => {
            use raygraph::bench::error::{self as error_bench, ErrorConfig};
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let backends = backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec());
            bench_filters(&gpu, quick, &filter_args, *backends.first().context("no back-end")?, &out)?;
            if filters_only {
                return Ok(());
            }
            let root = PathBuf::from(".");
            let cfg = if quick { ErrorConfig::quick(&root, backends) } else { ErrorConfig::full(&root, backends) };
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.size);
            let files = |rows: &[_]| [("error.csv", error_bench::csv(&info, rows)), ("error.md", error_bench::markdown(&info, rows))];
            let rows = with_progress(|progress| error_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows))))?;
            write_results(&out, &files(&rows))?;
            write_plots(error_bench::plots(&out, &rows))?;
            let (scenes, size): (&[&str], _) = if quick { (&["default"], (96, 54)) } else { (&["default", "atrium"], (1280, 720)) };
            let hybrid = error_bench::run_hybrid(&gpu, &cfg, scenes, size)?;
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, size);
            write_results(&out, &[("hybrid.csv", error_bench::hybrid_csv(&info, &hybrid)), ("hybrid.md", error_bench::hybrid_markdown(&info, &hybrid))])?;
            let sweep = if quick { error_bench::ShadowMapSweep::quick() } else { error_bench::ShadowMapSweep::full() };
            // The ray-traced truth is the same on every back-end (tests/reference_channels.rs):
            // the first one traces it.
            let backend = *cfg.backends.first().context("no back-end to trace the shadow rays with")?;
            let shadow_maps = error_bench::run_shadow_maps(&gpu, &cfg, &sweep, backend)?;
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, sweep.size);
            write_results(
                &out,
                &[
                    ("shadow_maps.csv", error_bench::shadow_map_csv(&info, &shadow_maps)),
                    ("shadow_maps.md", error_bench::shadow_map_markdown(&info, &shadow_maps)),
                ],
            )?;
            write_plots(error_bench::shadow_map_plot(&out, &shadow_maps))?;
        }
        Command::Bench { command: BenchCommand::Roofline { quick, rays, bandwidth, out } } => {
            use raygraph::bench::roofline;
            let bandwidth = bandwidth.unwrap_or(roofline::H100_L1_BYTES_PER_S);
            let (stride, ao_rays, scenes): (u32, u32, &[&str]) = if quick { (160, 4, &["box", "organic"]) } else { (16, 64, &["box", "organic", "atrium"]) };
            let mut rows = Vec::new();
            for name in scenes {
                let (s, _) = scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
                rows.push(roofline::scene_workload(&s, stride, ao_rays, bandwidth));
            }
            let (atrium, _) = scene::open(if quick { "organic" } else { "atrium" }, &LoadOptions { textures: false, ..Default::default() })?;
            let miss = raygraph::bench::rays::miss_outside_camera(&atrium);
            rows.push(roofline::primary_workload("Miss (outside)", &atrium, &miss, stride, bandwidth));
            if let Ok(inside) = atrium.preset(raygraph::bench::rays::MISS_INSIDE_PRESET) {
                rows.push(roofline::primary_workload("Miss (inside)", &atrium, &inside, stride, bandwidth));
            }
            let stress = atrium.preset(raygraph::bench::rays::STRESS_PRESET).map_err(anyhow::Error::msg)?;
            rows.push(roofline::primary_workload("Stress", &atrium, &stress, stride, bandwidth));
            if let Some(path) = &rays {
                let text = std::fs::read_to_string(path).with_context(|| format!("could not read {}", path.display()))?;
                roofline::with_achieved(&mut rows, &text);
            }
            write_results(&out, &[("roofline.csv", roofline::csv(&rows)), ("roofline.md", roofline::markdown(&rows, bandwidth, stride))])?;
        }
        Command::Bench { command: BenchCommand::Depth { quick, scene, width, height, backend, deadline, out } } => {
            use raygraph::bench::depth::{self as depth_bench, DepthConfig};
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let (w, h, max_bounces, frames) = if quick { (48, 27, 3, 1) } else { (2560, 1440, 8, 5) };
            let cfg = DepthConfig {
                scene,
                size: (width.unwrap_or(w), height.unwrap_or(h)),
                max_bounces,
                frames,
                backends: backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec()),
                root: PathBuf::from("."),
            };
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, cfg.size);
            let files = |rows: &[_]| [("depth.csv", depth_bench::csv(&info, rows)), ("depth.md", depth_bench::markdown(&info, rows))];
            let rows = with_progress(|progress| depth_bench::run(&gpu, &cfg, progress, |rows| write_partial(&out, &files(rows))))?;
            write_results(&out, &files(&rows))?;
            write_plots(depth_bench::plots(&out, &rows))?;
        }
        Command::Bench { command: BenchCommand::Modes { scenes, width, height, backend, deadline, out } } => {
            anyhow::ensure!(width > 0 && height > 0 && width <= 16384 && height <= 16384, "--width and --height must be between 1 and 16384");
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let backend = backend.unwrap_or(gpu.selection().backend);
            let mut loaded = Vec::new();
            for item in scenes.split(',').map(str::trim).filter(|s| !s.is_empty()) {
                // `NAME=SCENE` names the images; a bare scene is named by its file stem.
                let (name, spec) = match item.split_once('=') {
                    Some((name, spec)) => (name.to_string(), spec),
                    None => (Path::new(item).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| item.to_string()), item),
                };
                let (scene, _) = raygraph::scene::open(spec, &Default::default()).with_context(|| format!("cannot open scene {spec}"))?;
                loaded.push((name, scene));
            }
            let dir = raygraph::bench::results_dir(&out).with_context(|| format!("could not create {}", out.display()))?;
            let rows = raygraph::bench::modes::run(&gpu, Path::new("."), &loaded, backend, (width, height), &dir)?;
            let info = raygraph::bench::RunInfo::new(&std::env::args().collect::<Vec<_>>().join(" "), &gpu, (width, height));
            write_results(&out, &[("modes.md", raygraph::bench::modes::markdown(&info, backend, &rows))])?;
        }
        Command::View { scene, graph, mode, backend, deadline, width, height, camera, seed, gltf, frames, screenshot, script, verbose, animation, time } => {
            anyhow::ensure!(time.is_finite(), "--time {time}: give a finite number of seconds");
            anyhow::ensure!(width > 0 && height > 0 && width <= 16384 && height <= 16384, "--width and --height must be between 1 and 16384");
            let opts = raygraph::viewer::ViewerOptions {
                scene,
                graph,
                mode,
                backend,
                gpu_timeout: deadline.duration()?,
                size: (width, height),
                camera,
                seed,
                gltf_scene: gltf.gltf_scene,
                frames,
                screenshot,
                script,
                verbose,
                animation,
                time,
            };
            raygraph::viewer::run(opts).map_err(anyhow::Error::msg)?;
        }
        Command::Render { graph, mode, scene: scene_spec, copies, backend, deadline, view, width, height, out, frames, report, layers, shaders, off } => {
            let graph_file = mode.map(|m| PathBuf::from(m.graph())).unwrap_or(graph);
            let asked_height = height;
            // Until the camera is known (it may set the aspect ratio).
            let mut height = height.unwrap_or(720);
            anyhow::ensure!(width > 0 && height > 0, "--width and --height must be at least 1");
            anyhow::ensure!(copies.duplicate >= 1, "--duplicate must be at least 1");
            let project = project_for(&graph_file, layers, shaders);
            let switches = |mut options: graph::compile::CompileOptions| {
                options.enabled.extend(off.iter().map(|node| (node.clone(), false)));
                options
            };
            // Graph errors are reported before a device is opened.
            graph::compile::compile_with(&graph_file, &project, (width, height), &switches(Default::default()))?;
            let gpu = deadline.open_gpu(backend)?;
            println!("adapter: {}", gpu.describe());
            let largest = gpu.device().limits().max_texture_dimension_2d;
            anyhow::ensure!(
                width <= largest && height <= largest,
                "--width {width} --height {height}: this adapter's largest 2D texture is {largest} pixels on a side"
            );
            let mut plan = graph::compile::compile_with(&graph_file, &project, (width, height), &switches(gpu.compile_options()))?;
            if plan.passes().iter().any(|p| p.kind == raygraph::graph::desc::PassKind::Trace) {
                println!("back-end: {}", gpu.describe_backend());
            }
            let (mut scene, import) =
                scene::open(&scene_spec, &LoadOptions { textures: plan.scene_usage().textures, seed: view.seed, gltf_scene: view.gltf.gltf_scene.clone() })?;
            for note in import.notes() {
                log::warn!("{scene_spec}: {note}"); // once per run; repairs and fallbacks were logged by the import
            }
            if copies.duplicate > 1 {
                scene = copies.apply(scene);
                let n = copies.duplicate;
                println!(
                    "scene duplicated {n}x{n}x{n}: {} triangles, {} meshes, {} instances",
                    scene.triangle_count(),
                    scene.meshes().len(),
                    scene.instances().len()
                );
            }
            let track = view.track.as_deref().map(Track::load).transpose()?;
            view.pose(&mut scene, track.as_ref())?;
            let camera = match (&view.camera, &track) {
                (Some(name), _) => scene.preset(name).map_err(anyhow::Error::msg)?,
                (None, Some(track)) => track.camera_at_frame(view.track_frame, scene.camera()).fit_clip_planes(scene.bounds()),
                (None, None) => *scene.camera(),
            };
            let sized = output_height(width, asked_height, &camera);
            if sized != height {
                height = sized;
                anyhow::ensure!(
                    height <= largest,
                    "--width {width}: the camera's aspect ratio asks for a height of {height} pixels, past this adapter's largest 2D texture ({largest})"
                );
                plan = graph::compile::compile_with(&graph_file, &project, (width, height), &switches(gpu.compile_options()))?;
            }
            let mut exec = Executor::new(&gpu, plan, &scene)?;
            // Warm-up: pipeline compilation, first use, and the GPU's clocks back up.
            raygraph::runtime::warm_up::WarmUp::for_gpu(&gpu, 1).run(&gpu, &mut exec, &scene, &camera)?;
            let mut timings = Vec::new();
            for _ in 0..frames.max(1) {
                timings.push(exec.render(&gpu, &camera, &scene)?);
            }
            let img = exec.read_output(&gpu)?;
            write_png(&out, &img)?;
            let names: Vec<(String, &'static str)> = exec.plan().passes().iter().map(|p| (p.name.clone(), p.kind.name())).collect();
            println!("graph {} on scene `{}` at {width}x{height}", graph_file.display(), scene.name());
            print!("{}", pass_table(&names, &timings, width as u64 * height as u64));
            if let Some(dir) = &report {
                let r = raygraph::runtime::report::Report::new(&names, width as u64 * height as u64, &timings);
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
                graph::compile::fmt_bytes(exec.plan().bytes_with_reuse()),
                graph::compile::fmt_bytes(exec.plan().bytes_without_reuse())
            );
            println!("wrote {}", out.display());
        }
    }
    Ok(())
}

/// `raygraph soak`: the run, its lines on stdout and, with `--log`, in the log file.
fn run_soak(gpu: &Gpu, cfg: &raygraph::soak::SoakConfig, log: Option<&Path>) -> Result<()> {
    use raygraph::soak::{self, Check};
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
    summary.iter().for_each(|l| println!("{l}"));
    lines.extend(summary);
    write_log(&lines)?;
    if !report.failures.is_empty() {
        anyhow::bail!("soak failed: {} failed checks (listed above)", report.failures.len());
    }
    Ok(())
}

/// `raygraph selftest`: every suite's line on stdout and, with `--out`, in DIR/selftest.log.
fn run_selftest(gpu: &Gpu, cfg: &raygraph::selftest::SelftestConfig, out: Option<&Path>, verbose: bool) -> Result<()> {
    use raygraph::selftest;
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
