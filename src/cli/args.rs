//! The argument groups that several subcommands share through `#[command(flatten)]`: the GPU a
//! command opens, frame sizes, copies of the scene and the glTF scene drawn.

use anyhow::{Context, Result};
use raygraph::backend::Backend;
use raygraph::bench::rays::RaysConfig;
use raygraph::runtime::Gpu;
use raygraph::scene::Scene;
use std::path::Path;

/// The GPU deadline of a command that renders.
#[derive(clap::Args)]
pub(crate) struct Deadline {
    /// Seconds one GPU submission may run; past it the run ends with an error naming the
    /// frame's passes, and nothing is written [default: 10, 120 on a software adapter such as
    /// lavapipe].
    #[arg(long, value_name = "SECONDS")]
    gpu_timeout: Option<f64>,
}

impl Deadline {
    /// The deadline asked for (`None`: the adapter's default).
    pub(crate) fn duration(&self) -> Result<Option<std::time::Duration>> {
        let Some(seconds) = self.gpu_timeout else { return Ok(None) };
        let d = std::time::Duration::try_from_secs_f64(seconds).ok().filter(|d| !d.is_zero());
        d.map(Some).with_context(|| format!("--gpu-timeout {seconds}: give a positive number of seconds"))
    }

    /// Opens the GPU with `backend` forced (or selected) and this deadline.
    pub(crate) fn open_gpu(&self, backend: Option<Backend>) -> Result<Gpu> {
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

/// The traversal back-end and the GPU deadline of a command that renders. A command whose
/// `--backend` needs a help line gives it with `#[command(mut_arg("backend", ..))]`.
#[derive(clap::Args)]
pub(crate) struct GpuArgs {
    #[arg(long)]
    pub(crate) backend: Option<Backend>,
    #[command(flatten)]
    pub(crate) deadline: Deadline,
}

impl GpuArgs {
    /// Opens the GPU with the back-end and deadline asked for, and prints its adapter.
    pub(crate) fn open_gpu(&self) -> Result<Gpu> {
        let gpu = self.deadline.open_gpu(self.backend)?;
        println!("adapter: {}", gpu.describe());
        Ok(gpu)
    }

    /// The back-ends a bench runs: the one asked for, else every one `gpu` has.
    pub(crate) fn backends(&self, gpu: &Gpu) -> Vec<Backend> {
        backends(self.backend, gpu)
    }
}

/// `backend` alone when one is asked for, else every back-end `gpu` has.
pub(crate) fn backends(backend: Option<Backend>, gpu: &Gpu) -> Vec<Backend> {
    backend.map(|b| vec![b]).unwrap_or_else(|| gpu.backends().to_vec())
}

/// An error unless `width` and `height` are both between 1 and 16384.
pub(crate) fn ensure_size_in_range(width: u32, height: u32) -> Result<()> {
    anyhow::ensure!(width > 0 && height > 0 && width <= 16384 && height <= 16384, "--width and --height must be between 1 and 16384");
    Ok(())
}

/// A frame size that replaces a command's own, side by side.
#[derive(clap::Args)]
pub(crate) struct FrameSize {
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
}

impl FrameSize {
    /// The size given, each side not given taken from `default`.
    pub(crate) fn or(&self, default: (u32, u32)) -> (u32, u32) {
        (self.width.unwrap_or(default.0), self.height.unwrap_or(default.1))
    }
}

/// Frame size and timed frames of the ray benches (`bench rays`, `bench scale`).
#[derive(clap::Args)]
pub(crate) struct TimingArgs {
    #[command(flatten)]
    size: FrameSize,
    #[arg(long)]
    frames: Option<u32>,
}

impl TimingArgs {
    /// The ray benches' configuration (`quick`: the CI one, else the paper's) on `backends`,
    /// with the size and frame count given.
    pub(crate) fn config(&self, quick: bool, backends: Vec<Backend>) -> RaysConfig {
        let root = Path::new(".");
        let mut cfg = if quick { RaysConfig::quick(root, backends) } else { RaysConfig::paper(root, backends) };
        cfg.size = self.size.or(cfg.size);
        cfg.frames = self.frames.unwrap_or(cfg.frames);
        cfg
    }
}

/// Layer substitutions asked for on the command line (`CompileOptions::layers`).
#[derive(clap::Args)]
pub(crate) struct LayerChoice {
    /// Compile the graph's nodes of layer LAYER from `layers/VARIANT.ron` instead, a layer with
    /// the same inputs, outputs and parameters (repeatable), e.g. `rt_ao=rt_ao_compacted` or
    /// `rt_ao=rt_ao_persistent` (the AO schedules).
    #[arg(long = "use-layer", value_name = "LAYER=VARIANT", value_parser = parse_layer_substitution)]
    use_layer: Vec<(String, String)>,
}

impl LayerChoice {
    /// The substitutions, `layer -> variant`.
    pub(crate) fn substitutions(&self) -> std::collections::BTreeMap<String, String> {
        self.use_layer.iter().cloned().collect()
    }
}

/// `LAYER=VARIANT`, both non-empty layer names.
fn parse_layer_substitution(s: &str) -> Result<(String, String), String> {
    let named = |n: &str| !n.is_empty() && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    match s.split_once('=') {
        Some((layer, variant)) if named(layer.trim()) && named(variant.trim()) => Ok((layer.trim().to_string(), variant.trim().to_string())),
        _ => Err(format!("`{s}`: give LAYER=VARIANT, two layer file names without `.ron` (e.g. rt_ao=rt_ao_compacted)")),
    }
}

/// Copies of the scene on a grid.
#[derive(clap::Args)]
pub(crate) struct DuplicateArgs {
    /// Copy the scene N×N×N times on a grid (the camera stays the scene's).
    #[arg(long, default_value_t = 1)]
    pub(crate) duplicate: u32,
    /// With --duplicate: give every copy its own meshes (unique triangles, nothing instanced).
    #[arg(long)]
    pub(crate) no_dedup: bool,
}

impl DuplicateArgs {
    /// `s` copied as asked (itself for one copy).
    pub(crate) fn apply(&self, s: Scene) -> Scene {
        if self.duplicate > 1 {
            raygraph::scene::duplicate::duplicate(&s, self.duplicate, !self.no_dedup)
        } else {
            s
        }
    }
}

/// Which scene of a glTF file is drawn.
#[derive(clap::Args)]
pub(crate) struct GltfSceneArg {
    /// The glTF file's scene to draw, by index or name (see `raygraph scene info`) [default:
    /// the file's `scene`].
    #[arg(long, value_name = "INDEX|NAME")]
    pub(crate) gltf_scene: Option<String>,
}

/// An environment map lighting the scene in place of the default sun and sky.
#[derive(clap::Args)]
pub(crate) struct EnvArgs {
    /// An equirectangular HDR environment map (Radiance .hdr or OpenEXR .exr, twice as wide as
    /// high) that lights the scene in place of the default sun and sky; the file's own lights
    /// stay.
    #[arg(long, value_name = "FILE")]
    pub(crate) env: Option<std::path::PathBuf>,
    /// Scales the environment map's radiance.
    #[arg(long, default_value_t = 1.0, requires = "env", value_parser = parse_non_negative)]
    pub(crate) env_intensity: f32,
    /// Turns the environment map about the up axis (+Y) by this many degrees, counter-clockwise
    /// seen from above.
    #[arg(long, default_value_t = 0.0, requires = "env", allow_negative_numbers = true)]
    pub(crate) env_rotation: f32,
}

impl EnvArgs {
    /// The map given, loaded, with its intensity and rotation; `None` without `--env`.
    pub(crate) fn load(&self) -> Result<Option<raygraph::scene::environment::Environment>> {
        let Some(path) = &self.env else { return Ok(None) };
        let mut env = raygraph::scene::environment::Environment::load(path)?;
        env.intensity = self.env_intensity;
        env.rotation = self.env_rotation.to_radians();
        Ok(Some(env))
    }

    /// Lights `scene` by the map given, if any.
    pub(crate) fn apply(&self, scene: &mut Scene) -> Result<()> {
        if let Some(env) = self.load()? {
            scene.set_environment(Some(env));
        }
        Ok(())
    }
}

/// A finite number of at least 0.
fn parse_non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!("`{s}`: give a finite number of at least 0")),
    }
}
