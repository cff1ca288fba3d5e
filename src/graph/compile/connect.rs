//! The graph's resources and connections: every layer output and transient declared with its
//! size, every layer input joined to the output that produces it (or to a constant fallback
//! texture), and the errors of inputs left unconnected, unknown or of the wrong format.

use super::plan::{PlannedResource, Usage};
use super::resolve::ResolvedNode;
use super::source::SourceText;
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;

pub(super) fn declare_resources(nodes: &mut [ResolvedNode], resources: &mut Vec<PlannedResource>, frame: (u32, u32)) {
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

pub(super) fn connect_inputs(graph: &GraphDesc, gsrc: &SourceText, nodes: &mut [ResolvedNode], resources: &mut Vec<PlannedResource>) -> Result<(), GraphError> {
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

pub(super) fn split_ref(s: &str) -> (&str, &str) {
    s.split_once('.').unwrap_or((s, ""))
}

pub(super) fn unknown_output(reference: &str, loc: Location, nodes: &[ResolvedNode]) -> GraphError {
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
