//! Serde types of graph description files (`graph/*.ron`) and layer definition files
//! (`layers/*.ron`). These are the file formats; the compiler turns them into a plan.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;

/// A frame: layer instances connected by named outputs, and the output to present.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, rename = "Graph")]
pub(crate) struct GraphDesc {
    /// The resource presented as the frame's image, as `"node.output"`.
    pub(crate) output: String,
    /// The linear, scene-referred HDR image (`"node.output"`, a float colour texture: the tone
    /// map's input) that `render --out x.exr` writes, as `hdr_output: "blend.color"`; without
    /// it the graph has no HDR output.
    #[serde(default, deserialize_with = "some_string")]
    pub(crate) hdr_output: Option<String>,
    /// The graph's nodes by name.
    pub(crate) nodes: BTreeMap<String, NodeDesc>,
}

/// An optional string field written as a plain string (`field: "a.b"`, not `Some("a.b")`).
fn some_string<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    String::deserialize(d).map(Some)
}

/// A node of a graph file.
#[derive(Debug, Clone, Deserialize)]
pub(crate) enum NodeDesc {
    /// An instance of a layer file.
    Layer(LayerNode),
    /// The acceleration-structure cache: output `tlas`, built or updated only when the scene
    /// changes, and only if a kept trace pass reads it.
    Accel(AccelNode),
}

/// Settings of the acceleration-structure node.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AccelNode {
    /// Identical meshes share one BLAS (off: one BLAS per instance).
    pub dedup: bool,
    /// `compute` back-end: one BVH over every instance's world-space triangles instead of a
    /// BLAS per mesh under a TLAS of instances. Faster to trace where instance boxes overlap;
    /// any change to the scene rebuilds it. The `ray-query` back-end ignores it.
    pub merge: bool,
}

impl Default for AccelNode {
    fn default() -> Self {
        Self { dedup: true, merge: false }
    }
}

/// A node that instantiates a layer file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LayerNode {
    /// Layer file name without extension, looked up in the layers directory.
    pub layer: String,
    /// Layer input name -> `"node.output"` that feeds it.
    #[serde(default)]
    pub inputs: BTreeMap<String, String>,
    /// Parameter overrides.
    #[serde(default)]
    pub params: BTreeMap<String, ParamValue>,
    /// `false` switches the node off: its passes and resources are not instantiated, and the
    /// inputs it fed read what its layer's `bypass` passes through, else their declared
    /// `fallback` value.
    #[serde(default = "enabled_default")]
    pub enabled: bool,
}

fn enabled_default() -> bool {
    true
}

/// A parameter value as written in a graph file.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    /// `true` or `false`.
    Bool(bool),
    /// An integer (also an enum parameter's index).
    Int(i64),
    /// A float.
    Float(f64),
}

impl ParamValue {
    /// `bool`, `int` or `float`, for messages.
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            ParamValue::Bool(_) => "bool",
            ParamValue::Int(_) => "int",
            ParamValue::Float(_) => "float",
        }
    }
}

/// A value as the graph file writes it: `true`, `3`, `0.5`.
impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ParamValue::Bool(b) => write!(f, "{b}"),
            ParamValue::Int(i) => write!(f, "{i}"),
            ParamValue::Float(x) => write_float(f, x),
        }
    }
}

/// A float with a decimal point, as RON needs it to read a float back (`1.0`, not `1`).
fn write_float(f: &mut fmt::Formatter<'_>, x: f64) -> fmt::Result {
    if x.is_finite() && x.fract() == 0.0 {
        write!(f, "{x:.1}")
    } else {
        write!(f, "{x}")
    }
}

/// A reusable sub-graph of passes with typed inputs, outputs and parameters.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, rename = "Layer")]
pub struct LayerDesc {
    /// Resources the layer reads from other nodes.
    #[serde(default)]
    pub inputs: BTreeMap<String, ResourceDecl>,
    /// Resources the layer gives other nodes.
    #[serde(default)]
    pub outputs: BTreeMap<String, ResourceDecl>,
    /// Resources private to the layer, written by one of its passes and read by another.
    #[serde(default)]
    pub transients: BTreeMap<String, ResourceDecl>,
    /// History resources: each name (a resource the layer's passes may read, never write) holds
    /// the previous frame's contents of the output or transient texture it names, e.g.
    /// `history: {"ao_previous": "ao"}`. The two textures are allocated apart from every
    /// transient and swapped by the executor after every frame; on a frame where the history is
    /// not valid (the first, after a recompile, a resize or a camera cut) `frame.history_valid`
    /// is 0 and the history's contents are undefined.
    #[serde(default)]
    pub history: BTreeMap<String, String>,
    /// Pass-through when the node is switched off: each output named here is replaced, for the
    /// nodes that read it, by whatever feeds the input it names, e.g. `bypass: {"filtered":
    /// "signal"}` for a filter. The two must be textures of one format. Outputs without a bypass
    /// leave their readers on their `fallback`.
    #[serde(default)]
    pub bypass: BTreeMap<String, String>,
    /// Parameters a graph file may set.
    #[serde(default)]
    pub params: BTreeMap<String, ParamDecl>,
    /// The layer's passes, in order.
    pub passes: Vec<PassDesc>,
}

/// A declared resource: a texture, a buffer, or the acceleration structure.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum ResourceDecl {
    /// A texture.
    Texture(TextureDecl),
    /// A storage buffer.
    Buffer(BufferDecl),
    /// The scene's acceleration structure (produced by an `Accel` node, read by trace passes
    /// through the back-end's trace module).
    Accel,
}

/// A declaration as a layer file writes it: `Texture(format: Rgba16Float)`, `Buffer(size: 64)`, `Accel`.
impl fmt::Display for ResourceDecl {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResourceDecl::Texture(t) => {
                write!(f, "Texture(format: {}", t.format)?;
                if t.size != SizeDecl::default() {
                    write!(f, ", size: {}", t.size)?;
                }
                if t.layers != 1 {
                    write!(f, ", layers: {}", t.layers)?;
                }
                if let Some((r, g, b, a)) = t.fallback {
                    write!(f, ", fallback: Some((")?;
                    for (i, c) in [r, g, b, a].into_iter().enumerate() {
                        if i > 0 {
                            write!(f, ", ")?;
                        }
                        write_float(f, c.into())?;
                    }
                    write!(f, "))")?;
                }
                write!(f, ")")
            }
            ResourceDecl::Buffer(b) if b.zeroed => write!(f, "Buffer(size: {}, zeroed: true)", b.size),
            ResourceDecl::Buffer(b) => write!(f, "Buffer(size: {})", b.size),
            ResourceDecl::Accel => write!(f, "Accel"),
        }
    }
}

impl ResourceDecl {
    /// Whether this is a depth texture (a pass's depth attachment rather than a colour one).
    pub(crate) fn is_depth_texture(&self) -> bool {
        matches!(self, ResourceDecl::Texture(t) if t.format.is_depth())
    }
}

/// A declared texture.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDecl {
    /// The texel format.
    pub format: Format,
    /// The size, relative to the frame by default.
    #[serde(default)]
    pub size: SizeDecl,
    /// Array layers (default 1). A texture of several is read as a `_2d_array` texture and
    /// drawn one layer at a time by render passes that name it (`PassDesc::layer`): the faces
    /// of cube shadow maps.
    #[serde(default = "one_layer")]
    pub layers: u32,
    /// For a layer input: the value it reads (a 1x1 texture) when its producer is switched
    /// off or it is not connected. Inputs without one must be connected.
    #[serde(default)]
    pub fallback: Option<(f32, f32, f32, f32)>,
}

fn one_layer() -> u32 {
    1
}

/// A declared storage buffer.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BufferDecl {
    /// Size in bytes.
    pub size: u64,
    /// Zeroed every frame just before the pass that writes it runs, or would run in a frame
    /// where its `runs_when` keeps it from running (counters that a pass appends to with
    /// atomics). Default `false`: the contents are undefined until written.
    #[serde(default)]
    pub zeroed: bool,
}

/// Texture size, relative to the frame or absolute.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub enum SizeDecl {
    /// A fraction of the frame size (1.0 = full resolution).
    Relative(f32),
    /// A size in texels.
    Absolute(u32, u32),
}

impl Default for SizeDecl {
    fn default() -> Self {
        SizeDecl::Relative(1.0)
    }
}

/// `Relative(0.5)` or `Absolute(64, 64)`, as a layer file writes it.
impl fmt::Display for SizeDecl {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SizeDecl::Relative(s) => {
                write!(f, "Relative(")?;
                write_float(f, s.into())?;
                write!(f, ")")
            }
            SizeDecl::Absolute(w, h) => write!(f, "Absolute({w}, {h})"),
        }
    }
}

impl SizeDecl {
    /// The size in texels for a frame of `frame` pixels (at least 1x1).
    pub(crate) fn resolve(&self, frame: (u32, u32)) -> (u32, u32) {
        match *self {
            SizeDecl::Relative(s) => (((frame.0 as f32 * s).round() as u32).max(1), ((frame.1 as f32 * s).round() as u32).max(1)),
            SizeDecl::Absolute(w, h) => (w.max(1), h.max(1)),
        }
    }
}

/// Texture formats a layer may declare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
pub enum Format {
    /// One 8-bit normalized channel.
    R8Unorm,
    /// Two 8-bit normalized channels.
    Rg8Unorm,
    /// Four 8-bit normalized channels.
    Rgba8Unorm,
    /// Four 8-bit normalized channels, sRGB-encoded colour.
    Rgba8UnormSrgb,
    /// One 16-bit float channel.
    R16Float,
    /// Two 16-bit float channels.
    Rg16Float,
    /// Four 16-bit float channels.
    Rgba16Float,
    /// One 32-bit float channel.
    R32Float,
    /// Two 32-bit float channels.
    Rg32Float,
    /// Four 32-bit float channels.
    Rgba32Float,
    /// One 32-bit unsigned integer channel.
    R32Uint,
    /// Two 32-bit unsigned integer channels.
    Rg32Uint,
    /// Four 32-bit unsigned integer channels.
    Rgba32Uint,
    /// 32-bit float depth.
    Depth32Float,
}

/// The format's name as layer files write it (`Rgba16Float`).
impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The variant names are the file spelling (serde reads them unchanged).
        fmt::Debug::fmt(self, f)
    }
}

impl Format {
    /// The wgpu format.
    pub(crate) fn to_wgpu(self) -> wgpu::TextureFormat {
        use wgpu::TextureFormat as T;
        match self {
            Format::R8Unorm => T::R8Unorm,
            Format::Rg8Unorm => T::Rg8Unorm,
            Format::Rgba8Unorm => T::Rgba8Unorm,
            Format::Rgba8UnormSrgb => T::Rgba8UnormSrgb,
            Format::R16Float => T::R16Float,
            Format::Rg16Float => T::Rg16Float,
            Format::Rgba16Float => T::Rgba16Float,
            Format::R32Float => T::R32Float,
            Format::Rg32Float => T::Rg32Float,
            Format::Rgba32Float => T::Rgba32Float,
            Format::R32Uint => T::R32Uint,
            Format::Rg32Uint => T::Rg32Uint,
            Format::Rgba32Uint => T::Rgba32Uint,
            Format::Depth32Float => T::Depth32Float,
        }
    }

    /// The WGSL storage-texture format of the same name, where one exists.
    pub(crate) fn to_storage(self) -> Option<naga::StorageFormat> {
        use naga::StorageFormat as S;
        Some(match self {
            Format::R8Unorm => S::R8Unorm,
            Format::Rg8Unorm => S::Rg8Unorm,
            Format::Rgba8Unorm => S::Rgba8Unorm,
            Format::R16Float => S::R16Float,
            Format::Rg16Float => S::Rg16Float,
            Format::Rgba16Float => S::Rgba16Float,
            Format::R32Float => S::R32Float,
            Format::Rg32Float => S::Rg32Float,
            Format::Rgba32Float => S::Rgba32Float,
            Format::R32Uint => S::R32Uint,
            Format::Rg32Uint => S::Rg32Uint,
            Format::Rgba32Uint => S::Rgba32Uint,
            Format::Rgba8UnormSrgb | Format::Depth32Float => return None,
        })
    }

    /// Whether it is the depth format.
    pub(crate) fn is_depth(self) -> bool {
        matches!(self, Format::Depth32Float)
    }

    /// Whether its channels are unsigned integers.
    pub(crate) fn is_uint(self) -> bool {
        matches!(self, Format::R32Uint | Format::Rg32Uint | Format::Rgba32Uint)
    }

    /// Whether a shader may sample it with a filtering sampler.
    pub(crate) fn is_filterable(self) -> bool {
        !matches!(
            self,
            Format::R32Float | Format::Rg32Float | Format::Rgba32Float | Format::R32Uint | Format::Rg32Uint | Format::Rgba32Uint | Format::Depth32Float
        )
    }

    /// The channels of a texel and how each is stored (depth: one f32).
    pub(crate) fn texel_layout(self) -> (usize, TexelKind) {
        use TexelKind::*;
        match self {
            Format::R8Unorm => (1, Unorm8),
            Format::Rg8Unorm => (2, Unorm8),
            Format::Rgba8Unorm | Format::Rgba8UnormSrgb => (4, Unorm8),
            Format::R16Float => (1, Float16),
            Format::Rg16Float => (2, Float16),
            Format::Rgba16Float => (4, Float16),
            Format::R32Float | Format::Depth32Float => (1, Float32),
            Format::Rg32Float => (2, Float32),
            Format::Rgba32Float => (4, Float32),
            Format::R32Uint => (1, Uint32),
            Format::Rg32Uint => (2, Uint32),
            Format::Rgba32Uint => (4, Uint32),
        }
    }

    /// One texel holding `v` (the channels the format has), for constant textures; `None` for
    /// depth, which cannot be written from the CPU.
    pub(crate) fn encode_texel(self, v: [f32; 4]) -> Option<Vec<u8>> {
        if self.is_depth() {
            return None;
        }
        let unorm = |x: f32| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let (channels, kind) = self.texel_layout();
        let mut out = Vec::new();
        for &x in &v[..channels] {
            match kind {
                TexelKind::Unorm8 => out.push(unorm(x)),
                TexelKind::Float16 => out.extend_from_slice(&f32_to_f16(x).to_le_bytes()),
                TexelKind::Float32 => out.extend_from_slice(&x.to_le_bytes()),
                TexelKind::Uint32 => out.extend_from_slice(&(x.max(0.0) as u32).to_le_bytes()),
            }
        }
        Some(out)
    }

    /// Bytes of one texel.
    pub(crate) fn bytes_per_texel(self) -> u64 {
        let (channels, kind) = self.texel_layout();
        (channels * kind.bytes()) as u64
    }
}

/// How each channel of a texel is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TexelKind {
    /// 8-bit normalized.
    Unorm8,
    /// 16-bit float.
    Float16,
    /// 32-bit float.
    Float32,
    /// 32-bit unsigned integer.
    Uint32,
}

impl TexelKind {
    /// Bytes per channel.
    pub fn bytes(self) -> usize {
        match self {
            TexelKind::Unorm8 => 1,
            TexelKind::Float16 => 2,
            TexelKind::Float32 | TexelKind::Uint32 => 4,
        }
    }
}

/// A declared parameter: type, default and range. Parameters reach shaders through a
/// uniform struct named `params` whose members are matched by name.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum ParamDecl {
    /// A float parameter.
    Float {
        /// The value without an override.
        default: f64,
        /// The smallest value allowed.
        min: f64,
        /// The largest value allowed.
        max: f64,
    },
    /// An integer parameter.
    Int {
        /// The value without an override.
        default: i64,
        /// The smallest value allowed.
        min: i64,
        /// The largest value allowed.
        max: i64,
    },
    /// A switch.
    Bool {
        /// The value without an override.
        default: bool,
    },
    /// One of named choices; the shader sees the chosen one's index (i32 or u32), and a graph
    /// file sets it by index.
    Enum {
        /// The chosen value's name without an override.
        default: String,
        /// The names of the choices, in index order.
        values: Vec<String>,
    },
}

impl ParamDecl {
    /// `float`, `int`, `bool` or `enum`, for messages.
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            ParamDecl::Float { .. } => "float",
            ParamDecl::Int { .. } => "int",
            ParamDecl::Bool { .. } => "bool",
            ParamDecl::Enum { .. } => "enum",
        }
    }

    /// The default value; an enum whose default is not one of its values (a layer file error
    /// the compiler reports) defaults to its first.
    pub fn default_value(&self) -> ParamValue {
        match self {
            ParamDecl::Float { default, .. } => ParamValue::Float(*default),
            ParamDecl::Int { default, .. } => ParamValue::Int(*default),
            ParamDecl::Bool { default } => ParamValue::Bool(*default),
            ParamDecl::Enum { default, values } => ParamValue::Int(values.iter().position(|v| v == default).unwrap_or(0) as i64),
        }
    }
}

/// One GPU pass of a layer.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, rename = "Pass")]
pub struct PassDesc {
    /// The pass's name, unique in its layer.
    pub name: String,
    /// What kind of GPU work it is.
    pub kind: PassKind,
    /// WGSL file, relative to the `shaders/` directory beside the layers directory (none for
    /// `Rust` passes).
    #[serde(default)]
    pub shader: String,
    /// Entry point: the compute entry for `Compute`, the fragment entry for render passes; for
    /// `Rust`, the name the pass is registered under.
    #[serde(default)]
    pub entry: Option<String>,
    /// Vertex entry of render passes (default `vs_main`).
    #[serde(default)]
    pub vertex_entry: Option<String>,
    /// Layer resources the pass reads (bound as textures or read-only buffers).
    #[serde(default)]
    pub reads: Vec<String>,
    /// Layer resources the pass writes (storage textures/buffers for compute, attachments for
    /// render passes, in fragment output order; a depth texture becomes the depth attachment).
    #[serde(default)]
    pub writes: Vec<String>,
    /// How many workgroups a compute pass dispatches.
    #[serde(default)]
    pub dispatch: Dispatch,
    /// `SceneRaster` only: the rasterizer culls the back faces of single-sided materials (the
    /// default; glTF `doubleSided` materials are drawn on both sides, and mirroring instance
    /// transforms are accounted for). `false` draws both sides of every material.
    #[serde(default = "enabled_default")]
    pub cull_back_faces: bool,
    /// `SceneRaster` with a `shadow_slot` only: cull the back faces of instances whose mesh is
    /// closed and wound outwards (`scene::topology`), opaque and wholly beyond the near plane of
    /// the slot's light, whatever `cull_back_faces` says. From a light outside a closed mesh the
    /// nearest surface is always a front face, so a pass that writes the nearest depth is
    /// unchanged and draws about half the triangles. Default `false`.
    #[serde(default)]
    pub cull_closed_back_faces: bool,
    /// `SceneRaster` only: the pass draws raster shadow-map slot N. In a frame where no light
    /// has that slot, the pass is not recorded (its texture keeps what it had; no shader reads
    /// a slot no light has) and its row reads 0 ms.
    #[serde(default)]
    pub shadow_slot: Option<u32>,
    /// With `shadow_slot`: (columns, rows): the pass draws columns x rows slots from
    /// `shadow_slot` on in one render pass, slot `shadow_slot + k` into tile (k % columns,
    /// k / columns) of its attachments, each tile a viewport of (width / columns, height /
    /// rows) texels, row 0 at the top (a cube map's six faces side by side: one render pass
    /// instead of six, whose encoding is most of a frame's CPU time). The pass is recorded when
    /// a light uses any of its slots; a tile whose slot none uses is cleared and left so.
    #[serde(default)]
    pub shadow_tiles: Option<(u32, u32)>,
    /// Render passes only: the array layer of its layered attachments the pass draws into
    /// (`TextureDecl::layers`); attachments of one layer ignore it. A render pass that writes
    /// a layered texture must name one.
    #[serde(default)]
    pub layer: Option<u32>,
    /// `SceneRaster` only: instances of BLEND materials are not drawn (a G-buffer of the
    /// opaque surfaces, over which the `rt_blend` layer composites the translucent ones by
    /// ray tracing), or that a `translucent` pass blends over them. Default `false`: they are drawn
    /// screen-door (`shaders/common/raster_alpha_test.wgsl`), as the shadow maps draw them.
    #[serde(default)]
    pub skip_blend: bool,
    /// `SceneRaster` only: the pass draws the translucent instances alone (BLEND or
    /// transmissive materials), back to front by the centre of each instance's bounds, with
    /// blending into its colour targets (cleared to transparent): the first with premultiplied
    /// alpha (`src + (1 - src.a) x dst`: the translucent layer's radiance and coverage), any
    /// other by `src + (1 - src) x dst` per channel (with `src` one minus a surface's
    /// transmittance, it holds one minus the product of the transmittances: the tint of what
    /// lies behind). It has no depth attachment; its shader tests depth against the opaque
    /// pass's.
    /// In a frame without translucent instances it is not recorded (its targets keep what they
    /// had; readers compile their use out with `SCENE_BLEND`). Default `false`.
    #[serde(default)]
    pub translucent: bool,
    /// The pass is recorded only in frames where this holds of a count an earlier frame wrote
    /// (`runs_when: Some(AtLeast(buffer: "covered", fraction: 0.25))`); in the others it is not
    /// recorded (what it writes keeps what it had; its row reads 0 ms), as [`RunsWhen`] says.
    /// Two passes with the opposite conditions on one count are two schedules of the same
    /// work, each compiled alone. Default: every frame.
    #[serde(default)]
    pub runs_when: Option<RunsWhen>,
}

/// When a pass with `runs_when` is recorded: the first two 32-bit words of `buffer` (one of
/// the layer's buffers, which one of its passes writes), a count and the whole it is part of
/// (the pixels with rays, and the pixels), compared as `count < fraction x whole` or its
/// opposite. The executor reads the words back after each frame and the next frame compares
/// what came back; before the first frame has come back, and after a recompile, the count is
/// taken as the whole. Every frame evaluates the conditions once, so all the passes of a frame
/// see the same count.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum RunsWhen {
    /// The count is below `fraction` x the whole.
    Below {
        /// The layer's buffer holding the count (word 0) and the whole (word 1).
        buffer: String,
        /// The share of the whole the count is compared with.
        fraction: f64,
    },
    /// The count is at least `fraction` x the whole.
    AtLeast {
        /// The layer's buffer holding the count (word 0) and the whole (word 1).
        buffer: String,
        /// The share of the whole the count is compared with.
        fraction: f64,
    },
}

impl RunsWhen {
    /// The buffer holding the count and the whole.
    pub fn buffer(&self) -> &str {
        match self {
            RunsWhen::Below { buffer, .. } | RunsWhen::AtLeast { buffer, .. } => buffer,
        }
    }

    /// The share of the whole the count is compared with.
    pub fn fraction(&self) -> f64 {
        match self {
            RunsWhen::Below { fraction, .. } | RunsWhen::AtLeast { fraction, .. } => *fraction,
        }
    }

    /// Whether the pass runs with `count` of `whole`.
    pub fn holds(&self, count: u32, whole: u32) -> bool {
        let below = f64::from(count) < self.fraction() * f64::from(whole);
        match self {
            RunsWhen::Below { .. } => below,
            RunsWhen::AtLeast { .. } => !below,
        }
    }
}

/// The kind of GPU work of a pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum PassKind {
    /// A compute shader dispatch.
    Compute,
    /// A full-screen triangle drawn into the pass's attachments.
    Fullscreen,
    /// The scene's meshes drawn into the pass's attachments.
    SceneRaster,
    /// A compute pass that reads the acceleration structure and includes `trace/trace.wgsl`,
    /// which the active back-end implements.
    Trace,
    /// The acceleration-structure build of an `Accel` node (no shader; not for layer files).
    #[serde(skip)]
    AccelBuild,
    /// GPU work recorded by Rust code (`crate::runtime::RustPass`): no shader; `entry` names
    /// the pass as the program registered it, and the resources it binds are the ones the
    /// layer file declares and lists in `reads` and `writes`.
    Rust,
}

impl PassKind {
    /// The kind's name in pass tables (`compute`, `scene_raster`, ...).
    pub fn name(self) -> &'static str {
        match self {
            PassKind::Compute => "compute",
            PassKind::Fullscreen => "fullscreen",
            PassKind::SceneRaster => "scene_raster",
            PassKind::Trace => "trace",
            PassKind::AccelBuild => "accel_build",
            PassKind::Rust => "rust",
        }
    }

    /// Whether the pass is recorded as a compute dispatch.
    pub(crate) fn is_compute(self) -> bool {
        matches!(self, PassKind::Compute | PassKind::Trace)
    }
}

/// Dispatch size of a compute pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
pub enum Dispatch {
    /// One invocation per texel of the first written texture (or of the frame), using the
    /// shader's workgroup size.
    #[default]
    PerPixel,
    /// A fixed number of workgroups.
    Groups(u32, u32, u32),
}

/// IEEE half precision from f32 (round to nearest even; overflow to infinity).
pub(crate) fn f32_to_f16(x: f32) -> u16 {
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32;
    let mant = bits & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if mant != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        // Subnormal half: value = m16 * 2^-24, so m16 = m >> (14 - e).
        let m = mant | 0x80_0000;
        let shift = (14 - e) as u32;
        let (q, rem, halfway) = (m >> shift, m & ((1 << shift) - 1), 1 << (shift - 1));
        let up = rem > halfway || (rem == halfway && q & 1 == 1);
        return sign | (q + up as u32) as u16;
    }
    let half = sign | ((e as u16) << 10) | (mant >> 13) as u16;
    let rest = mant & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && half & 1 != 0) {
        half + 1
    } else {
        half
    }
}

/// f32 from IEEE half precision.
pub(crate) fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let mant = (h & 0x3ff) as f32;
    sign * match exp {
        0 => mant * 2f32.powi(-24),
        31 => {
            if mant == 0.0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + mant / 1024.0) * 2f32.powi(e - 15),
    }
}
