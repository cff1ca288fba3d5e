//! Bypasses of switched-off nodes. An input (or the graph's output or HDR output) that names an output of a
//! switched-off node, whose layer declares a `bypass` for that output, is reconnected to what
//! feeds the node's bypassed input, through chains of switched-off filters: switching off a
//! denoiser hands its readers the noisy signal. Runs on the graph description before the
//! layers of the switched-on nodes are resolved, so the later phases never see the detour.

use super::options::Project;
use super::source::{parse_ron, read_file, SourceText};
use crate::error::{ErrorKind, GraphError};
use crate::graph::desc::*;
use std::collections::BTreeMap;

/// Node -> (output -> input) for every switched-off node whose layer passes outputs through.
type Bypasses = BTreeMap<String, BTreeMap<String, String>>;

/// Reconnects every reader of a bypassed output of a switched-off node (see the module doc).
/// `layers` maps a layer to the device's substitute, as for the switched-on nodes.
pub(super) fn apply_bypasses(graph: &mut GraphDesc, project: &Project, layers: &BTreeMap<String, String>) -> Result<(), GraphError> {
    let bypasses = switched_off_bypasses(graph, project, layers)?;
    if bypasses.is_empty() {
        return Ok(());
    }
    let mut rewrites = Vec::new();
    for (name, node) in &graph.nodes {
        let NodeDesc::Layer(ln) = node else { continue };
        if !ln.enabled {
            continue;
        }
        for (input, source) in &ln.inputs {
            if let Some(routed) = follow(graph, &bypasses, source) {
                rewrites.push((name.clone(), input.clone(), routed));
            }
        }
    }
    for (name, input, routed) in rewrites {
        if let Some(NodeDesc::Layer(ln)) = graph.nodes.get_mut(&name) {
            ln.inputs.insert(input, routed);
        }
    }
    if let Some(routed) = follow(graph, &bypasses, &graph.output) {
        graph.output = routed;
    }
    if let Some(routed) = graph.hdr_output.as_ref().and_then(|hdr| follow(graph, &bypasses, hdr)) {
        graph.hdr_output = Some(routed);
    }
    Ok(())
}

/// Where `source` (`"node.output"`) leads once every bypass on its way is taken; `None` when
/// it takes none. A bypassed input left unconnected ends the way at the switched-off node,
/// whose readers then get their fallback as without a bypass.
fn follow(graph: &GraphDesc, bypasses: &Bypasses, source: &str) -> Option<String> {
    let mut current = source.to_string();
    // A way visits each node at most once, unless switched-off nodes feed each other in a
    // cycle, which the bound ends.
    for _ in 0..=graph.nodes.len() {
        let (node, output) = current.split_once('.').unwrap_or((&current, ""));
        let Some(input) = bypasses.get(node).and_then(|b| b.get(output)) else { break };
        let Some(NodeDesc::Layer(ln)) = graph.nodes.get(node) else { break };
        let Some(next) = ln.inputs.get(input) else { break };
        current = next.clone();
    }
    (current != source).then_some(current)
}

/// The bypasses of the switched-off nodes whose layer files exist; each is checked.
fn switched_off_bypasses(graph: &GraphDesc, project: &Project, layers: &BTreeMap<String, String>) -> Result<Bypasses, GraphError> {
    let mut out = Bypasses::new();
    for (name, node) in &graph.nodes {
        let NodeDesc::Layer(ln) = node else { continue };
        if ln.enabled {
            continue;
        }
        let (layer_name, path) = super::resolve::layer_file(project, layers, &ln.layer);
        if !crate::graph::files::exists(&path) {
            continue; // a switched-off node's layer is not required to exist
        }
        let src = read_file(&path, None)?;
        let layer: LayerDesc = parse_ron(&src, "layer")?;
        check_bypass(&layer, &src, layer_name)?;
        if !layer.bypass.is_empty() {
            out.insert(name.clone(), layer.bypass);
        }
    }
    Ok(out)
}

/// Every bypass of a layer joins one of its outputs to one of its inputs, both textures of one
/// format.
pub(super) fn check_bypass(layer: &LayerDesc, src: &SourceText, layer_name: &str) -> Result<(), GraphError> {
    for (output, input) in &layer.bypass {
        let at = src.locate(&["bypass", &SourceText::quoted(output)]);
        let (Some(out_decl), Some(in_decl)) = (layer.outputs.get(output), layer.inputs.get(input)) else {
            let outputs: Vec<&str> = layer.outputs.keys().map(|s| s.as_str()).collect();
            let inputs: Vec<&str> = layer.inputs.keys().map(|s| s.as_str()).collect();
            return Err(GraphError::new(
                ErrorKind::UnknownOutput,
                at,
                format!("bypass `{output}` -> `{input}` of layer `{layer_name}`: it must join an output of the layer to an input"),
            )
            .help(format!("outputs: {}; inputs: {}", outputs.join(", "), inputs.join(", "))));
        };
        let same_texture = matches!((out_decl, in_decl), (ResourceDecl::Texture(a), ResourceDecl::Texture(b)) if a.format == b.format);
        if !same_texture {
            return Err(GraphError::new(
                ErrorKind::FormatMismatch,
                at,
                format!("bypass `{output}` -> `{input}` of layer `{layer_name}` joins {out_decl} to {in_decl}: a bypass passes a texture through unchanged"),
            )
            .help("bypass an output with an input texture of the same format"));
        }
    }
    Ok(())
}
