//! Passes and their order: each pass's reads and writes looked up (one producer per resource),
//! the petgraph graph of pass and resource vertices, cycles reported as their path of nodes,
//! and the culling and topological order of the passes.

use super::plan::{PlannedResource, ResourceId};
use super::resolve::ResolvedNode;
use super::source::SourceText;
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::Direction;
use std::collections::HashMap;

#[derive(Debug, Clone, Copy)]
pub(super) enum Vertex {
    Pass(usize),
    Resource(ResourceId),
}

pub(super) struct PassNode {
    pub(super) node: usize,
    pub(super) index: usize,
    pub(super) reads: Vec<(String, ResourceId)>,
    pub(super) writes: Vec<(String, ResourceId)>,
    pub(super) location: Location,
}

pub(super) fn collect_passes(
    nodes: &[ResolvedNode],
    _resources: &[PlannedResource],
    producers: &mut HashMap<ResourceId, usize>,
) -> Result<Vec<PassNode>, GraphError> {
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

/// The cycle through `start` as graph node names, `a -> b -> a`, pointing at the first node.
pub(super) fn cycle_error(
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

pub(super) fn pass_name(nodes: &[ResolvedNode], p: &PassNode) -> String {
    format!("{}/{}", nodes[p.node].name, nodes[p.node].layer.passes[p.index].name)
}
