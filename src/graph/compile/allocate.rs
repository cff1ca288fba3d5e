//! Memory for the kept resources: identical resources (same type, format and size) whose
//! lifetimes do not overlap share one slot.

use crate::graph::desc::*;

pub(super) fn same_shape(a: &ResourceDecl, b: &ResourceDecl) -> bool {
    match (a, b) {
        (ResourceDecl::Texture(x), ResourceDecl::Texture(y)) => x.format == y.format,
        (ResourceDecl::Buffer(x), ResourceDecl::Buffer(y)) => x.size == y.size,
        // One acceleration structure per Accel node: never shared.
        _ => false,
    }
}
