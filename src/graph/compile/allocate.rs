//! Memory for the kept resources: identical resources (same type, format and size) whose
//! lifetimes do not overlap share one slot (greedy interval packing, in order of first use;
//! off with `CompileOptions { reuse: false }`); constant textures, history resources and the
//! resources they keep never share.

use super::plan::{PlannedResource, ResourceId, Slot, Usage};
use crate::graph::desc::*;

/// Gives each resource of `used` a slot, shared where `reuse` allows, and returns the slots;
/// resources nobody uses get none.
pub(super) fn allocate_slots(resources: &mut [PlannedResource], mut used: Vec<ResourceId>, reuse: bool) -> Vec<Slot> {
    let mut slots: Vec<Slot> = Vec::new();
    used.sort_by_key(|r| (resources[*r].first_use, *r));
    for r in used {
        let res = &resources[r];
        let fits = slots.iter().position(|s| {
            reuse
                && res.constant.is_none()
                && s.constant.is_none()
                && !res.persistent
                && s.members.iter().all(|m| !resources[*m].persistent)
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
    slots
}

/// Whether two resources could share memory: textures of one format, buffers of one size.
fn same_shape(a: &ResourceDecl, b: &ResourceDecl) -> bool {
    match (a, b) {
        (ResourceDecl::Texture(x), ResourceDecl::Texture(y)) => x.format == y.format && x.layers == y.layers,
        (ResourceDecl::Buffer(x), ResourceDecl::Buffer(y)) => x.size == y.size,
        // One acceleration structure per Accel node: never shared.
        _ => false,
    }
}
