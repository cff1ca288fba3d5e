//! A pass kind written in Rust: a layer file whose pass is `kind: Rust`, run by a compute
//! pipeline this program makes itself, after a WGSL pass that draws a gradient. Renders one
//! frame headless and saves it as a PNG: `cargo run --example rust_pass -- out.png`.
//!
//! The project (a graph, two layer files and a shader) is written to a temporary directory;
//! the Rust pass is registered with the executor under the name the layer file's `entry` gives.

use anyhow::{bail, Context};
use raygraph::graph::{self, Project};
use raygraph::runtime::profiler::FrameTimings;
use raygraph::runtime::{Executor, Gpu, RustPass, RustPassError, RustPassIo, RustPasses};
use raygraph::scene::builtin::default_scene;
use std::path::{Path, PathBuf};

pub const SIZE: (u32, u32) = (64, 48);

/// The graph: the gradient, inverted by the Rust pass, is the output.
const INVERT_GRAPH: &str = r#"Graph(
    output: "invert.inverted",
    nodes: {
        "gradient": Layer(layer: "gradient"),
        "invert": Layer(layer: "invert", inputs: {"image": "gradient.color"}),
    },
)"#;

/// The gradient alone, to compare with.
const GRADIENT_GRAPH: &str = r#"Graph(
    output: "gradient.color",
    nodes: {"gradient": Layer(layer: "gradient")},
)"#;

const GRADIENT_LAYER: &str = r#"Layer(
    outputs: {"color": Texture(format: Rgba8Unorm)},
    passes: [Pass(name: "gradient", kind: Compute, shader: "gradient.wgsl", writes: ["color"])],
)"#;

const GRADIENT_SHADER: &str = "
@group(0) @binding(0) var color: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if any(id.xy >= size) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    textureStore(color, id.xy, vec4<f32>(uv.x, uv.y, 0.25, 1.0));
}
";

/// A layer with no shader: its pass runs the Rust pass registered as `invert`. The resources
/// it binds are the ones declared here.
const INVERT_LAYER: &str = r#"Layer(
    inputs: {"image": Texture(format: Rgba8Unorm)},
    outputs: {"inverted": Texture(format: Rgba8Unorm)},
    params: {"amount": Float(default: 1.0, min: 0.0, max: 1.0)},
    passes: [Pass(name: "invert", kind: Rust, entry: Some("invert"), reads: ["image"], writes: ["inverted"])],
)"#;

/// The Rust pass's own compute shader: `amount` of the way from the image to its inverse.
const INVERT_SHADER: &str = "
struct Settings {
    amount: f32,
}

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var inverted: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(2) var<uniform> settings: Settings;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(inverted);
    if any(id.xy >= size) {
        return;
    }
    let c = textureLoad(image, id.xy, 0);
    textureStore(inverted, id.xy, vec4<f32>(mix(c.rgb, 1.0 - c.rgb, settings.amount), c.a));
}
";

/// Inverts the colours of `image` into `inverted` (alpha kept), by the layer's `amount`.
#[derive(Default)]
pub struct Invert {
    /// Made in `build`: the pipeline, its bind group over the pass's textures, and the
    /// uniform buffer holding `amount`.
    gpu_objects: Option<(wgpu::ComputePipeline, wgpu::BindGroup, wgpu::Buffer)>,
}

impl RustPass for Invert {
    fn build(&mut self, gpu: &Gpu, io: &RustPassIo) -> Result<(), RustPassError> {
        let device = gpu.device();
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("invert"), source: wgpu::ShaderSource::Wgsl(INVERT_SHADER.into()) });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("invert"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let settings = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("invert settings"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let image = io.texture("image")?.texture.create_view(&Default::default());
        let inverted = io.texture("inverted")?.texture.create_view(&Default::default());
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("invert"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&image) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&inverted) },
                wgpu::BindGroupEntry { binding: 2, resource: settings.as_entire_binding() },
            ],
        });
        self.gpu_objects = Some((pipeline, bind_group, settings));
        Ok(())
    }

    fn record(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, io: &RustPassIo) -> Result<(), RustPassError> {
        let Some((pipeline, bind_group, settings)) = &self.gpu_objects else { return Err("the invert pass was not built".into()) };
        let amount = match io.param("amount") {
            Some(graph::desc::ParamValue::Float(v)) => v as f32,
            other => return Err(format!("parameter `amount` is {other:?}, not a float").into()),
        };
        let mut words = [0f32; 4];
        words[0] = amount;
        gpu.queue().write_buffer(settings, 0, &words.iter().flat_map(|w| w.to_le_bytes()).collect::<Vec<u8>>());
        let size = io.texture("inverted")?.texture.size();
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(io.pass_name()), timestamp_writes: None });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(size.width.div_ceil(8), size.height.div_ceil(8), 1);
        Ok(())
    }
}

/// The Rust passes of this example's layer files.
pub fn rust_passes() -> RustPasses {
    RustPasses::new().with("invert", Invert::default)
}

/// Writes the example's project under `dir` (`graph/`, `layers/`, `shaders/`); returns the
/// graph files (with the Rust pass, the gradient alone).
pub fn write_project(dir: &Path) -> anyhow::Result<(PathBuf, PathBuf)> {
    let files = [
        ("graph/invert.ron", INVERT_GRAPH),
        ("graph/gradient.ron", GRADIENT_GRAPH),
        ("layers/gradient.ron", GRADIENT_LAYER),
        ("layers/invert.ron", INVERT_LAYER),
        ("shaders/gradient.wgsl", GRADIENT_SHADER),
    ];
    for (rel, text) in files {
        let path = dir.join(rel);
        std::fs::create_dir_all(path.parent().expect("a relative path with a folder")).with_context(|| format!("cannot create {}", dir.display()))?;
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok((dir.join("graph/invert.ron"), dir.join("graph/gradient.ron")))
}

/// Executor of `graph_file` at [`SIZE`] with `passes` registered.
pub fn executor(gpu: &Gpu, graph_file: &Path, passes: RustPasses) -> anyhow::Result<Executor> {
    let plan = graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), SIZE, &gpu.compile_options())?;
    // The graph reads no scene: nothing of it is uploaded.
    Ok(Executor::with_rust_passes(gpu, plan, &default_scene(), passes)?)
}

/// One frame of `graph_file` with this example's Rust passes, read back from the GPU, and its
/// timings.
pub fn render(gpu: &Gpu, graph_file: &Path) -> anyhow::Result<(image::RgbaImage, FrameTimings, Executor)> {
    let mut exec = executor(gpu, graph_file, rust_passes())?;
    let scene = default_scene();
    let timings = exec.render(gpu, scene.camera(), &scene)?;
    Ok((exec.read_output(gpu)?, timings, exec))
}

fn main() -> anyhow::Result<()> {
    let Some(out) = std::env::args().nth(1).map(PathBuf::from) else { bail!("usage: rust_pass OUT.png") };
    let dir = std::env::temp_dir().join(format!("raygraph-rust-pass-{}", std::process::id()));
    let (graph_file, _) = write_project(&dir)?;
    let gpu = Gpu::new()?;
    let rendered = render(&gpu, &graph_file);
    let _ = std::fs::remove_dir_all(&dir);
    let (image, timings, exec) = rendered?;
    image.save(&out).with_context(|| format!("cannot write {}", out.display()))?;
    let names: Vec<(String, &'static str)> = exec.plan().passes().iter().map(|p| (p.name.clone(), p.kind.name())).collect();
    println!("{}", raygraph::runtime::profiler::pass_table(&names, &[timings], (SIZE.0 * SIZE.1) as u64));
    println!("wrote {} ({}x{})", out.display(), image.width(), image.height());
    Ok(())
}
