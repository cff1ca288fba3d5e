//! The graph compiler. Its phases read top to bottom in [`compile`]:
//! parse -> resolve layers -> build the petgraph graph -> validate -> cull -> schedule ->
//! shader interface check -> resource lifetimes -> allocation with reuse -> plan.

use super::builtins;
use super::desc::*;
use super::reflect::{self, BindingKind, ShaderInfo};
use crate::backend::Backend;
use crate::error::{ErrorKind, GraphError, Location};
use crate::scene::gpu::SceneUsage;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::Direction;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where layer files and shaders are found.
#[derive(Debug, Clone)]
pub struct Project {
    /// Directory holding `<layer>.ron` files.
    pub layers_dir: PathBuf,
    /// Directory that shader paths in layer files are relative to.
    pub shaders_dir: PathBuf,
}

impl Project {
    /// The layout of this repository: `graph/`, `layers/` and `shaders/` side by side. A file
    /// missing there is read from the built-in copy ([`super::files`]).
    pub fn beside_graph(graph_file: &Path) -> Self {
        let root = graph_file.parent().and_then(|p| p.parent()).unwrap_or(Path::new("."));
        let root = if root.as_os_str().is_empty() { Path::new(".") } else { root };
        Self { layers_dir: root.join("layers"), shaders_dir: root.join("shaders") }
    }
}

pub type ResourceId = usize;

/// A resource of the compiled graph.
#[derive(Debug, Clone)]
pub struct PlannedResource {
    /// `"node.output"` for layer outputs, `"node/name"` for transients.
    pub name: String,
    pub decl: ResourceDecl,
    /// Resolved texture size (textures only).
    pub extent: (u32, u32),
    pub usage: Usage,
    /// Index into [`Plan::passes`] of the pass that writes it (kept resources only).
    pub first_use: usize,
    pub last_use: usize,
    /// Physical allocation (kept resources only).
    pub slot: Option<usize>,
    /// A constant texture (an unconnected input's fallback value): filled once, never written.
    pub constant: Option<[f32; 4]>,
}

impl PlannedResource {
    pub fn bytes(&self) -> u64 {
        match &self.decl {
            ResourceDecl::Texture(t) => self.extent.0 as u64 * self.extent.1 as u64 * t.format.bytes_per_texel(),
            ResourceDecl::Buffer(b) => b.size,
            // Owned by the acceleration-structure cache, not a transient of the frame.
            ResourceDecl::Accel => 0,
        }
    }
}

/// How a resource is used over the frame (decides wgpu usage flags).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Usage {
    pub sampled: bool,
    pub storage: bool,
    pub attachment: bool,
    pub copy_src: bool,
}

impl Usage {
    fn union(self, o: Usage) -> Usage {
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
    pub decl: ResourceDecl,
    pub extent: (u32, u32),
    pub usage: Usage,
    pub bytes: u64,
    pub members: Vec<ResourceId>,
    /// A constant (fallback) texture's value, written once when the slot is created.
    pub constant: Option<[f32; 4]>,
}

/// A kept pass, in execution order.
#[derive(Debug, Clone)]
pub struct PlannedPass {
    /// `"node/pass"`.
    pub name: String,
    pub node: String,
    pub kind: PassKind,
    pub shader: Arc<ShaderInfo>,
    pub entry: String,
    pub vertex_entry: String,
    /// (name the shader binds it by, resource)
    pub reads: Vec<(String, ResourceId)>,
    pub writes: Vec<(String, ResourceId)>,
    pub dispatch: Dispatch,
    /// `SceneRaster`: whether the pipeline culls back faces (`PassDesc::cull_back_faces`).
    pub cull_back_faces: bool,
    /// `SceneRaster`: the shadow-map slot the pass draws (`PassDesc::shadow_slot`).
    pub shadow_slot: Option<u32>,
    /// `AccelBuild`: the settings of its `Accel` node.
    pub accel: Option<AccelNode>,
    /// Parameter values after graph overrides.
    pub params: BTreeMap<String, (ParamDecl, ParamValue)>,
    pub location: Location,
}

/// The executable result of compiling a graph for one frame size.
#[derive(Debug, Clone)]
pub struct Plan {
    pub graph_file: PathBuf,
    pub frame_size: (u32, u32),
    pub passes: Vec<PlannedPass>,
    /// Names of passes whose outputs never reach the graph output.
    pub culled: Vec<String>,
    pub resources: Vec<PlannedResource>,
    pub slots: Vec<Slot>,
    pub output: ResourceId,
    /// Which parts of the scene the kept passes draw or read.
    pub scene_usage: SceneUsage,
    /// The back-end trace passes were compiled for.
    pub backend: Backend,
}

impl Plan {
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
            let _ = writeln!(
                s,
                "  {i:>2}. {:<28} {:<12} {}  reads [{}] writes [{}]",
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
                ResourceDecl::Texture(t) => format!("{} {}x{}", t.format, r.extent.0, r.extent.1),
                ResourceDecl::Buffer(b) => format!("buffer {} B", b.size),
                ResourceDecl::Accel => "acceleration structure".to_string(),
            };
            match r.slot {
                Some(slot) => {
                    let _ = writeln!(s, "  {:<28} {:<26} live passes {}..={}  slot {}", r.name, what, r.first_use, r.last_use, slot);
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

pub fn fmt_bytes(b: u64) -> String {
    if b >= 1 << 20 {
        format!("{:.2} MiB", b as f64 / (1u64 << 20) as f64)
    } else if b >= 1 << 10 {
        format!("{:.1} KiB", b as f64 / 1024.0)
    } else {
        format!("{b} B")
    }
}

/// Text of a file with helpers to find where a name is written.
#[derive(Clone)]
struct SourceText {
    path: PathBuf,
    text: String,
    /// `text` with its comments blanked (same byte offsets): what `locate` searches.
    code: String,
}

impl SourceText {
    /// Location of the last anchor, each searched after the previous one; falls back to the
    /// last anchor found (or the file start).
    fn locate(&self, anchors: &[&str]) -> Location {
        let mut pos = 0usize;
        let mut found = 0usize;
        for a in anchors {
            if let Some(p) = self.code[pos..].find(a) {
                found = pos + p;
                pos = found + a.len();
            }
        }
        Location::at_offset(&self.path, &self.text, found)
    }

    fn quoted(s: &str) -> String {
        format!("\"{s}\"")
    }
}

/// `text` with every `//` and `/* */` comment (nested ones too, as RON allows) made spaces,
/// byte for byte, so that a name in a comment is never where an error points; string contents
/// are kept.
fn blank_comments(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = bytes.to_vec();
    let (mut i, mut in_string, mut depth) = (0usize, false, 0usize);
    while i < bytes.len() {
        let pair = (bytes[i], bytes.get(i + 1).copied().unwrap_or(0));
        let width = if depth > 0 {
            match pair {
                (b'*', b'/') => depth -= 1,
                (b'/', b'*') => depth += 1,
                _ => {}
            }
            let width = if matches!(pair, (b'*', b'/') | (b'/', b'*')) { 2 } else { 1 };
            out[i..i + width].iter_mut().filter(|b| **b != b'\n').for_each(|b| *b = b' ');
            width
        } else if in_string {
            in_string = bytes[i] != b'"';
            if bytes[i] == b'\\' {
                2
            } else {
                1
            }
        } else {
            match pair {
                (b'/', b'/') => {
                    let end = text[i..].find('\n').map_or(bytes.len(), |e| i + e);
                    out[i..end].fill(b' ');
                    end - i
                }
                (b'/', b'*') => {
                    depth = 1;
                    out[i..i + 2].fill(b' ');
                    2
                }
                _ => {
                    in_string = bytes[i] == b'"';
                    1
                }
            }
        };
        i += width;
    }
    // Whole characters were replaced, each byte by an ASCII space: still UTF-8.
    String::from_utf8(out).unwrap_or_else(|_| text.to_string())
}

fn read_file(path: &Path, from: Option<Location>) -> Result<SourceText, GraphError> {
    match super::files::read(path) {
        Ok(f) => Ok(SourceText { path: f.path, code: blank_comments(&f.text), text: f.text }),
        Err(e) => Err(GraphError::new(ErrorKind::Io, from.unwrap_or_else(|| Location::file_start(path)), format!("cannot read {}: {e}", path.display()))),
    }
}

fn parse_ron<T: serde::de::DeserializeOwned>(src: &SourceText, what: &str) -> Result<T, GraphError> {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES).from_str::<T>(&src.text).map_err(|e| {
        GraphError::new(ErrorKind::Syntax, Location::new(&src.path, e.position.line as u32, e.position.col as u32), format!("invalid {what} file: {}", e.code))
            .help(format!("see docs/ARCHITECTURE.md for the {what} file format"))
    })
}

/// Phase 1: parse a graph file.
pub fn parse_graph(path: &Path) -> Result<GraphDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "graph")
}

/// Phase 1 for layers: parse a layer file.
pub fn parse_layer(path: &Path) -> Result<LayerDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "layer")
}

struct ResolvedNode {
    name: String,
    layer_name: String,
    layer: LayerDesc,
    layer_src: SourceText,
    params: BTreeMap<String, (ParamDecl, ParamValue)>,
    /// local name -> resource id (filled in phase 3)
    locals: HashMap<String, ResourceId>,
    /// An `Accel` node's settings.
    accel: Option<AccelNode>,
}

#[derive(Debug, Clone, Copy)]
enum Vertex {
    Pass(usize),
    Resource(ResourceId),
}

struct PassNode {
    node: usize,
    index: usize,
    reads: Vec<(String, ResourceId)>,
    writes: Vec<(String, ResourceId)>,
    location: Location,
}

/// Compiles a graph file into an executable plan for a frame of `frame_size`.
pub fn compile(graph_file: &Path, project: &Project, frame_size: (u32, u32)) -> Result<Plan, GraphError> {
    compile_with(graph_file, project, frame_size, &CompileOptions::default())
}

/// Compiler switches.
#[derive(Debug, Clone)]
pub struct CompileOptions {
    /// Let identical resources with disjoint lifetimes share memory.
    pub reuse: bool,
    /// Include substitutions of the device (see [`reflect::IncludeAliases`]).
    pub includes: reflect::IncludeAliases,
    /// The traversal back-end trace passes are compiled for: `trace/trace.wgsl` becomes its
    /// module.
    pub backend: Backend,
    /// Parameter values that override the graph file's, as `("node", "param") -> value`
    /// (benches, the viewer); checked like the file's own.
    pub params: BTreeMap<(String, String), ParamValue>,
    /// Layer nodes switched on (`true`) or off (`false`) over the graph file's `enabled`
    /// (the viewer's effect switches).
    pub enabled: BTreeMap<String, bool>,
}

impl Default for CompileOptions {
    fn default() -> Self {
        Self { reuse: true, includes: reflect::IncludeAliases::new(), backend: Backend::Compute, params: BTreeMap::new(), enabled: BTreeMap::new() }
    }
}

impl CompileOptions {
    /// The include substitutions in effect: the device's, plus the back-end's trace module.
    pub fn all_includes(&self) -> reflect::IncludeAliases {
        let mut a = self.includes.clone();
        // `trace/trace.wgsl` itself includes the compute back-end, the default.
        if self.backend != Backend::Compute {
            a.insert(TRACE_INCLUDE.into(), self.backend.trace_module().into());
        }
        a
    }
}

/// The include every trace pass uses; the back-end substitutes its module for it.
pub const TRACE_INCLUDE: &str = "trace/trace.wgsl";

/// [`compile`] with explicit options.
pub fn compile_with(graph_file: &Path, project: &Project, frame_size: (u32, u32), options: &CompileOptions) -> Result<Plan, GraphError> {
    // Phase 1: parse.
    let gsrc = read_file(graph_file, None)?;
    let mut graph: GraphDesc = parse_ron(&gsrc, "graph")?;
    for (node, on) in &options.enabled {
        match graph.nodes.get_mut(node) {
            Some(NodeDesc::Layer(l)) => l.enabled = *on,
            _ => {
                return Err(GraphError::new(
                    ErrorKind::UnknownLayer,
                    Location::file_start(graph_file),
                    format!("a switch names node `{node}`, which is not a layer node of the graph"),
                ))
            }
        }
    }

    // Phase 2: resolve layers and parameters.
    let mut nodes = resolve_layers(&graph, &gsrc, project)?;
    for ((node, param), value) in &options.params {
        let loc = Location::file_start(graph_file);
        let n = nodes.iter_mut().find(|n| &n.name == node).ok_or_else(|| {
            GraphError::new(
                ErrorKind::UnknownLayer,
                loc.clone(),
                format!("a parameter override names node `{node}`, which the graph does not have (or has switched off)"),
            )
        })?;
        let decl = n
            .params
            .get(param)
            .map(|(d, _)| d.clone())
            .ok_or_else(|| GraphError::new(ErrorKind::UnknownParam, loc.clone(), format!("node `{node}` has no parameter `{param}`")))?;
        let checked = check_param(&decl, *value)
            .map_err(|(kind, msg, help)| GraphError::new(kind, loc.clone(), format!("override of `{node}.{param}`: {msg}")).help(help))?;
        n.params.insert(param.clone(), (decl, checked));
    }

    // Phase 3: build the petgraph graph of passes and resources.
    let mut resources: Vec<PlannedResource> = Vec::new();
    let mut producers: HashMap<ResourceId, usize> = HashMap::new();
    declare_resources(&mut nodes, &mut resources, frame_size);
    connect_inputs(&graph, &gsrc, &mut nodes, &mut resources)?;
    let passes = collect_passes(&nodes, &resources, &mut producers)?;

    let mut g: DiGraph<Vertex, ()> = DiGraph::new();
    let res_vertex: Vec<NodeIndex> = (0..resources.len()).map(|r| g.add_node(Vertex::Resource(r))).collect();
    let pass_vertex: Vec<NodeIndex> = (0..passes.len()).map(|p| g.add_node(Vertex::Pass(p))).collect();
    for (pi, p) in passes.iter().enumerate() {
        for (_, r) in &p.reads {
            g.add_edge(res_vertex[*r], pass_vertex[pi], ());
        }
        for (_, r) in &p.writes {
            g.add_edge(pass_vertex[pi], res_vertex[*r], ());
        }
    }

    // Phase 4: validate: every read has a producer, no cycles, output exists.
    for p in &passes {
        for (local, r) in &p.reads {
            if !producers.contains_key(r) && resources[*r].constant.is_none() {
                let node = &nodes[p.node];
                let pass = &node.layer.passes[p.index];
                return Err(GraphError::new(
                    ErrorKind::NoProducer,
                    p.location.clone(),
                    format!("pass `{}` of layer `{}` reads `{local}` ({}), but no pass writes it", pass.name, node.layer_name, resources[*r].name),
                )
                .help(format!("add `{local}` to the `writes` of a pass that produces it, or remove it from `reads`")));
            }
        }
    }
    let topo = petgraph::algo::toposort(&g, None).map_err(|cycle| cycle_error(&g, cycle.node_id(), &gsrc, &nodes, &passes, &resources))?;
    let (output_node, output_name) = split_ref(&graph.output);
    let output_loc = gsrc.locate(&["output", &SourceText::quoted(&graph.output)]);
    let output = nodes
        .iter()
        .find(|n| n.name == output_node)
        .and_then(|n| n.layer.outputs.get(output_name).and(n.locals.get(output_name)))
        .copied()
        .ok_or_else(|| unknown_output(&graph.output, output_loc.clone(), &nodes))?;
    if !producers.contains_key(&output) {
        return Err(GraphError::new(ErrorKind::NoProducer, output_loc, format!("graph output `{}` is never written", graph.output))
            .help("write the output in one of the layer's passes"));
    }
    match &resources[output].decl {
        ResourceDecl::Texture(t) if matches!(t.format, Format::Rgba8Unorm | Format::Rgba8UnormSrgb) => {}
        other => {
            return Err(GraphError::new(
                ErrorKind::Unsupported,
                output_loc,
                format!("graph output `{}` is `{other}`; the output must be an Rgba8Unorm or Rgba8UnormSrgb texture", graph.output),
            )
            .help("add a tone-map layer that writes an Rgba8UnormSrgb texture and make it the output"))
        }
    }

    // Phase 5: cull passes that do not reach the output.
    let mut reaches = vec![false; g.node_count()];
    let mut stack = vec![res_vertex[output]];
    while let Some(v) = stack.pop() {
        if std::mem::replace(&mut reaches[v.index()], true) {
            continue;
        }
        stack.extend(g.neighbors_directed(v, Direction::Incoming));
    }

    // Phase 6: schedule (topological order of kept passes).
    let schedule: Vec<usize> = topo
        .iter()
        .filter_map(|v| match g[*v] {
            Vertex::Pass(p) if reaches[v.index()] => Some(p),
            _ => None,
        })
        .collect();
    let culled: Vec<String> = (0..passes.len()).filter(|p| !reaches[pass_vertex[*p].index()]).map(|p| pass_name(&nodes, &passes[p])).collect();

    // Phase 7: shader interface check (every pass, kept or culled: a broken file is an error).
    let includes = options.all_includes();
    let mut shader_cache: HashMap<PathBuf, Arc<ShaderInfo>> = HashMap::new();
    let mut shaders: Vec<Arc<ShaderInfo>> = Vec::new();
    for p in &passes {
        let node = &nodes[p.node];
        let pass = &node.layer.passes[p.index];
        // Passes without a shader: the `Accel` node's build, and Rust passes (their resources
        // are the ones the layer file declares).
        if matches!(pass.kind, PassKind::AccelBuild | PassKind::Rust) {
            shaders.push(Arc::new(ShaderInfo::none()));
            continue;
        }
        let path = project.shaders_dir.join(&pass.shader);
        let shader_loc = node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name), "shader"]);
        let info = match shader_cache.get(&path) {
            Some(info) => info.clone(),
            None => {
                let info = Arc::new(reflect::reflect_with(&path, &project.shaders_dir, &shader_loc, &includes)?);
                shader_cache.insert(path.clone(), info.clone());
                info
            }
        };
        check_interface(node, pass, p, &info, &resources)?;
        shaders.push(info);
    }

    // Phase 8: resource lifetimes and usage, in schedule order.
    let mut planned: Vec<PlannedPass> = Vec::new();
    let mut first: HashMap<ResourceId, usize> = HashMap::new();
    let mut last: HashMap<ResourceId, usize> = HashMap::new();
    let mut scene_usage = SceneUsage::default();
    for (order, &pi) in schedule.iter().enumerate() {
        let p = &passes[pi];
        let node = &nodes[p.node];
        let pass = &node.layer.passes[p.index];
        for (_, r) in p.reads.iter().chain(&p.writes) {
            first.entry(*r).or_insert(order);
            last.insert(*r, order);
        }
        for (_, r) in &p.reads {
            resources[*r].usage.sampled = true;
            if matches!(resources[*r].decl, ResourceDecl::Buffer(_)) {
                resources[*r].usage.storage = true;
            }
        }
        for (_, r) in &p.writes {
            match pass.kind {
                PassKind::Compute | PassKind::Trace => resources[*r].usage.storage = true,
                PassKind::AccelBuild => {}
                _ => resources[*r].usage.attachment = true,
            }
        }
        let shader = shaders[pi].clone();
        scene_usage.geometry |= pass.kind == PassKind::SceneRaster;
        for b in &shader.bindings {
            scene_usage.add_binding(b);
        }
        planned.push(PlannedPass {
            name: pass_name(&nodes, p),
            node: node.name.clone(),
            kind: pass.kind,
            entry: entry_name(pass),
            vertex_entry: pass.vertex_entry.clone().unwrap_or_else(|| "vs_main".into()),
            shader,
            reads: p.reads.clone(),
            writes: p.writes.clone(),
            dispatch: pass.dispatch,
            cull_back_faces: pass.cull_back_faces,
            shadow_slot: pass.shadow_slot,
            accel: node.accel.clone(),
            params: node.params.clone(),
            location: p.location.clone(),
        });
    }
    resources[output].usage.copy_src = true;
    last.insert(output, planned.len().saturating_sub(1));
    for (r, res) in resources.iter_mut().enumerate() {
        if let (Some(f), Some(l)) = (first.get(&r), last.get(&r)) {
            res.first_use = *f;
            res.last_use = *l;
        }
    }

    // Phase 9: allocation. Identical resources (same type, format and size) whose lifetimes do
    // not overlap share a slot; resources nobody uses get none.
    let mut slots: Vec<Slot> = Vec::new();
    let mut order: Vec<ResourceId> = (0..resources.len()).filter(|r| first.contains_key(r)).collect();
    order.sort_by_key(|r| (resources[*r].first_use, *r));
    for r in order {
        let res = &resources[r];
        let fits = slots.iter().position(|s| {
            options.reuse
                && res.constant.is_none()
                && s.constant.is_none()
                && same_shape(&s.decl, &res.decl)
                && s.extent == res.extent
                && s.members.iter().all(|m| resources[*m].last_use < res.first_use || res.last_use < resources[*m].first_use)
        });
        let slot = match fits {
            Some(s) => s,
            None => {
                slots.push(Slot {
                    decl: res.decl.clone(),
                    extent: res.extent,
                    usage: Usage::default(),
                    bytes: res.bytes(),
                    members: Vec::new(),
                    constant: res.constant,
                });
                slots.len() - 1
            }
        };
        slots[slot].members.push(r);
        slots[slot].usage = slots[slot].usage.union(res.usage);
        resources[r].slot = Some(slot);
    }

    // Phase 10: the plan.
    Ok(Plan { graph_file: graph_file.to_path_buf(), frame_size, passes: planned, culled, resources, slots, output, scene_usage, backend: options.backend })
}

/// The cycle through `start` as graph node names, `a -> b -> a`, pointing at the first node.
fn cycle_error(
    g: &DiGraph<Vertex, ()>,
    start: NodeIndex,
    gsrc: &SourceText,
    nodes: &[ResolvedNode],
    passes: &[PassNode],
    resources: &[PlannedResource],
) -> GraphError {
    let node_of = |v: NodeIndex| match g[v] {
        Vertex::Pass(p) => nodes[passes[p].node].name.clone(),
        Vertex::Resource(r) => resources[r].name.split(['.', '/']).next().unwrap_or_default().to_string(),
    };
    let mut names: Vec<String> = Vec::new();
    for v in shortest_cycle(g, start) {
        let name = node_of(v);
        if names.last() != Some(&name) {
            names.push(name);
        }
    }
    if names.len() > 1 && names.first() == names.last() {
        names.pop();
    }
    let first = names.first().cloned().unwrap_or_else(|| node_of(start));
    let path: Vec<&str> = names.iter().chain(std::iter::once(&first)).map(|s| s.as_str()).collect();
    let loc = gsrc.locate(&["nodes", &SourceText::quoted(&first)]);
    GraphError::new(ErrorKind::Cycle, loc, format!("the graph has a cycle: {}", path.join(" -> ")))
        .help("a node's inputs must not depend on its own outputs; break the loop by removing one connection")
}

/// The vertices of a shortest cycle through `start` (breadth-first), `start` first and not repeated.
fn shortest_cycle(g: &DiGraph<Vertex, ()>, start: NodeIndex) -> Vec<NodeIndex> {
    let mut parent: HashMap<NodeIndex, NodeIndex> = HashMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for w in g.neighbors_directed(v, Direction::Outgoing) {
            if w == start {
                let mut path = vec![v];
                let mut at = v;
                while let Some(&p) = parent.get(&at) {
                    path.push(p);
                    at = p;
                }
                path.reverse();
                return path;
            }
            if let std::collections::hash_map::Entry::Vacant(e) = parent.entry(w) {
                e.insert(v);
                queue.push_back(w);
            }
        }
    }
    vec![start]
}

fn same_shape(a: &ResourceDecl, b: &ResourceDecl) -> bool {
    match (a, b) {
        (ResourceDecl::Texture(x), ResourceDecl::Texture(y)) => x.format == y.format,
        (ResourceDecl::Buffer(x), ResourceDecl::Buffer(y)) => x.size == y.size,
        // One acceleration structure per Accel node: never shared.
        _ => false,
    }
}

fn entry_name(pass: &PassDesc) -> String {
    pass.entry.clone().unwrap_or_else(|| match pass.kind {
        PassKind::Compute | PassKind::Trace => "cs_main".into(),
        // A Rust pass has no default: the executor reports one that names none.
        PassKind::Rust => String::new(),
        _ => "fs_main".into(),
    })
}

fn pass_name(nodes: &[ResolvedNode], p: &PassNode) -> String {
    format!("{}/{}", nodes[p.node].name, nodes[p.node].layer.passes[p.index].name)
}

fn split_ref(s: &str) -> (&str, &str) {
    s.split_once('.').unwrap_or((s, ""))
}

fn unknown_output(reference: &str, loc: Location, nodes: &[ResolvedNode]) -> GraphError {
    let (node, output) = split_ref(reference);
    match nodes.iter().find(|n| n.name == node) {
        None => {
            let names: Vec<&str> = nodes.iter().map(|n| n.name.as_str()).collect();
            GraphError::new(ErrorKind::UnknownOutput, loc, format!("`{reference}` names node `{node}`, which the graph does not have"))
                .help(format!("write \"node.output\" with one of the nodes: {}", names.join(", ")))
        }
        Some(n) => {
            let outs: Vec<&str> = n.layer.outputs.keys().map(|s| s.as_str()).collect();
            GraphError::new(ErrorKind::UnknownOutput, loc, format!("node `{node}` (layer `{}`) has no output `{output}`", n.layer_name))
                .help(format!("its outputs are: {}", outs.join(", ")))
        }
    }
}

fn resolve_layers(graph: &GraphDesc, gsrc: &SourceText, project: &Project) -> Result<Vec<ResolvedNode>, GraphError> {
    check_one_accel(graph, gsrc)?;
    let mut out = Vec::new();
    for (name, node) in &graph.nodes {
        let ln = match node {
            NodeDesc::Layer(ln) if !ln.enabled => continue,
            NodeDesc::Layer(ln) => ln,
            NodeDesc::Accel(accel) => {
                out.push(accel_node(name, accel, gsrc));
                continue;
            }
        };
        let node_anchor = SourceText::quoted(name);
        let path = project.layers_dir.join(format!("{}.ron", ln.layer));
        if !super::files::exists(&path) {
            let loc = gsrc.locate(&["nodes", &node_anchor, &SourceText::quoted(&ln.layer)]);
            let known = super::files::ron_stems(&project.layers_dir);
            return Err(GraphError::new(ErrorKind::UnknownLayer, loc, format!("unknown layer `{}`: there is no file {}", ln.layer, path.display()))
                .help(format!("use one of the layers in {}: {}", project.layers_dir.display(), known.join(", "))));
        }
        let layer_src = read_file(&path, None)?;
        let layer: LayerDesc = parse_ron(&layer_src, "layer")?;
        for (pname, decl) in &layer.params {
            if let ParamDecl::Enum { default, values } = decl {
                if !values.contains(default) {
                    let loc = layer_src.locate(&["params", &SourceText::quoted(pname)]);
                    return Err(GraphError::new(
                        ErrorKind::ParamOutOfRange,
                        loc,
                        format!("enum parameter `{pname}`: its default `{default}` is not one of its values"),
                    )
                    .help(format!("use one of: {}", values.join(", "))));
                }
            }
        }
        let mut params: BTreeMap<String, (ParamDecl, ParamValue)> = layer.params.iter().map(|(k, d)| (k.clone(), (d.clone(), d.default_value()))).collect();
        for (pname, value) in &ln.params {
            let loc = gsrc.locate(&["nodes", &node_anchor, "params", &SourceText::quoted(pname)]);
            let Some(decl) = layer.params.get(pname) else {
                let names: Vec<&str> = layer.params.keys().map(|s| s.as_str()).collect();
                return Err(GraphError::new(ErrorKind::UnknownParam, loc, format!("layer `{}` has no parameter `{pname}`", ln.layer))
                    .help(format!("its parameters are: {}", if names.is_empty() { "none".into() } else { names.join(", ") })));
            };
            let value = check_param(decl, *value)
                .map_err(|(kind, msg, help)| GraphError::new(kind, loc.clone(), format!("parameter `{pname}` of node `{name}`: {msg}")).help(help))?;
            params.insert(pname.clone(), (decl.clone(), value));
        }
        out.push(ResolvedNode { name: name.clone(), layer_name: ln.layer.clone(), layer, layer_src, params, locals: HashMap::new(), accel: None });
    }
    Ok(out)
}

/// A graph has at most one `Accel` node: the runtime keeps one acceleration-structure cache per
/// graph (one scene, one set of ray counters), so a second node's settings would be dropped.
fn check_one_accel(graph: &GraphDesc, gsrc: &SourceText) -> Result<(), GraphError> {
    let accels: Vec<&String> = graph.nodes.iter().filter(|(_, n)| matches!(n, NodeDesc::Accel(_))).map(|(name, _)| name).collect();
    if accels.len() < 2 {
        return Ok(());
    }
    let at = |name: &str| gsrc.locate(&["nodes", &SourceText::quoted(name)]);
    let names: Vec<String> = accels.iter().map(|n| format!("`{n}`")).collect();
    Err(GraphError::new(
        ErrorKind::Unsupported,
        at(accels[1]),
        format!("the graph has {} Accel nodes ({}); a graph has one acceleration structure", accels.len(), names.join(", ")),
    )
    .note(at(accels[0]), format!("the first Accel node, `{}`", accels[0]))
    .help(format!("connect every trace layer's `tlas` input to `{}` and remove the other Accel nodes", accels[0])))
}

/// The built-in acceleration-structure node: one `AccelBuild` pass writing `tlas`; its typed
/// settings travel to the runtime in `PlannedPass::accel`.
fn accel_node(name: &str, accel: &AccelNode, gsrc: &SourceText) -> ResolvedNode {
    let layer = LayerDesc {
        inputs: BTreeMap::new(),
        outputs: BTreeMap::from([("tlas".to_string(), ResourceDecl::Accel)]),
        transients: BTreeMap::new(),
        params: BTreeMap::new(),
        passes: vec![PassDesc {
            name: "build".into(),
            kind: PassKind::AccelBuild,
            shader: String::new(),
            entry: None,
            vertex_entry: None,
            reads: Vec::new(),
            writes: vec!["tlas".into()],
            dispatch: Dispatch::default(),
            cull_back_faces: true,
            shadow_slot: None,
        }],
    };
    ResolvedNode {
        name: name.to_string(),
        layer_name: "Accel".into(),
        layer,
        layer_src: gsrc.clone(),
        params: BTreeMap::new(),
        locals: HashMap::new(),
        accel: Some(accel.clone()),
    }
}

type ParamProblem = (ErrorKind, String, String);

/// Checks a value against its declaration; ints are accepted where floats are expected.
pub fn check_param(decl: &ParamDecl, value: ParamValue) -> Result<ParamValue, ParamProblem> {
    let wrong = || {
        (ErrorKind::ParamType, format!("expected {}, found {} (`{value}`)", decl.type_name(), value.type_name()), format!("write a {} value", decl.type_name()))
    };
    match (decl, value) {
        (ParamDecl::Float { min, max, .. }, ParamValue::Float(_) | ParamValue::Int(_)) => {
            let v = match value {
                ParamValue::Float(f) => f,
                ParamValue::Int(i) => i as f64,
                ParamValue::Bool(_) => unreachable!(),
            };
            if !v.is_finite() || v < *min || v > *max {
                return Err((ErrorKind::ParamOutOfRange, format!("{v} is outside the range {min}..={max}"), format!("use a value between {min} and {max}")));
            }
            Ok(ParamValue::Float(v))
        }
        (ParamDecl::Int { min, max, .. }, ParamValue::Int(v)) => {
            if v < *min || v > *max {
                return Err((ErrorKind::ParamOutOfRange, format!("{v} is outside the range {min}..={max}"), format!("use a value between {min} and {max}")));
            }
            Ok(value)
        }
        (ParamDecl::Bool { .. }, ParamValue::Bool(_)) => Ok(value),
        (ParamDecl::Enum { values, .. }, ParamValue::Int(v)) => {
            if v < 0 || v as usize >= values.len() {
                let choices: Vec<String> = values.iter().enumerate().map(|(i, n)| format!("{i} ({n})")).collect();
                return Err((ErrorKind::ParamOutOfRange, format!("{v} is not one of the choices"), format!("use the index of one of: {}", choices.join(", "))));
            }
            Ok(value)
        }
        _ => Err(wrong()),
    }
}

fn declare_resources(nodes: &mut [ResolvedNode], resources: &mut Vec<PlannedResource>, frame: (u32, u32)) {
    for node in nodes.iter_mut() {
        let decls: Vec<(String, String, ResourceDecl)> = node
            .layer
            .outputs
            .iter()
            .map(|(k, d)| (k.clone(), format!("{}.{k}", node.name), d.clone()))
            .chain(node.layer.transients.iter().map(|(k, d)| (k.clone(), format!("{}/{k}", node.name), d.clone())))
            .collect();
        for (local, name, decl) in decls {
            let extent = match &decl {
                ResourceDecl::Texture(t) => t.size.resolve(frame),
                ResourceDecl::Buffer(_) | ResourceDecl::Accel => (0, 0),
            };
            node.locals.insert(local, resources.len());
            resources.push(PlannedResource { name, decl, extent, usage: Usage::default(), first_use: 0, last_use: 0, slot: None, constant: None });
        }
    }
}

fn connect_inputs(graph: &GraphDesc, gsrc: &SourceText, nodes: &mut [ResolvedNode], resources: &mut Vec<PlannedResource>) -> Result<(), GraphError> {
    let mut unconnected: Vec<Unconnected> = Vec::new();
    for ni in 0..nodes.len() {
        let name = nodes[ni].name.clone();
        let NodeDesc::Layer(ln) = &graph.nodes[&name] else { continue };
        let node_anchor = SourceText::quoted(&name);
        for input in ln.inputs.keys() {
            if !nodes[ni].layer.inputs.contains_key(input) {
                let loc = gsrc.locate(&["nodes", &node_anchor, "inputs", &SourceText::quoted(input)]);
                let names: Vec<&str> = nodes[ni].layer.inputs.keys().map(|s| s.as_str()).collect();
                return Err(GraphError::new(ErrorKind::UnknownOutput, loc, format!("layer `{}` has no input `{input}`", nodes[ni].layer_name))
                    .help(format!("its inputs are: {}", if names.is_empty() { "none".into() } else { names.join(", ") })));
            }
        }
        let inputs: Vec<(String, ResourceDecl)> = nodes[ni].layer.inputs.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
        for (input, decl) in inputs {
            let fallback = match &decl {
                ResourceDecl::Texture(t) => t.fallback,
                _ => None,
            };
            let disabled_source = ln.inputs.get(&input).and_then(|source| {
                let (src_node, _) = split_ref(source);
                matches!(graph.nodes.get(src_node), Some(NodeDesc::Layer(l)) if !l.enabled).then(|| src_node.to_string())
            });
            if ln.inputs.get(&input).is_none() || disabled_source.is_some() {
                if let (Some(value), ResourceDecl::Texture(t)) = (fallback, &decl) {
                    // A constant 1x1 texture holding the fallback value.
                    let mut t = t.clone();
                    t.size = SizeDecl::Absolute(1, 1);
                    nodes[ni].locals.insert(input.clone(), resources.len());
                    resources.push(PlannedResource {
                        name: format!("{name}/{input} (fallback)"),
                        decl: ResourceDecl::Texture(t),
                        extent: (1, 1),
                        usage: Usage::default(),
                        first_use: 0,
                        last_use: 0,
                        slot: None,
                        constant: Some([value.0, value.1, value.2, value.3]),
                    });
                    continue;
                }
                if let Some(src) = disabled_source {
                    let loc = gsrc.locate(&["nodes", &node_anchor, "inputs", &SourceText::quoted(&input)]);
                    return Err(GraphError::new(
                        ErrorKind::NoProducer,
                        loc,
                        format!(
                            "input `{input}` of node `{name}` comes from node `{src}`, which is switched off, and layer `{}` declares no fallback for it",
                            nodes[ni].layer_name
                        ),
                    )
                    .help(format!("switch `{src}` on, or give the input a `fallback: Some((r, g, b, a))` in the layer file")));
                }
            }
            let Some(source) = ln.inputs.get(&input) else {
                unconnected.push(Unconnected {
                    location: gsrc.locate(&["nodes", &node_anchor]),
                    input,
                    node: name.clone(),
                    layer: nodes[ni].layer_name.clone(),
                });
                continue;
            };
            let loc = gsrc.locate(&["nodes", &node_anchor, "inputs", &SourceText::quoted(&input), &SourceText::quoted(source)]);
            let (src_node, src_out) = split_ref(source);
            let rid = nodes
                .iter()
                .find(|n| n.name == src_node)
                .and_then(|n| n.layer.outputs.get(src_out).and(n.locals.get(src_out)))
                .copied()
                .ok_or_else(|| unknown_output(source, loc.clone(), nodes))?;
            let produced = &resources[rid].decl;
            let compatible = match (&decl, produced) {
                (ResourceDecl::Texture(a), ResourceDecl::Texture(b)) => a.format == b.format,
                (ResourceDecl::Buffer(a), ResourceDecl::Buffer(b)) => a.size <= b.size,
                (ResourceDecl::Accel, ResourceDecl::Accel) => true,
                _ => false,
            };
            if !compatible {
                return Err(GraphError::new(
                    ErrorKind::FormatMismatch,
                    loc,
                    format!("input `{input}` of node `{name}` expects {}, but `{source}` is {}", describe_decl(&decl), describe_decl(produced)),
                )
                .note(nodes[ni].layer_src.locate(&["inputs", &SourceText::quoted(&input)]), "the input is declared here")
                .help("connect an output of the expected format, or insert a conversion layer"));
            }
            nodes[ni].locals.insert(input.clone(), rid);
        }
    }
    match unconnected_error(&unconnected) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// A layer input that the graph leaves unconnected and that has no fallback.
struct Unconnected {
    location: Location,
    input: String,
    node: String,
    layer: String,
}

/// One error for every unconnected input: the first at the error's place, the others as notes.
fn unconnected_error(all: &[Unconnected]) -> Option<GraphError> {
    let first = all.first()?;
    let what = |u: &Unconnected| format!("input `{}` of node `{}` (layer `{}`)", u.input, u.node, u.layer);
    if all.len() == 1 {
        return Some(
            GraphError::new(ErrorKind::NoProducer, first.location.clone(), format!("{} is not connected: nothing produces it", what(first)))
                .help(format!("add `inputs: {{\"{}\": \"node.output\"}}` to node `{}`", first.input, first.node)),
        );
    }
    let mut e = GraphError::new(
        ErrorKind::NoProducer,
        first.location.clone(),
        format!("{} inputs are not connected (nothing produces them): {} and the {} noted below", all.len(), what(first), all.len() - 1),
    );
    for u in &all[1..] {
        e = e.note(u.location.clone(), what(u));
    }
    Some(e.help("connect each of them in its node's `inputs: {\"input\": \"node.output\"}`"))
}

fn describe_decl(d: &ResourceDecl) -> String {
    match d {
        ResourceDecl::Texture(t) => format!("a {} texture", t.format),
        ResourceDecl::Buffer(b) => format!("a buffer of {} bytes", b.size),
        ResourceDecl::Accel => "an acceleration structure".into(),
    }
}

fn collect_passes(nodes: &[ResolvedNode], _resources: &[PlannedResource], producers: &mut HashMap<ResourceId, usize>) -> Result<Vec<PassNode>, GraphError> {
    let mut passes = Vec::new();
    let mut producer_loc: HashMap<ResourceId, (Location, String)> = HashMap::new();
    for (ni, node) in nodes.iter().enumerate() {
        for (pi, pass) in node.layer.passes.iter().enumerate() {
            let location = node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name)]);
            let lookup = |local: &String, what: &str| -> Result<(String, ResourceId), GraphError> {
                node.locals.get(local).map(|r| (local.clone(), *r)).ok_or_else(|| {
                    let mut names: Vec<&str> =
                        node.layer.inputs.keys().chain(node.layer.outputs.keys()).chain(node.layer.transients.keys()).map(|s| s.as_str()).collect();
                    names.sort();
                    GraphError::new(
                        ErrorKind::UnknownOutput,
                        node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name), what, &SourceText::quoted(local)]),
                        format!("pass `{}` {what} `{local}`, which layer `{}` does not declare", pass.name, node.layer_name),
                    )
                    .help(format!("declare it under inputs, outputs or transients; declared: {}", names.join(", ")))
                })
            };
            let reads = pass.reads.iter().map(|l| lookup(l, "reads")).collect::<Result<Vec<_>, _>>()?;
            let writes = pass.writes.iter().map(|l| lookup(l, "writes")).collect::<Result<Vec<_>, _>>()?;
            for (local, r) in &writes {
                if node.layer.inputs.contains_key(local) {
                    return Err(GraphError::new(
                        ErrorKind::TwoProducers,
                        location.clone(),
                        format!("pass `{}` writes `{local}`, an input of layer `{}` that another node produces", pass.name, node.layer_name),
                    )
                    .help("write a new output instead of the input"));
                }
                if let Some((first_loc, first_pass)) = producer_loc.get(r) {
                    return Err(GraphError::new(
                        ErrorKind::TwoProducers,
                        location.clone(),
                        format!("`{local}` is written by two passes: `{first_pass}` and `{}`", pass.name),
                    )
                    .note(first_loc.clone(), "first producer")
                    .help("give each pass its own output, or merge the passes"));
                }
                if reads.iter().any(|(_, rr)| rr == r) {
                    return Err(GraphError::new(ErrorKind::TwoProducers, location.clone(), format!("pass `{}` both reads and writes `{local}`", pass.name))
                        .help("write into a separate resource (ping-pong) instead"));
                }
                producer_loc.insert(*r, (location.clone(), pass.name.clone()));
                producers.insert(*r, passes.len());
            }
            if pass.shadow_slot.is_some() && pass.kind != PassKind::SceneRaster {
                return Err(GraphError::new(
                    ErrorKind::Unsupported,
                    location,
                    format!("pass `{}` has a `shadow_slot` but is not a SceneRaster pass", pass.name),
                )
                .help("only a pass that draws the scene can draw a shadow map: remove `shadow_slot`".to_string()));
            }
            passes.push(PassNode { node: ni, index: pi, reads, writes, location });
        }
    }
    Ok(passes)
}

/// Matches a pass's shader bindings by name against its declared resources and the built-ins.
fn check_interface(node: &ResolvedNode, pass: &PassDesc, p: &PassNode, info: &ShaderInfo, resources: &[PlannedResource]) -> Result<(), GraphError> {
    if pass.kind == PassKind::AccelBuild {
        return Ok(());
    }
    let shader_file = info.source.main_file().to_path_buf();
    let mismatch = |msg: String, shader_loc: Location, help: &str| {
        GraphError::new(ErrorKind::BindingMismatch, p.location.clone(), format!("layer `{}`, pass `{}`: {msg}", node.layer_name, pass.name))
            .note(shader_loc, format!("in {}", shader_file.display()))
            .help(help.to_string())
    };
    let file_loc = Location::file_start(&shader_file);

    // Entry points.
    let entry = entry_name(pass);
    let stage_ok = |name: &str, stage: naga::ShaderStage| info.entry(name).map(|e| e.stage == stage).unwrap_or(false);
    let accel_reads = p.reads.iter().filter(|(_, r)| resources[*r].decl == ResourceDecl::Accel).count();
    let binds_trace = info.bindings.iter().any(|b| builtins::is_accel_binding(&b.name));
    match pass.kind {
        PassKind::AccelBuild | PassKind::Rust => {}
        PassKind::Compute | PassKind::Trace => {
            // The rt-pipeline back-end's trace module makes a trace pass's compute entry point
            // a ray-generation shader (reflect::compute_to_ray_generation).
            let ray_generation = pass.kind == PassKind::Trace && stage_ok(&entry, naga::ShaderStage::RayGeneration);
            if !stage_ok(&entry, naga::ShaderStage::Compute) && !ray_generation {
                return Err(mismatch(
                    format!("the shader has no compute entry point `{entry}`"),
                    file_loc,
                    "add `@compute @workgroup_size(8, 8) fn ...` or set `entry:` in the pass",
                ));
            }
            if pass.kind == PassKind::Trace && (accel_reads != 1 || !binds_trace) {
                return Err(mismatch(
                    format!(
                        "a trace pass reads exactly one acceleration structure and includes the trace module; this one reads {accel_reads} and {} it",
                        if binds_trace { "includes" } else { "does not include" }
                    ),
                    file_loc,
                    "add the layer's `Accel` input to `reads` and `//#include \"trace/trace.wgsl\"` to the shader",
                ));
            }
            if pass.kind == PassKind::Compute && accel_reads > 0 {
                return Err(mismatch("a compute pass reads an acceleration structure".into(), file_loc, "make it `kind: Trace`"));
            }
        }
        PassKind::Fullscreen | PassKind::SceneRaster => {
            let vs = pass.vertex_entry.clone().unwrap_or_else(|| "vs_main".into());
            if !stage_ok(&vs, naga::ShaderStage::Vertex) {
                return Err(mismatch(
                    format!("the shader has no vertex entry point `{vs}`"),
                    file_loc,
                    "add a `@vertex` function or set `vertex_entry:` in the pass",
                ));
            }
            if !stage_ok(&entry, naga::ShaderStage::Fragment) {
                return Err(mismatch(
                    format!("the shader has no fragment entry point `{entry}`"),
                    file_loc,
                    "add a `@fragment` function or set `entry:` in the pass",
                ));
            }
            let colors: Vec<&(String, ResourceId)> = p.writes.iter().filter(|(_, r)| !resources[*r].decl.is_depth_texture()).collect();
            let outs = &info.entry(&entry).map(|e| e.locations.clone()).unwrap_or_default();
            let expected: Vec<u32> = (0..colors.len() as u32).collect();
            if *outs != expected {
                return Err(mismatch(
                    format!(
                        "the pass writes {} colour attachment(s) ({}), but `{entry}` writes {}",
                        colors.len(),
                        colors.iter().map(|(l, _)| l.as_str()).collect::<Vec<_>>().join(", "),
                        if outs.is_empty() {
                            "no @location".to_string()
                        } else {
                            outs.iter().map(|l| format!("@location({l})")).collect::<Vec<_>>().join(", ")
                        }
                    ),
                    file_loc,
                    "make the fragment outputs @location(0..n) match the order of `writes`",
                ));
            }
            if p.writes.iter().filter(|(_, r)| resources[*r].decl.is_depth_texture()).count() > 1 {
                return Err(mismatch("the pass writes more than one depth texture".into(), file_loc, "write at most one Depth32Float texture"));
            }
            if pass.kind == PassKind::SceneRaster {
                let vs_locs = info.entry(&vs).map(|e| e.locations.clone()).unwrap_or_default();
                if let Some(bad) = vs_locs.iter().find(|l| **l > 2) {
                    return Err(mismatch(
                        format!("vertex input @location({bad}) does not exist"),
                        file_loc,
                        "scene vertices provide @location(0) position, (1) normal, (2) uv",
                    ));
                }
            }
        }
    }

    // Every binding the shader declares must be a declared resource or a built-in.
    for b in &info.bindings {
        let want_group = if b.name == builtins::SCENE_TEXTURES {
            builtins::SCENE_TEXTURES_GROUP
        } else if builtins::is_accel_binding(&b.name) {
            builtins::ACCEL_GROUP
        } else {
            0
        };
        if b.group != want_group {
            return Err(mismatch(
                format!("binding `{}` is in @group({}); it lives in @group({want_group})", b.name, b.group),
                b.location.clone(),
                &format!("use @group({want_group}) (bindings live in @group(0), except `scene_textures`, which is in @group(1): a binding array may not share a group with uniform buffers)"),
            ));
        }
        let read = p.reads.iter().find(|(l, _)| *l == b.name);
        let write = p.writes.iter().find(|(l, _)| *l == b.name);
        let expected: Option<String> = if let Some((_, r)) = read {
            match &resources[*r].decl {
                ResourceDecl::Texture(t) if t.format.is_depth() => (b.kind != BindingKind::DepthTexture).then(|| "texture_depth_2d".to_string()),
                ResourceDecl::Texture(t) => {
                    let kind = if t.format.is_uint() { naga::ScalarKind::Uint } else { naga::ScalarKind::Float };
                    let want = BindingKind::SampledTexture { dim: naga::ImageDimension::D2, arrayed: false, kind };
                    (b.kind != want).then(|| want.describe())
                }
                ResourceDecl::Buffer(_) => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read>".to_string()),
                ResourceDecl::Accel => Some("no binding of that name (the trace module binds the acceleration structure)".into()),
            }
        } else if let Some((_, r)) = write {
            if !pass.kind.is_compute() {
                Some("no binding (it is a render attachment of this pass)".into())
            } else {
                match &resources[*r].decl {
                    ResourceDecl::Texture(t) => match t.format.to_storage() {
                        None => Some(format!("nothing: {} cannot be a storage texture", t.format)),
                        Some(fmt) => match &b.kind {
                            BindingKind::StorageTexture { format, access } if *format == fmt && access.contains(naga::StorageAccess::STORE) => None,
                            _ => Some(BindingKind::StorageTexture { format: fmt, access: naga::StorageAccess::STORE }.describe()),
                        },
                    },
                    ResourceDecl::Buffer(_) => {
                        (!matches!(b.kind, BindingKind::Storage { read_only: false, .. })).then(|| "var<storage, read_write>".to_string())
                    }
                    ResourceDecl::Accel => Some("nothing: only an Accel node writes an acceleration structure".into()),
                }
            }
        } else if builtins::is_accel_binding(&b.name) {
            (pass.kind != PassKind::Trace).then(|| "no trace-module binding: only `kind: Trace` passes trace rays".to_string())
        } else if builtins::is_builtin(&b.name) {
            check_builtin(node, b)?
        } else {
            return Err(mismatch(
                format!("shader binding `{}` ({}) is not a resource of this pass", b.name, b.kind.describe()),
                b.location.clone(),
                "add it to the pass's `reads` or `writes` (declared in the layer), or remove it from the shader",
            ));
        };
        if let Some(want) = expected {
            return Err(mismatch(
                format!("shader binding `{}` is {}, but the pass's resource needs {want}", b.name, b.kind.describe()),
                b.location.clone(),
                "change the WGSL declaration or the resource's format in the layer file",
            ));
        }
    }
    // Every declared read (and compute write) must be bound by the shader.
    for (local, r) in p.reads.iter().chain(p.writes.iter().filter(|_| pass.kind.is_compute())) {
        if resources[*r].decl != ResourceDecl::Accel && info.binding(local).is_none() {
            return Err(mismatch(
                format!("the pass declares `{local}` ({}) but the shader has no binding named `{local}`", resources[*r].name),
                file_loc,
                "declare `@group(0) @binding(N) var <name>: ...` in the shader, or remove it from the pass",
            ));
        }
    }
    Ok(())
}

/// Checks a built-in binding's type; `Err` for a hard error, `Ok(Some(expected))` for a mismatch.
fn check_builtin(node: &ResolvedNode, b: &reflect::ShaderBinding) -> Result<Option<String>, GraphError> {
    Ok(match b.name.as_str() {
        builtins::FRAME => match &b.kind {
            BindingKind::Uniform { size, .. } if *size == builtins::frame_uniform_size() => None,
            _ => Some(format!("var<uniform> frame: Frame ({} bytes, from common/frame.wgsl)", builtins::frame_uniform_size())),
        },
        builtins::DEBUG_COUNTERS => {
            (!matches!(b.kind, BindingKind::Storage { read_only: false, .. })).then(|| "var<storage, read_write> array<atomic<u32>>".into())
        }
        builtins::SCENE_INSTANCES => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Instance>".into()),
        builtins::SCENE_MATERIALS => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Material>".into()),
        builtins::SCENE_LIGHTS => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Light>".into()),
        builtins::SCENE_VERTICES | builtins::SCENE_INDICES | builtins::SCENE_MESHES => {
            (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> (declared in common/scene.wgsl)".into())
        }
        builtins::SCENE_TEXTURES => {
            // The texture array everywhere, or a binding array where the device has them
            // (chosen through the `common/scene_textures.wgsl` include).
            let array = BindingKind::SampledTexture { dim: naga::ImageDimension::D2, arrayed: true, kind: naga::ScalarKind::Float };
            (b.kind != array && b.kind != BindingKind::TextureBindingArray)
                .then(|| format!("var scene_textures: SceneTextures (from common/scene_textures.wgsl), i.e. {}", array.describe()))
        }
        builtins::LINEAR_SAMPLER | builtins::NEAREST_SAMPLER => (b.kind != BindingKind::Sampler { comparison: false }).then(|| "sampler".into()),
        builtins::PARAMS => match &b.kind {
            BindingKind::Uniform { members, .. } => {
                for m in members {
                    if m.name.starts_with('_') {
                        continue;
                    }
                    let Some(decl) = node.layer.params.get(&m.name) else {
                        return Ok(Some(format!(
                            "only members named after the layer's parameters; `{}` is not one (declared: {})",
                            m.name,
                            node.layer.params.keys().cloned().collect::<Vec<_>>().join(", ")
                        )));
                    };
                    let ok = matches!(
                        (decl, m.scalar, m.components),
                        (ParamDecl::Float { .. }, Some(naga::ScalarKind::Float), 1)
                            | (ParamDecl::Int { .. } | ParamDecl::Enum { .. }, Some(naga::ScalarKind::Sint | naga::ScalarKind::Uint), 1)
                            | (ParamDecl::Bool { .. }, Some(naga::ScalarKind::Uint), 1)
                    );
                    if !ok {
                        let want = match decl {
                            ParamDecl::Float { .. } => "f32",
                            ParamDecl::Int { .. } | ParamDecl::Enum { .. } => "i32 or u32",
                            ParamDecl::Bool { .. } => "u32",
                        };
                        return Ok(Some(format!("member `{}` of type {want} (parameter `{}` is a {})", m.name, m.name, decl.type_name())));
                    }
                }
                None
            }
            _ => Some("var<uniform> params: <struct of the layer's parameters>".into()),
        },
        _ => None,
    })
}
