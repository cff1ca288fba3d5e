//! The graph compiler. Its phases read top to bottom in [`compile_with`]:
//! parse -> resolve layers -> build the petgraph graph -> validate -> cull -> schedule ->
//! shader interface check -> resource lifetimes -> allocation with reuse -> plan.

mod allocate;
mod connect;
mod interface;
mod options;
mod plan;
mod resolve;
mod schedule;
mod source;

pub use options::{CompileOptions, Project, TRACE_INCLUDE};
pub use plan::{fmt_bytes, Plan, PlannedPass, PlannedResource, ResourceId, Slot, Usage};
pub use resolve::check_param;
pub use source::{parse_graph, parse_layer};

use allocate::same_shape;
use connect::{connect_inputs, declare_resources, split_ref, unknown_output};
use interface::{check_interface, entry_name};
use resolve::resolve_layers;
use schedule::{collect_passes, cycle_error, pass_name, Vertex};
use source::{parse_ron, read_file, SourceText};

use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use crate::graph::reflect::{self, ShaderInfo};
use crate::scene::gpu::SceneUsage;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::Direction;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Compiles a graph file into an executable plan for a frame of `frame_size`.
pub fn compile(graph_file: &Path, project: &Project, frame_size: (u32, u32)) -> Result<Plan, GraphError> {
    compile_with(graph_file, project, frame_size, &CompileOptions::default())
}

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
        if pass.kind == PassKind::AccelBuild {
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
