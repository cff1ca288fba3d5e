//! The compiler's result: [`Plan`] (kept passes in execution order, culled passes, resources,
//! slots), its parts [`PlannedPass`], [`PlannedResource`], [`Slot`] and [`Usage`], and the
//! human-readable report of a plan.

use crate::backend::Backend;
use crate::error::Location;
use crate::graph::desc::*;
use crate::graph::reflect::ShaderInfo;
use crate::scene::usage::SceneUsage;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Index of a resource in [`Plan::resources`].
pub type ResourceId = usize;

/// A resource of the compiled graph.
#[derive(Debug, Clone)]
pub struct PlannedResource {
    /// `"node.output"` for layer outputs, `"node/name"` for transients.
    pub name: String,
    /// What it is: a texture with its format and size rule, a buffer, or the acceleration
    /// structure.
    pub decl: ResourceDecl,
    /// Resolved texture size (textures only).
    pub extent: (u32, u32),
    /// How the frame uses it.
    pub usage: Usage,
    /// Index into [`Plan::passes`] of the pass that writes it (kept resources only).
    pub first_use: usize,
    /// Index into [`Plan::passes`] of the last pass that reads it (kept resources only).
    pub last_use: usize,
    /// Physical allocation (kept resources only).
    pub slot: Option<usize>,
    /// A constant texture (an unconnected input's fallback value): filled once, never written.
    pub constant: Option<[f32; 4]>,
    /// A history resource (`LayerDesc::history`): the resource whose previous frame it holds.
    pub history_of: Option<ResourceId>,
    /// Lives from frame to frame: a used history resource or the resource it is the history
    /// of. Never shares its slot.
    pub persistent: bool,
}

impl PlannedResource {
    /// A resource not yet used by any pass.
    pub(crate) fn new(name: String, decl: ResourceDecl, extent: (u32, u32)) -> Self {
        Self { name, decl, extent, usage: Usage::default(), first_use: 0, last_use: 0, slot: None, constant: None, history_of: None, persistent: false }
    }

    /// Bytes of GPU memory it needs (0 for the acceleration structure, which its cache owns).
    pub fn bytes(&self) -> u64 {
        match &self.decl {
            ResourceDecl::Texture(t) => self.extent.0 as u64 * self.extent.1 as u64 * t.format.bytes_per_texel() * t.layers as u64,
            ResourceDecl::Buffer(b) => b.size,
            // Owned by the acceleration-structure cache, not a transient of the frame.
            ResourceDecl::Accel => 0,
        }
    }
}

/// How a resource is used over the frame (decides wgpu usage flags).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Usage {
    /// Read through a sampled texture binding.
    pub sampled: bool,
    /// Bound as a storage texture or buffer.
    pub storage: bool,
    /// A render pass's colour or depth attachment.
    pub attachment: bool,
    /// Copied out (the graph's output).
    pub copy_src: bool,
}

impl Usage {
    pub(super) fn union(self, o: Usage) -> Usage {
        Usage {
            sampled: self.sampled || o.sampled,
            storage: self.storage || o.storage,
            attachment: self.attachment || o.attachment,
            copy_src: self.copy_src || o.copy_src,
        }
    }
}

/// A physical texture or buffer shared by resources whose lifetimes do not overlap.
#[derive(Debug, Clone)]
pub struct Slot {
    /// The declaration every member shares (format or size).
    pub decl: ResourceDecl,
    /// Texture size.
    pub extent: (u32, u32),
    /// The union of its members' usages.
    pub usage: Usage,
    /// Bytes of GPU memory.
    pub bytes: u64,
    /// The resources that live in it, one after the other.
    pub members: Vec<ResourceId>,
    /// A constant (fallback) texture's value, written once when the slot is created.
    pub constant: Option<[f32; 4]>,
}

/// A kept pass, in execution order.
#[derive(Debug, Clone)]
pub struct PlannedPass {
    /// `"node/pass"`.
    pub name: String,
    /// The graph node it belongs to.
    pub node: String,
    /// What kind of GPU work it is.
    pub kind: PassKind,
    /// The reflected shader (empty for passes without one).
    pub shader: Arc<ShaderInfo>,
    /// Entry point: compute or fragment entry; a Rust pass's registered name.
    pub entry: String,
    /// Vertex entry of render passes.
    pub vertex_entry: String,
    /// (name the shader binds it by, resource)
    pub reads: Vec<(String, ResourceId)>,
    /// (name the shader writes it by, resource)
    pub writes: Vec<(String, ResourceId)>,
    /// How a compute or trace pass's workgroups cover the frame.
    pub dispatch: Dispatch,
    /// `SceneRaster`: whether the pipeline culls back faces (`PassDesc::cull_back_faces`).
    pub cull_back_faces: bool,
    /// `SceneRaster` with a shadow slot: back faces of closed meshes culled where the slot's
    /// light is outside them (`PassDesc::cull_closed_back_faces`).
    pub cull_closed_back_faces: bool,
    /// `SceneRaster`: the shadow-map slot the pass draws (`PassDesc::shadow_slot`).
    pub shadow_slot: Option<u32>,
    /// `SceneRaster` with a shadow slot: the (columns, rows) of slots it draws side by side
    /// (`PassDesc::shadow_tiles`).
    pub shadow_tiles: Option<(u32, u32)>,
    /// Render passes: the array layer of layered attachments drawn into (`PassDesc::layer`).
    pub layer: Option<u32>,
    /// `SceneRaster`: BLEND instances are not drawn (`PassDesc::skip_blend`).
    pub skip_blend: bool,
    /// `SceneRaster`: only translucent instances, back to front, blended (`PassDesc::translucent`).
    pub translucent: bool,
    /// The frames the pass is recorded in (`PassDesc::runs_when`), with the resource holding
    /// the count; `None`: every frame.
    pub runs_when: Option<(RunsWhen, ResourceId)>,
    /// `AccelBuild`: the settings of its `Accel` node.
    pub accel: Option<AccelNode>,
    /// Parameter values after graph overrides.
    pub params: BTreeMap<String, (ParamDecl, ParamValue)>,
    /// Where the pass is declared (its layer file).
    pub location: Location,
}

/// The executable result of compiling a graph for one frame size. Code outside the crate
/// reads it through the accessors below.
#[derive(Debug, Clone)]
pub struct Plan {
    pub(crate) graph_file: PathBuf,
    pub(crate) frame_size: (u32, u32),
    pub(crate) passes: Vec<PlannedPass>,
    /// Names of passes whose outputs never reach the graph output.
    pub(crate) culled: Vec<String>,
    pub(crate) resources: Vec<PlannedResource>,
    pub(crate) slots: Vec<Slot>,
    pub(crate) output: ResourceId,
    /// The linear HDR image the graph names (`hdr_output`), if any and switched on.
    pub(crate) hdr_output: Option<ResourceId>,
    /// Which parts of the scene the kept passes draw or read.
    pub(crate) scene_usage: SceneUsage,
    /// The back-end trace passes were compiled for.
    pub(crate) backend: Backend,
}

impl PlannedPass {
    /// The shadow-map slots the pass draws, in tile order: `shadow_slot` and the slots after
    /// it that its `shadow_tiles` hold (none without a slot).
    pub fn shadow_slots(&self) -> std::ops::Range<u32> {
        let tiles = self.shadow_tiles.map_or(1, |(columns, rows)| columns * rows);
        self.shadow_slot.map_or(0..0, |slot| slot..slot + tiles)
    }

    /// The tiles of the pass's attachments, (columns, rows): (1, 1) without `shadow_tiles`.
    pub fn tile_grid(&self) -> (u32, u32) {
        self.shadow_tiles.unwrap_or((1, 1))
    }
}

impl Plan {
    /// The graph file the plan was compiled from.
    pub fn graph_file(&self) -> &Path {
        &self.graph_file
    }

    /// The frame size (width, height) the plan's texture sizes are resolved for.
    pub fn frame_size(&self) -> (u32, u32) {
        self.frame_size
    }

    /// The kept passes, in execution order.
    pub fn passes(&self) -> &[PlannedPass] {
        &self.passes
    }

    /// Names (`node/pass`) of the passes whose outputs never reach the graph output.
    pub fn culled(&self) -> &[String] {
        &self.culled
    }

    /// Every resource of the graph, kept or not; a [`ResourceId`] indexes it.
    pub fn resources(&self) -> &[PlannedResource] {
        &self.resources
    }

    /// The physical allocations, each shared by the resources listed in its `members`.
    pub fn slots(&self) -> &[Slot] {
        &self.slots
    }

    /// The resource the graph presents (its `output`).
    pub fn output(&self) -> ResourceId {
        self.output
    }

    /// The graph's linear, scene-referred HDR image (its `hdr_output`, a float colour texture
    /// that lives to the end of the frame), if it names one whose node is switched on.
    pub fn hdr_output(&self) -> Option<ResourceId> {
        self.hdr_output
    }

    /// Which parts of the scene the kept passes draw or read; only these are uploaded.
    pub fn scene_usage(&self) -> SceneUsage {
        self.scene_usage
    }

    /// The back-end trace passes were compiled for.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// Whether resource `r` is used by a kept pass (and so has a slot).
    pub fn is_kept(&self, r: ResourceId) -> bool {
        self.resources[r].slot.is_some()
    }

    /// Bytes of transient memory if every kept resource had its own allocation.
    pub fn bytes_without_reuse(&self) -> u64 {
        self.resources.iter().filter(|r| r.slot.is_some()).map(|r| r.bytes()).sum()
    }

    /// Bytes actually allocated, with reuse of non-overlapping identical resources.
    pub fn bytes_with_reuse(&self) -> u64 {
        self.slots.iter().map(|s| s.bytes).sum()
    }

    /// Whether the plan keeps any texture from frame to frame (a history resource).
    #[cfg(feature = "cli")]
    pub(crate) fn has_history(&self) -> bool {
        self.resources.iter().any(|r| r.history_of.is_some())
    }

    /// The resource named `name` (`"node.output"`, `"node/transient"`).
    pub fn resource_by_name(&self, name: &str) -> Option<ResourceId> {
        self.resources.iter().position(|r| r.name == name)
    }

    /// A human-readable report of the plan.
    pub fn report(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "graph {} at {}x{}", self.graph_file.display(), self.frame_size.0, self.frame_size.1);
        let _ = writeln!(s, "passes kept ({}), in execution order:", self.passes.len());
        for (i, p) in self.passes.iter().enumerate() {
            let reads: Vec<&str> = p.reads.iter().map(|(_, r)| self.resources[*r].name.as_str()).collect();
            let writes: Vec<&str> = p.writes.iter().map(|(_, r)| self.resources[*r].name.as_str()).collect();
            let runs_when = p.runs_when.as_ref().map_or(String::new(), |(condition, r)| {
                let comparison = if matches!(condition, RunsWhen::Below { .. }) { "below" } else { "at least" };
                format!("  runs when {} of the frame before is {comparison} {} x its whole", self.resources[*r].name, condition.fraction())
            });
            let _ = writeln!(
                s,
                "  {i:>2}. {:<28} {:<12} {}  reads [{}] writes [{}]{runs_when}",
                p.name,
                p.kind.name(),
                p.shader.path.display(),
                reads.join(", "),
                writes.join(", ")
            );
        }
        let _ = writeln!(s, "passes culled ({}): {}", self.culled.len(), if self.culled.is_empty() { "none".to_string() } else { self.culled.join(", ") });
        let _ = writeln!(s, "resources:");
        for r in &self.resources {
            let what = match &r.decl {
                ResourceDecl::Texture(t) if t.layers > 1 => format!("{} {}x{}x{}", t.format, r.extent.0, r.extent.1, t.layers),
                ResourceDecl::Texture(t) => format!("{} {}x{}", t.format, r.extent.0, r.extent.1),
                ResourceDecl::Buffer(b) => format!("buffer {} B", b.size),
                ResourceDecl::Accel => "acceleration structure".to_string(),
            };
            let history = match (r.history_of, r.persistent) {
                (Some(source), _) => format!("  history: the previous frame of {}", self.resources[source].name),
                (None, true) => "  kept for the next frame".to_string(),
                (None, false) => String::new(),
            };
            match r.slot {
                Some(slot) => {
                    let _ = writeln!(s, "  {:<28} {:<26} live passes {}..={}  slot {}{history}", r.name, what, r.first_use, r.last_use, slot);
                }
                None => {
                    let _ = writeln!(s, "  {:<28} {:<26} not allocated (unused)", r.name, what);
                }
            }
        }
        let _ = writeln!(
            s,
            "transient memory: {} with reuse, {} without ({} slots for {} resources)",
            fmt_bytes(self.bytes_with_reuse()),
            fmt_bytes(self.bytes_without_reuse()),
            self.slots.len(),
            self.resources.iter().filter(|r| r.slot.is_some()).count()
        );
        let _ = writeln!(s, "scene on GPU: {}", self.scene_usage.describe());
        s
    }
}

/// `b` bytes as B, KiB or MiB with two decimals (the plan report and the pass table).
pub fn fmt_bytes(b: u64) -> String {
    if b >= 1 << 20 {
        format!("{:.2} MiB", b as f64 / (1u64 << 20) as f64)
    } else if b >= 1 << 10 {
        format!("{:.1} KiB", b as f64 / 1024.0)
    } else {
        format!("{b} B")
    }
}
