//! The graph's resources and connections: every layer output and transient declared with its
//! size, every layer input joined to the output that produces it (or to a constant fallback
//! texture), and the errors of inputs left unconnected, unknown or of the wrong format.

use super::plan::{PlannedResource, ResourceId};
use super::resolve::ResolvedNode;
use super::source::SourceText;
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;

/// Every layer output (`node.output`) and transient (`node/transient`) as a resource, its
/// texture size resolved for the frame; each node's `locals` name them.
pub(super) fn declare_resources(nodes: &mut [ResolvedNode], frame: (u32, u32)) -> Vec<PlannedResource> {
    let mut resources = Vec::new();
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
            resources.push(PlannedResource::new(name, decl, extent));
        }
        for (history, source) in &node.layer.history {
            // Checked by `check_history`; an unknown source declares nothing here.
            let Some(&src) = node.locals.get(source) else { continue };
            let mut res = PlannedResource::new(format!("{}.{history}", node.name), resources[src].decl.clone(), resources[src].extent);
            res.history_of = Some(src);
            node.locals.insert(history.clone(), resources.len());
            resources.push(res);
        }
    }
    resources
}

/// Every history declaration names an output or transient texture of its layer, under a name
/// of its own.
pub(super) fn check_history(nodes: &[ResolvedNode]) -> Result<(), GraphError> {
    for node in nodes {
        for (history, source) in &node.layer.history {
            let at = node.layer_src.locate(&["history", &SourceText::quoted(history)]);
            let taken = node.layer.inputs.contains_key(history) || node.layer.outputs.contains_key(history) || node.layer.transients.contains_key(history);
            if taken {
                return Err(GraphError::new(
                    ErrorKind::Syntax,
                    at,
                    format!("history `{history}` of layer `{}` has the name of another resource of the layer", node.layer_name),
                )
                .help(format!("give the previous frame of `{source}` a name of its own, such as `{source}_previous`")));
            }
            match node.layer.outputs.get(source).or_else(|| node.layer.transients.get(source)) {
                Some(ResourceDecl::Texture(_)) => {}
                Some(other) => {
                    return Err(GraphError::new(
                        ErrorKind::Unsupported,
                        at,
                        format!("history `{history}` keeps `{source}`, a {other}: only textures have a history"),
                    )
                    .help("keep the previous frame of a texture"))
                }
                None => {
                    let mut names: Vec<&str> = node.layer.outputs.keys().chain(node.layer.transients.keys()).map(|s| s.as_str()).collect();
                    names.sort();
                    return Err(GraphError::new(
                        ErrorKind::UnknownOutput,
                        at,
                        format!("history `{history}` keeps `{source}`, which is not an output or transient of layer `{}`", node.layer_name),
                    )
                    .help(format!("name one of: {}", names.join(", "))));
                }
            }
        }
    }
    Ok(())
}

/// Joins every layer input to the output the graph connects it to (or to a constant texture of
/// its fallback value); all inputs left unconnected are reported in one error.
pub(super) fn connect_inputs(graph: &GraphDesc, gsrc: &SourceText, nodes: &mut [ResolvedNode], resources: &mut Vec<PlannedResource>) -> Result<(), GraphError> {
    let mut unconnected: Vec<Unconnected> = Vec::new();
    for ni in 0..nodes.len() {
        let NodeDesc::Layer(ln) = &graph.nodes[&nodes[ni].name] else { continue };
        check_known_inputs(gsrc, &nodes[ni], ln)?;
        let inputs: Vec<(String, ResourceDecl)> = nodes[ni].layer.inputs.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
        for (input, decl) in inputs {
            let source = ln.inputs.get(&input);
            let disabled_source = source.and_then(|source| {
                let (src_node, _) = split_ref(source);
                matches!(graph.nodes.get(src_node), Some(NodeDesc::Layer(l)) if !l.enabled).then(|| src_node.to_string())
            });
            if source.is_none() || disabled_source.is_some() {
                if let Some(constant) = fallback_texture(&nodes[ni].name, &input, &decl) {
                    nodes[ni].locals.insert(input.clone(), resources.len());
                    resources.push(constant);
                    continue;
                }
                if let Some(src) = disabled_source {
                    return Err(switched_off_source(gsrc, &nodes[ni], &input, &src));
                }
            }
            let Some(source) = source else {
                let node = &nodes[ni];
                let location = gsrc.locate(&["nodes", &SourceText::quoted(&node.name)]);
                unconnected.push(Unconnected { location, input, node: node.name.clone(), layer: node.layer_name.clone() });
                continue;
            };
            let rid = source_resource(gsrc, nodes, ni, (&input, &decl), source, resources)?;
            nodes[ni].locals.insert(input.clone(), rid);
        }
    }
    match unconnected_error(&unconnected) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Every input the graph connects for a node is one its layer declares.
fn check_known_inputs(gsrc: &SourceText, node: &ResolvedNode, ln: &LayerNode) -> Result<(), GraphError> {
    for input in ln.inputs.keys() {
        if !node.layer.inputs.contains_key(input) {
            let loc = gsrc.locate(&["nodes", &SourceText::quoted(&node.name), "inputs", &SourceText::quoted(input)]);
            let names: Vec<&str> = node.layer.inputs.keys().map(|s| s.as_str()).collect();
            return Err(GraphError::new(ErrorKind::UnknownOutput, loc, format!("layer `{}` has no input `{input}`", node.layer_name))
                .help(format!("its inputs are: {}", if names.is_empty() { "none".into() } else { names.join(", ") })));
        }
    }
    Ok(())
}

/// A constant 1x1 texture holding an input's fallback value, if the layer declares one.
fn fallback_texture(node: &str, input: &str, decl: &ResourceDecl) -> Option<PlannedResource> {
    let ResourceDecl::Texture(t) = decl else { return None };
    let value = t.fallback?;
    let mut t = t.clone();
    t.size = SizeDecl::Absolute(1, 1);
    let mut res = PlannedResource::new(format!("{node}/{input} (fallback)"), ResourceDecl::Texture(t), (1, 1));
    res.constant = Some([value.0, value.1, value.2, value.3]);
    Some(res)
}

/// The error of an input connected to a switched-off node and without a fallback.
fn switched_off_source(gsrc: &SourceText, node: &ResolvedNode, input: &str, src: &str) -> GraphError {
    let name = &node.name;
    let loc = gsrc.locate(&["nodes", &SourceText::quoted(name), "inputs", &SourceText::quoted(input)]);
    GraphError::new(
        ErrorKind::NoProducer,
        loc,
        format!("input `{input}` of node `{name}` comes from node `{src}`, which is switched off, and layer `{}` declares no fallback for it", node.layer_name),
    )
    .help(format!("switch `{src}` on, or give the input a `fallback: Some((r, g, b, a))` in the layer file"))
}

/// The resource that `source` (`"node.output"`) names for input `(name, declaration)` of node
/// `ni`, checked to be of the input's format.
fn source_resource(
    gsrc: &SourceText,
    nodes: &[ResolvedNode],
    ni: usize,
    (input, decl): (&str, &ResourceDecl),
    source: &str,
    resources: &[PlannedResource],
) -> Result<ResourceId, GraphError> {
    let name = &nodes[ni].name;
    let loc = gsrc.locate(&["nodes", &SourceText::quoted(name), "inputs", &SourceText::quoted(input), &SourceText::quoted(source)]);
    let rid = output_resource(nodes, source).ok_or_else(|| unknown_output(source, loc.clone(), nodes))?;
    let produced = &resources[rid].decl;
    let compatible = match (decl, produced) {
        (ResourceDecl::Texture(a), ResourceDecl::Texture(b)) => a.format == b.format && a.layers == b.layers,
        (ResourceDecl::Buffer(a), ResourceDecl::Buffer(b)) => a.size <= b.size,
        (ResourceDecl::Accel, ResourceDecl::Accel) => true,
        _ => false,
    };
    if !compatible {
        return Err(GraphError::new(
            ErrorKind::FormatMismatch,
            loc,
            format!("input `{input}` of node `{name}` expects {}, but `{source}` is {}", describe_decl(decl), describe_decl(produced)),
        )
        .note(nodes[ni].layer_src.locate(&["inputs", &SourceText::quoted(input)]), "the input is declared here")
        .help("connect an output of the expected format, or insert a conversion layer"));
    }
    Ok(rid)
}

/// The resource of an output reference `"node.output"`, if the node has that output.
pub(super) fn output_resource(nodes: &[ResolvedNode], reference: &str) -> Option<ResourceId> {
    let (node, output) = split_ref(reference);
    nodes.iter().find(|n| n.name == node).and_then(|n| n.layer.outputs.get(output).and(n.locals.get(output))).copied()
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
        ResourceDecl::Texture(t) if t.layers > 1 => format!("a {} texture of {} layers", t.format, t.layers),
        ResourceDecl::Texture(t) => format!("a {} texture", t.format),
        ResourceDecl::Buffer(b) => format!("a buffer of {} bytes", b.size),
        ResourceDecl::Accel => "an acceleration structure".into(),
    }
}

fn split_ref(s: &str) -> (&str, &str) {
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
