//! The kept passes as the plan lists them: each a [`PlannedPass`] in execution order, each
//! resource's first and last use and its usage flags, and the parts of the scene the passes
//! draw or bind.

use super::interface::entry_name;
use super::plan::{PlannedPass, PlannedResource, ResourceId};
use super::resolve::ResolvedNode;
use super::schedule::{pass_name, PassNode};
use crate::graph::desc::*;
use crate::graph::reflect::ShaderInfo;
use crate::scene::usage::SceneUsage;
use std::collections::HashMap;
use std::sync::Arc;

/// The kept passes (`kept`, indices into `passes` in execution order) with their shaders and
/// settings.
pub(super) fn planned_passes(kept: &[usize], nodes: &[ResolvedNode], passes: &[PassNode], shaders: &[Arc<ShaderInfo>]) -> Vec<PlannedPass> {
    kept.iter()
        .map(|&pi| {
            let p = &passes[pi];
            let node = &nodes[p.node];
            let pass = &node.layer.passes[p.index];
            PlannedPass {
                name: pass_name(nodes, p),
                node: node.name.clone(),
                kind: pass.kind,
                entry: entry_name(pass),
                vertex_entry: pass.vertex_entry.clone().unwrap_or_else(|| "vs_main".into()),
                shader: shaders[pi].clone(),
                reads: p.reads.clone(),
                writes: p.writes.clone(),
                dispatch: pass.dispatch,
                cull_back_faces: pass.cull_back_faces,
                cull_closed_back_faces: pass.cull_closed_back_faces,
                shadow_slot: pass.shadow_slot,
                shadow_tiles: pass.shadow_tiles,
                layer: pass.layer,
                skip_blend: pass.skip_blend,
                translucent: pass.translucent,
                runs_when: pass.runs_when.clone().zip(p.runs_when),
                accel: node.accel.clone(),
                params: node.params.clone(),
                location: p.location.clone(),
            }
        })
        .collect()
}

/// Sets each resource's usage flags and its first and last use (indices into `planned`); the
/// outputs (`output` and the HDR output `hdr`) live to the last pass and can be copied out.
/// Returns the resources some kept pass uses.
pub(super) fn set_lifetimes_and_usage(
    planned: &[PlannedPass],
    resources: &mut [PlannedResource],
    output: ResourceId,
    hdr: Option<ResourceId>,
) -> Vec<ResourceId> {
    let mut first: HashMap<ResourceId, usize> = HashMap::new();
    let mut last: HashMap<ResourceId, usize> = HashMap::new();
    for (order, pass) in planned.iter().enumerate() {
        for (_, r) in pass.reads.iter().chain(&pass.writes) {
            first.entry(*r).or_insert(order);
            last.insert(*r, order);
        }
        for (_, r) in &pass.reads {
            resources[*r].usage.sampled = true;
            if matches!(resources[*r].decl, ResourceDecl::Buffer(_)) {
                resources[*r].usage.storage = true;
            }
        }
        for (_, r) in &pass.writes {
            match pass.kind {
                PassKind::Compute | PassKind::Trace => resources[*r].usage.storage = true,
                PassKind::AccelBuild => {}
                _ => resources[*r].usage.attachment = true,
            }
        }
    }
    // The counts of `runs_when` are copied out after the last pass: no resource shares them.
    let counts = planned.iter().filter_map(|p| p.runs_when.as_ref().map(|(_, r)| *r)).filter(|r| first.contains_key(r));
    for r in std::iter::once(output).chain(hdr).chain(counts.collect::<Vec<_>>()) {
        resources[r].usage.copy_src = true;
        last.insert(r, planned.len().saturating_sub(1));
    }
    // A used history and the resource it keeps trade textures every frame: both live from
    // frame to frame, with the usages of either.
    for h in 0..resources.len() {
        if let (Some(source), true) = (resources[h].history_of, first.contains_key(&h)) {
            let usage = resources[h].usage.union(resources[source].usage);
            for r in [h, source] {
                resources[r].persistent = true;
                resources[r].usage = usage;
            }
        }
    }
    for (r, res) in resources.iter_mut().enumerate() {
        if let (Some(f), Some(l)) = (first.get(&r), last.get(&r)) {
            res.first_use = *f;
            res.last_use = *l;
        }
    }
    (0..resources.len()).filter(|r| first.contains_key(r)).collect()
}

/// Which parts of the scene the kept passes draw (`SceneRaster` passes) or bind.
pub(super) fn scene_usage(planned: &[PlannedPass]) -> SceneUsage {
    let mut usage = SceneUsage::default();
    for pass in planned {
        usage.geometry |= pass.kind == PassKind::SceneRaster;
        usage.closed_meshes |= pass.cull_closed_back_faces;
        for b in &pass.shader.bindings {
            usage.add_binding(b);
        }
    }
    usage
}
