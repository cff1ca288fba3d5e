//! Passes and their order: each pass's reads and writes looked up (one producer per resource,
//! or per layer of a layered texture), the petgraph graph of pass and resource vertices, cycles
//! reported as their path of nodes, and the culling and topological order of the passes.

use super::connect::{output_resource, unknown_output};
use super::plan::{PlannedResource, ResourceId};
use super::resolve::ResolvedNode;
use super::source::SourceText;
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::Direction;
use std::collections::HashMap;

/// A vertex of the petgraph graph: a pass or a resource (indices).
#[derive(Debug, Clone, Copy)]
enum Vertex {
    Pass(usize),
    Resource(ResourceId),
}

/// A pass of a resolved node: its node and index in the layer's passes, its reads and writes as
/// `(local name, resource)`, and where the layer file declares it.
pub(super) struct PassNode {
    pub(super) node: usize,
    pub(super) index: usize,
    pub(super) reads: Vec<(String, ResourceId)>,
    pub(super) writes: Vec<(String, ResourceId)>,
    /// The buffer `runs_when` counts in.
    pub(super) runs_when: Option<ResourceId>,
    pub(super) location: Location,
}

/// Which pass writes each resource (an index into the passes; of a layered texture, one of them).
pub(super) type Producers = HashMap<ResourceId, usize>;

/// What one pass at most may write: a resource, and the layer of a layered texture
/// (`TextureDecl::layers`; 0 for any other).
type WrittenPart = (ResourceId, u32);

/// Every pass of every node with its reads and writes looked up in the node's `locals`, and
/// the pass that writes each resource (one; a pass per layer of a layered texture).
pub(super) fn collect_passes(nodes: &[ResolvedNode]) -> Result<(Vec<PassNode>, Producers), GraphError> {
    let mut passes = Vec::new();
    let mut producers = Producers::new();
    let mut producer_loc: HashMap<WrittenPart, (Location, String)> = HashMap::new();
    for (ni, node) in nodes.iter().enumerate() {
        for (pi, pass) in node.layer.passes.iter().enumerate() {
            let location = node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name)]);
            let reads = pass.reads.iter().map(|e| pass_resource(node, pass, e, "reads")).collect::<Result<Vec<_>, _>>()?;
            let writes = pass.writes.iter().map(|e| pass_resource(node, pass, e, "writes")).collect::<Result<Vec<_>, _>>()?;
            for w in &writes {
                let part = (w.resource, if layer_count(node, &w.local) > 1 { pass.layer.unwrap_or(0) } else { 0 });
                check_write(node, pass, &location, (w, part), &reads, &producer_loc)?;
                producer_loc.insert(part, (location.clone(), pass.name.clone()));
                producers.insert(w.resource, passes.len());
            }
            check_pass_options(pass, &location)?;
            let runs_when = pass.runs_when.as_ref().map(|c| pass_resource(node, pass, c.buffer(), "runs_when")).transpose()?.map(|r| r.resource);
            let bound = |list: Vec<PassResource>| list.into_iter().map(|a| (a.binding, a.resource)).collect();
            passes.push(PassNode { node: ni, index: pi, reads: bound(reads), writes: bound(writes), runs_when, location });
        }
    }
    Ok((passes, producers))
}

/// One entry of a pass's `reads` or `writes`: `"name"` binds resource `name` under its own
/// name; `"binding=name"` binds it under another (so that one shader serves passes over
/// different resources).
struct PassResource {
    binding: String,
    local: String,
    resource: ResourceId,
}

fn pass_resource(node: &ResolvedNode, pass: &PassDesc, entry: &str, what: &str) -> Result<PassResource, GraphError> {
    let (binding, local) = entry.split_once('=').map(|(b, l)| (b.trim(), l.trim())).unwrap_or((entry, entry));
    node.locals.get(local).map(|r| PassResource { binding: binding.to_string(), local: local.to_string(), resource: *r }).ok_or_else(|| {
        let mut names: Vec<&str> = node
            .layer
            .inputs
            .keys()
            .chain(node.layer.outputs.keys())
            .chain(node.layer.transients.keys())
            .chain(node.layer.history.keys())
            .map(|s| s.as_str())
            .collect();
        names.sort();
        GraphError::new(
            ErrorKind::UnknownOutput,
            node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name), what, &SourceText::quoted(entry)]),
            format!("pass `{}` {what} `{local}`, which layer `{}` does not declare", pass.name, node.layer_name),
        )
        .help(format!("declare it under inputs, outputs, transients or history; declared: {}", names.join(", ")))
    })
}

/// A write is of the layer's own output or transient, by one pass, which does not read it.
fn check_write(
    node: &ResolvedNode,
    pass: &PassDesc,
    location: &Location,
    (w, part): (&PassResource, WrittenPart),
    reads: &[PassResource],
    producer_loc: &HashMap<WrittenPart, (Location, String)>,
) -> Result<(), GraphError> {
    let local = &w.local;
    if let Some(source) = node.layer.history.get(local) {
        return Err(GraphError::new(
            ErrorKind::TwoProducers,
            location.clone(),
            format!("pass `{}` writes `{local}`, the previous frame of `{source}`, which only the executor writes", pass.name),
        )
        .help(format!("write `{source}`: it becomes `{local}` on the next frame")));
    }
    if node.layer.inputs.contains_key(local) {
        return Err(GraphError::new(
            ErrorKind::TwoProducers,
            location.clone(),
            format!("pass `{}` writes `{local}`, an input of layer `{}` that another node produces", pass.name, node.layer_name),
        )
        .help("write a new output instead of the input"));
    }
    if let Some((first_loc, first_pass)) = producer_loc.get(&part) {
        return Err(GraphError::new(
            ErrorKind::TwoProducers,
            location.clone(),
            format!(
                "`{local}` is written by two passes: `{first_pass}` and `{}`{}",
                pass.name,
                if part.1 > 0 || layer_count(node, local) > 1 { format!(" (layer {})", part.1) } else { String::new() }
            ),
        )
        .note(first_loc.clone(), "first producer")
        .help("give each pass its own output, or merge the passes"));
    }
    if reads.iter().any(|r| r.resource == w.resource) {
        return Err(GraphError::new(ErrorKind::TwoProducers, location.clone(), format!("pass `{}` both reads and writes `{local}`", pass.name))
            .help("write into a separate resource (ping-pong) instead"));
    }
    check_layered_write(node, pass, location, local)
}

/// The array layers of `local`, an output or transient texture of `node`'s layer (1 for
/// anything else).
fn layer_count(node: &ResolvedNode, local: &str) -> u32 {
    match node.layer.outputs.get(local).or_else(|| node.layer.transients.get(local)) {
        Some(ResourceDecl::Texture(t)) => t.layers,
        _ => 1,
    }
}

/// A layered texture (`TextureDecl::layers`) is written one layer at a time, as the attachment
/// of a render pass that names a layer it has.
fn check_layered_write(node: &ResolvedNode, pass: &PassDesc, location: &Location, local: &str) -> Result<(), GraphError> {
    let layers = layer_count(node, local);
    if layers <= 1 {
        return Ok(());
    }
    let render = matches!(pass.kind, PassKind::SceneRaster | PassKind::Fullscreen);
    match pass.layer {
        Some(layer) if render && layer < layers => Ok(()),
        _ => Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!("pass `{}` writes `{local}`, a texture of {layers} layers, but is not a render pass with a `layer` below {layers}", pass.name),
        )
        .help("draw the texture one layer at a time: a SceneRaster or Fullscreen pass per layer, each with `layer: Some(n)`")),
    }
}

/// `shadow_slot` only on scene raster passes, and below `SHADOW_SLOTS`; `layer` only on render
/// passes; `cull_closed_back_faces` only with a slot.
fn check_pass_options(pass: &PassDesc, location: &Location) -> Result<(), GraphError> {
    if pass.shadow_slot.is_some() && pass.kind != PassKind::SceneRaster {
        return Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!("pass `{}` has a `shadow_slot` but is not a SceneRaster pass", pass.name),
        )
        .help("only a pass that draws the scene can draw a shadow map: remove `shadow_slot`".to_string()));
    }
    if pass.layer.is_some() && !matches!(pass.kind, PassKind::SceneRaster | PassKind::Fullscreen) {
        return Err(GraphError::new(ErrorKind::Unsupported, location.clone(), format!("pass `{}` has a `layer` but is not a render pass", pass.name))
            .help("only SceneRaster and Fullscreen passes draw into one layer of their attachments: remove `layer`".to_string()));
    }
    if pass.shadow_slot.is_some_and(|slot| slot as usize >= crate::uniforms::SHADOW_SLOTS) {
        return Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!(
                "pass `{}` draws shadow slot {}, but there are {} (0 to {})",
                pass.name,
                pass.shadow_slot.unwrap_or(0),
                crate::uniforms::SHADOW_SLOTS,
                crate::uniforms::SHADOW_SLOTS - 1
            ),
        )
        .help("slots 0-3 are the directional and spot lights' maps, the next six each the faces of a point light's cube map".to_string()));
    }
    if pass.translucent && (pass.kind != PassKind::SceneRaster || pass.skip_blend || pass.shadow_slot.is_some()) {
        return Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!("pass `{}` is `translucent` but not a SceneRaster pass of colour targets (or also has `skip_blend` or `shadow_slot`)", pass.name),
        )
        .help("a translucent pass draws the scene's translucent instances blended into colour targets: make it a SceneRaster pass without `skip_blend` and `shadow_slot`".to_string()));
    }
    if pass.cull_closed_back_faces && pass.shadow_slot.is_none() {
        return Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!("pass `{}` has `cull_closed_back_faces` but no `shadow_slot`", pass.name),
        )
        .help("the culling needs the light a shadow map is drawn from: add `shadow_slot`, or set `cull_back_faces` instead".to_string()));
    }
    check_shadow_tiles(pass, location)
}

/// `shadow_tiles` only with a `shadow_slot`, at least one column and row, and every slot of
/// its tiles below `SHADOW_SLOTS`.
fn check_shadow_tiles(pass: &PassDesc, location: &Location) -> Result<(), GraphError> {
    let Some((columns, rows)) = pass.shadow_tiles else { return Ok(()) };
    let Some(slot) = pass.shadow_slot else {
        return Err(GraphError::new(ErrorKind::Unsupported, location.clone(), format!("pass `{}` has `shadow_tiles` but no `shadow_slot`", pass.name))
            .help("tiles hold the slots from the pass's `shadow_slot` on: add `shadow_slot`, or remove `shadow_tiles`".to_string()));
    };
    let last = u64::from(slot) + u64::from(columns) * u64::from(rows);
    if columns == 0 || rows == 0 || last > crate::uniforms::SHADOW_SLOTS as u64 {
        return Err(GraphError::new(
            ErrorKind::Unsupported,
            location.clone(),
            format!(
                "pass `{}` draws {columns} x {rows} shadow tiles from slot {slot}, but there are {} slots (0 to {})",
                pass.name,
                crate::uniforms::SHADOW_SLOTS,
                crate::uniforms::SHADOW_SLOTS - 1
            ),
        )
        .help("give at least one column and one row, and no more tiles than the slots from `shadow_slot` to the last".to_string()));
    }
    Ok(())
}

/// A pass of shadow tiles has at least one texel a tile in every attachment it draws.
pub(super) fn check_tile_sizes(nodes: &[ResolvedNode], passes: &[PassNode], resources: &[PlannedResource]) -> Result<(), GraphError> {
    for p in passes {
        let pass = &nodes[p.node].layer.passes[p.index];
        let Some((columns, rows)) = pass.shadow_tiles else { continue };
        for (local, r) in &p.writes {
            let (width, height) = resources[*r].extent;
            if width < columns || height < rows {
                return Err(GraphError::new(
                    ErrorKind::Unsupported,
                    p.location.clone(),
                    format!("pass `{}` draws {columns} x {rows} shadow tiles into `{local}` of {width}x{height} texels: a tile would be empty", pass.name),
                )
                .help("give the texture at least one texel a tile, or fewer tiles"));
            }
        }
    }
    Ok(())
}

/// A pass's `runs_when` counts in a buffer of its layer (of at least two words) that one of the
/// layer's passes writes, and compares the count with a finite, non-negative fraction.
pub(super) fn check_conditions(nodes: &[ResolvedNode], passes: &[PassNode], resources: &[PlannedResource]) -> Result<(), GraphError> {
    for p in passes {
        let pass = &nodes[p.node].layer.passes[p.index];
        let (Some(condition), Some(count)) = (&pass.runs_when, p.runs_when) else { continue };
        let refuse = |message: String, help: &str| Err(GraphError::new(ErrorKind::Unsupported, p.location.clone(), message).help(help.to_string()));
        let buffer = condition.buffer();
        if !matches!(&resources[count].decl, ResourceDecl::Buffer(b) if b.size >= 8) {
            return refuse(
                format!("pass `{}` runs when a count in `{buffer}` allows, but `{buffer}` is not a buffer of at least 8 bytes", pass.name),
                "name a buffer whose first two 32-bit words, a count and its whole, a pass of the layer writes",
            );
        }
        if !passes.iter().any(|q| q.node == p.node && q.writes.iter().any(|(_, r)| *r == count)) {
            return refuse(
                format!("pass `{}` runs when a count in `{buffer}` allows, but no pass of its layer writes `{buffer}`", pass.name),
                "add `buffer` to the `writes` of the pass that counts",
            );
        }
        let fraction = condition.fraction();
        if !fraction.is_finite() || fraction < 0.0 {
            return refuse(
                format!("pass `{}` compares its count with {fraction} x its whole: not a finite, non-negative fraction", pass.name),
                "give `fraction` a value of 0 or more",
            );
        }
    }
    Ok(())
}

/// The passes that reach the graph output (or its HDR output), in execution order, and the
/// graph's outputs.
pub(super) struct Schedule {
    /// Indices of the kept passes in a topological order.
    pub(super) kept: Vec<usize>,
    /// Names (`node/pass`) of the passes whose outputs never reach the graph output.
    pub(super) culled: Vec<String>,
    pub(super) output: ResourceId,
    /// The linear HDR image of `hdr_output`, where the graph names one and its node is on.
    pub(super) hdr_output: Option<ResourceId>,
}

/// Checks that every read has a producer, that there is no cycle and that the output exists
/// and is presentable; then culls the passes that do not reach the output and orders the rest.
pub(super) fn schedule(
    graph: &GraphDesc,
    gsrc: &SourceText,
    nodes: &[ResolvedNode],
    passes: &[PassNode],
    resources: &[PlannedResource],
    producers: &Producers,
) -> Result<Schedule, GraphError> {
    let pg = PassGraph::new(passes, resources.len());
    check_producers(nodes, passes, resources, producers)?;
    let topo = petgraph::algo::toposort(&pg.g, None).map_err(|cycle| cycle_error(&pg.g, cycle.node_id(), gsrc, nodes, passes, resources))?;
    let output = graph_output(graph, gsrc, nodes, resources, producers)?;
    let hdr_output = graph_hdr_output(graph, gsrc, nodes, resources, producers)?;
    let roots: Vec<ResourceId> = std::iter::once(output).chain(hdr_output).collect();
    let reaches = pg.reaching(&roots, resources);
    let kept: Vec<usize> = topo
        .iter()
        .filter_map(|v| match pg.g[*v] {
            Vertex::Pass(p) if reaches[v.index()] => Some(p),
            _ => None,
        })
        .collect();
    let culled: Vec<String> = (0..passes.len()).filter(|p| !reaches[pg.pass_vertex[*p].index()]).map(|p| pass_name(nodes, &passes[p])).collect();
    Ok(Schedule { kept, culled, output, hdr_output })
}

/// The petgraph graph: an edge from each resource to the passes reading it, and from each pass
/// to the resources it writes.
struct PassGraph {
    g: DiGraph<Vertex, ()>,
    res_vertex: Vec<NodeIndex>,
    pass_vertex: Vec<NodeIndex>,
}

impl PassGraph {
    fn new(passes: &[PassNode], resource_count: usize) -> Self {
        let mut g: DiGraph<Vertex, ()> = DiGraph::new();
        let res_vertex: Vec<NodeIndex> = (0..resource_count).map(|r| g.add_node(Vertex::Resource(r))).collect();
        let pass_vertex: Vec<NodeIndex> = (0..passes.len()).map(|p| g.add_node(Vertex::Pass(p))).collect();
        for (pi, p) in passes.iter().enumerate() {
            for (_, r) in &p.reads {
                g.add_edge(res_vertex[*r], pass_vertex[pi], ());
            }
            for (_, r) in &p.writes {
                g.add_edge(pass_vertex[pi], res_vertex[*r], ());
            }
        }
        Self { g, res_vertex, pass_vertex }
    }

    /// For each vertex (by index), whether one of the resources `roots` (the graph's outputs)
    /// can be reached from it. A history resource is reached through the resource it keeps,
    /// written a frame earlier: whatever writes that is kept too (an edge for this walk only,
    /// not for the order).
    fn reaching(&self, roots: &[ResourceId], resources: &[PlannedResource]) -> Vec<bool> {
        let mut reaches = vec![false; self.g.node_count()];
        let mut stack: Vec<NodeIndex> = roots.iter().map(|r| self.res_vertex[*r]).collect();
        while let Some(v) = stack.pop() {
            if std::mem::replace(&mut reaches[v.index()], true) {
                continue;
            }
            stack.extend(self.g.neighbors_directed(v, Direction::Incoming));
            if let Vertex::Resource(r) = self.g[v] {
                stack.extend(resources[r].history_of.map(|source| self.res_vertex[source]));
            }
        }
        reaches
    }
}

/// Every read has a producer or is a constant (fallback) texture.
fn check_producers(nodes: &[ResolvedNode], passes: &[PassNode], resources: &[PlannedResource], producers: &Producers) -> Result<(), GraphError> {
    for p in passes {
        for (local, r) in &p.reads {
            if !producers.contains_key(r) && resources[*r].constant.is_none() && resources[*r].history_of.is_none() {
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
    Ok(())
}

/// The resource a graph field (`output`, `hdr_output`) names as `node.output`: an output of a
/// node, written by a pass; with the field's location for further errors.
fn named_output(field: &str, name: &str, gsrc: &SourceText, nodes: &[ResolvedNode], producers: &Producers) -> Result<(ResourceId, Location), GraphError> {
    let loc = gsrc.locate(&[field, &SourceText::quoted(name)]);
    let id = output_resource(nodes, name).ok_or_else(|| unknown_output(name, loc.clone(), nodes))?;
    if !producers.contains_key(&id) {
        let (what, help) = match field {
            "output" => (format!("graph output `{name}`"), "write the output in one of the layer's passes"),
            _ => (format!("graph `{field}` `{name}`"), "name an output that a pass of its layer writes"),
        };
        return Err(GraphError::new(ErrorKind::NoProducer, loc, format!("{what} is never written")).help(help));
    }
    Ok((id, loc))
}

/// The resource the graph names as its output: an output of a node, written by a pass, and an
/// Rgba8Unorm or Rgba8UnormSrgb texture.
fn graph_output(
    graph: &GraphDesc,
    gsrc: &SourceText,
    nodes: &[ResolvedNode],
    resources: &[PlannedResource],
    producers: &Producers,
) -> Result<ResourceId, GraphError> {
    let (output, output_loc) = named_output("output", &graph.output, gsrc, nodes, producers)?;
    match &resources[output].decl {
        ResourceDecl::Texture(t) if matches!(t.format, Format::Rgba8Unorm | Format::Rgba8UnormSrgb) => Ok(output),
        other => Err(GraphError::new(
            ErrorKind::Unsupported,
            output_loc,
            format!("graph output `{}` is `{other}`; the output must be an Rgba8Unorm or Rgba8UnormSrgb texture", graph.output),
        )
        .help("add a tone-map layer that writes an Rgba8UnormSrgb texture and make it the output")),
    }
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

/// The resource the graph names as its linear HDR image (`hdr_output`): `None` where it names
/// none or its node is switched off; else an output of a node, written by a pass, and an
/// Rgba16Float or Rgba32Float texture.
fn graph_hdr_output(
    graph: &GraphDesc,
    gsrc: &SourceText,
    nodes: &[ResolvedNode],
    resources: &[PlannedResource],
    producers: &Producers,
) -> Result<Option<ResourceId>, GraphError> {
    let Some(name) = &graph.hdr_output else { return Ok(None) };
    let node = name.split_once('.').map_or(name.as_str(), |(node, _)| node);
    if matches!(graph.nodes.get(node), Some(NodeDesc::Layer(l)) if !l.enabled) {
        return Ok(None);
    }
    let (hdr, loc) = named_output("hdr_output", name, gsrc, nodes, producers)?;
    match &resources[hdr].decl {
        ResourceDecl::Texture(t) if matches!(t.format, Format::Rgba16Float | Format::Rgba32Float) => Ok(Some(hdr)),
        other => Err(GraphError::new(
            ErrorKind::Unsupported,
            loc,
            format!("graph `hdr_output` `{name}` is `{other}`; the HDR output must be an Rgba16Float or Rgba32Float texture"),
        )
        .help("name the linear HDR image the tone map reads, e.g. `hdr_output: \"blend.color\"`")),
    }
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

/// `"node/pass"`.
pub(super) fn pass_name(nodes: &[ResolvedNode], p: &PassNode) -> String {
    format!("{}/{}", nodes[p.node].name, nodes[p.node].layer.passes[p.index].name)
}
