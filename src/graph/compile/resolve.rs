//! Resolving the graph's nodes: each layer node's layer file read and its parameters checked
//! (graph values, then the options' overrides), each `Accel` node made a one-pass built-in
//! layer, and at most one `Accel` node per graph.

use super::options::Project;
use super::plan::ResourceId;
use super::source::{parse_ron, read_file, SourceText};
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

pub(super) struct ResolvedNode {
    pub(super) name: String,
    pub(super) layer_name: String,
    pub(super) layer: LayerDesc,
    pub(super) layer_src: SourceText,
    pub(super) params: BTreeMap<String, (ParamDecl, ParamValue)>,
    /// local name -> resource id (filled in phase 3)
    pub(super) locals: HashMap<String, ResourceId>,
    /// An `Accel` node's settings.
    pub(super) accel: Option<AccelNode>,
}

/// Switches layer nodes on or off as the options say (`CompileOptions::enabled`).
pub(super) fn apply_switches(graph: &mut GraphDesc, enabled: &BTreeMap<String, bool>, graph_file: &Path) -> Result<(), GraphError> {
    for (node, on) in enabled {
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
    Ok(())
}

/// Each node's layer file read and checked (a layer the device substitutes, `layers`, read from
/// its substitute's file), and its parameters set from the graph file; an `Accel` node becomes
/// its built-in layer. Switched-off nodes are left out.
pub(super) fn resolve_layers(
    graph: &GraphDesc,
    gsrc: &SourceText,
    project: &Project,
    layers: &BTreeMap<String, String>,
) -> Result<Vec<ResolvedNode>, GraphError> {
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
        let (layer_name, path) = layer_file(project, layers, &ln.layer);
        if !crate::graph::files::exists(&path) {
            let loc = gsrc.locate(&["nodes", &node_anchor, &SourceText::quoted(&ln.layer)]);
            let known = crate::graph::files::ron_stems(&project.layers_dir);
            return Err(GraphError::new(ErrorKind::UnknownLayer, loc, format!("unknown layer `{}`: there is no file {}", ln.layer, path.display()))
                .help(format!("use one of the layers in {}: {}", project.layers_dir.display(), known.join(", "))));
        }
        let layer_src = read_file(&path, None)?;
        let layer: LayerDesc = parse_ron(&layer_src, "layer")?;
        check_declarations(&layer, &layer_src)?;
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
        out.push(ResolvedNode { name: name.clone(), layer_name: layer_name.clone(), layer, layer_src, params, locals: HashMap::new(), accel: None });
    }
    Ok(out)
}

/// The most array layers a texture may declare: the least every device allows
/// (`wgpu::Limits::max_texture_array_layers`'s default).
const MAX_TEXTURE_LAYERS: u32 = 256;

/// A layer file's own declarations: each enum parameter's default one of its values, each
/// texture of 1 to `MAX_TEXTURE_LAYERS` layers.
fn check_declarations(layer: &LayerDesc, layer_src: &SourceText) -> Result<(), GraphError> {
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
    let declared = [("inputs", &layer.inputs), ("outputs", &layer.outputs), ("transients", &layer.transients)];
    for (section, decls) in declared {
        for (name, decl) in decls.iter() {
            if let ResourceDecl::Texture(t) = decl {
                if t.layers == 0 || t.layers > MAX_TEXTURE_LAYERS {
                    let loc = layer_src.locate(&[section, &SourceText::quoted(name)]);
                    return Err(GraphError::new(ErrorKind::Syntax, loc, format!("texture `{name}` declares {} layers", t.layers))
                        .help(format!("declare 1 to {MAX_TEXTURE_LAYERS} layers")));
                }
            }
        }
    }
    Ok(())
}

/// The layer a node names (or the device's substitute for it, `layers`) and its file.
pub(super) fn layer_file<'a>(project: &Project, layers: &'a BTreeMap<String, String>, layer: &'a String) -> (&'a String, std::path::PathBuf) {
    let name = layers.get(layer).unwrap_or(layer);
    (name, project.layers_dir.join(format!("{name}.ron")))
}

/// A graph has at most one `Accel` node: the runtime keeps one acceleration-structure cache per
/// graph (one scene, one set of ray counters), so a second node's settings would be dropped.
pub(super) fn check_one_accel(graph: &GraphDesc, gsrc: &SourceText) -> Result<(), GraphError> {
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
        history: BTreeMap::new(),
        bypass: BTreeMap::new(),
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
            cull_closed_back_faces: false,
            shadow_slot: None,
            shadow_tiles: None,
            layer: None,
            skip_blend: false,
            translucent: false,
            runs_when: None,
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

/// Sets the parameter values the options override (`CompileOptions::params`), checked like the
/// graph file's own.
pub(super) fn apply_param_overrides(
    nodes: &mut [ResolvedNode],
    overrides: &BTreeMap<(String, String), ParamValue>,
    graph_file: &Path,
) -> Result<(), GraphError> {
    for ((node, param), value) in overrides {
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
    Ok(())
}

type ParamProblem = (ErrorKind, String, String);

/// Checks a value against its declaration; ints are accepted where floats are expected.
pub(crate) fn check_param(decl: &ParamDecl, value: ParamValue) -> Result<ParamValue, ParamProblem> {
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
