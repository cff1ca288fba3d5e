//! The GPU layout of the two-level BVH that the `compute` back-end's WGSL traverses, and
//! [`flatten`], which turns a [`SceneAccel`] into it.
//!
//! Four storage arrays, all `#[repr(C)]` + [`Pod`], none ever empty:
//!
//! - `blas_nodes: array<GpuBvhNode>`: the BLAS nodes of every BLAS, concatenated.
//! - `triangles: array<GpuTriangle>`: object-space triangles of every BLAS in leaf order.
//! - `tlas_nodes: array<GpuBvhNode>`: the TLAS, root at index 0.
//! - `instances: array<GpuInstance>`: the instances in TLAS leaf order.
//!
//! # Nodes
//!
//! A [`GpuBvhNode`] with `count == 0` is interior: its children are at `left_or_first` and
//! `left_or_first + 1` in the same array. With `count > 0` it is a leaf of `count` primitives
//! starting at `left_or_first`: triangles for a BLAS node, instances for a TLAS node. Every
//! index is absolute into its array. A traversal tests both children's boxes when visiting an
//! interior node (testing the root's box first is an optional early-out). The WGSL reads the
//! arrays as 16-byte words and carries a node as the descriptor `left_or_first << 3 | count`,
//! so `count` is at most 7 (`crate::accel::bvh::MAX_LEAF_LIMIT`) and every array is shorter
//! than `MAX_INDEX` (no descriptor can then equal the WGSL's `NO_HIT`, `0xffffffff`).
//! Node boxes are the exact bounds widened outward by one ulp plus 1e-20 ([`widen_up`]), so
//! that a ray with a zero direction component lying exactly in a face plane still enters the
//! box.
//!
//! # Empty trees
//!
//! An empty BLAS (a mesh with no usable triangle) and an empty TLAS (no usable instance) are a
//! single *leaf* of `count = 1` with the inverted box `min = +f32::MAX`, `max = -f32::MAX`
//! (`EMPTY_BOX_MIN`, `EMPTY_BOX_MAX`). A slab test that picks the near/far plane by the sign
//! of the direction (as [`crate::accel::cpu_traverse`] does) never enters it; one that takes
//! `min`/`max` of the two slab distances (as the WGSL does) sees an unbounded box, and a
//! traversal may not test the root's box at all, so the leaf also points at a primitive that
//! cannot be hit: the empty BLAS at a padding triangle with three
//! zero vertices (`det == 0`, rejected; `prim` = [`NO_PRIM`]), the empty TLAS at a padding
//! instance with `mask = 0`, `instance_id` = [`NO_INSTANCE`] and an empty BLAS. No box holds a
//! NaN.
//!
//! # Instances
//!
//! [`GpuInstance`] matrices are affine 3x4, row-major: row `r` is
//! `[m[r][0], m[r][1], m[r][2], t[r]]`, so `p' = (dot(row0.xyz, p) + row0.w, ...)`. They are
//! computed in f64 and rounded to f32. A ray is moved into object space with `world_to_object`
//! (origin as a point, direction as a vector, not renormalised, so `t` stays the world `t`).

use super::bvh::{instance_transform, mesh_triangle, Aabb, AccelOptions, Blas, Bvh, SceneAccel, Tlas, MAX_TREE_DEPTH};
use crate::scene::{Mesh, Scene};
use bytemuck::{Pod, Zeroable};
use glam::DAffine3;

/// `min` of an empty node's box.
pub(crate) const EMPTY_BOX_MIN: [f32; 3] = [f32::MAX; 3];
/// `max` of an empty node's box.
pub(crate) const EMPTY_BOX_MAX: [f32; 3] = [-f32::MAX; 3];
/// `prim` of the padding triangle.
pub const NO_PRIM: u32 = u32::MAX;
/// `instance_id` of the padding instance.
pub const NO_INSTANCE: u32 = u32::MAX;
/// `mask` of every real instance. The padding instance has 0, and the traversals skip instances
/// with `mask == 0` (a future ray mask would skip `mask & ray_mask == 0`).
pub(crate) const INSTANCE_MASK_ALL: u32 = 0xFF;
/// Bound on the length of every GPU array (29 bits of a traversal descriptor, less one).
pub(crate) const MAX_INDEX: usize = (1 << 29) - 1;

/// Traversal stack entries per ray (nearer-first traversal pushes at most one node per tree
/// level; the WGSL's one stack holds the TLAS's entries and then the BLAS's, the CPU mirror
/// keeps one such stack per level).
pub(crate) const TRAVERSAL_STACK_SIZE: usize = MAX_TREE_DEPTH;

/// A BVH node, 32 bytes. See the module docs for the meaning of `left_or_first` and `count`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default, Pod, Zeroable)]
pub struct GpuBvhNode {
    /// The box's smallest corner.
    pub min: [f32; 3],
    /// Interior: index of the left child; leaf: the first triangle or instance.
    pub left_or_first: u32,
    /// The box's largest corner.
    pub max: [f32; 3],
    /// Triangles or instances of a leaf; 0 for an interior node.
    pub count: u32,
}

/// An object-space triangle, 48 bytes, in BLAS leaf order. `prim` is the triangle's index in
/// its mesh (index / 3). In a merged BLAS ([`merge`]) `instance` is the scene instance the
/// triangle came from and `flags` holds `TRI_MIRRORED` and [`TRI_ALPHA`]; both are 0
/// otherwise.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default, Pod, Zeroable)]
pub struct GpuTriangle {
    /// First vertex.
    pub v0: [f32; 3],
    /// The triangle's index in its mesh.
    pub prim: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// The scene instance of a merged triangle (0 otherwise).
    pub instance: u32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// `TRI_MIRRORED` and [`TRI_ALPHA`] of a merged triangle (0 otherwise).
    pub flags: u32,
}

/// `GpuTriangle::flags` bit: the triangle's instance transform mirrors (negative determinant),
/// so a hit's `front_face` (defined in object space) is the opposite of the world-space winding.
pub(crate) const TRI_MIRRORED: u32 = 1;

/// `GpuTriangle::flags` bit (merged layout): the triangle's instance is alpha-tested
/// ([`crate::accel::alpha`]), so an accepted hit runs the alpha test.
pub const TRI_ALPHA: u32 = 2;

/// `GpuInstance::flags` bit (two-level layout): the instance is alpha-tested, so an accepted
/// hit on its BLAS runs the alpha test.
pub(crate) const INSTANCE_ALPHA: u32 = 1;

/// A merged triangle's flags.
pub(crate) fn merged_flags(o: &TriangleOrigin) -> u32 {
    (if o.mirrored { TRI_MIRRORED } else { 0 }) | if o.alpha { TRI_ALPHA } else { 0 }
}

/// `GpuInstance::instance_id` of the one instance over a merged BLAS: the hit's instance is
/// the triangle's `instance`.
pub(crate) const MERGED_INSTANCE: u32 = 0xFFFF_FFFE;

/// An instance, 112 bytes. Matrices are row-major 3x4 (see the module docs). `blas_root` is the
/// absolute index of its BLAS's root in `blas_nodes`; `instance_id` its index in
/// `Scene::instances`; `flags` holds `INSTANCE_ALPHA`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default, Pod, Zeroable)]
pub struct GpuInstance {
    /// World to object space, row-major 3x4.
    pub world_to_object: [[f32; 4]; 3],
    /// Object to world space, row-major 3x4.
    pub object_to_world: [[f32; 4]; 3],
    /// Absolute index of the BLAS root in `blas_nodes`.
    pub blas_root: u32,
    /// Index in `Scene::instances`.
    pub instance_id: u32,
    /// Visibility mask.
    pub mask: u32,
    /// `INSTANCE_ALPHA` where the instance is alpha-tested.
    pub flags: u32,
}

/// The flattened two-level BVH. Every array has at least one element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GpuAccel {
    /// Every BLAS's nodes, one tree after another.
    pub blas_nodes: Vec<GpuBvhNode>,
    /// Every BLAS's triangles, in leaf order.
    pub triangles: Vec<GpuTriangle>,
    /// The TLAS's nodes.
    pub tlas_nodes: Vec<GpuBvhNode>,
    /// The instances the TLAS leaves index.
    pub instances: Vec<GpuInstance>,
    /// Root of each BLAS in `blas_nodes`: per mesh with de-duplication (the default), per scene
    /// instance without. Host-side bookkeeping (empty for a scene without meshes), not a binding.
    pub blas_roots: Vec<u32>,
}

impl GpuAccel {
    /// Builds both levels for `scene` and flattens them.
    pub fn build(scene: &Scene, opts: &AccelOptions) -> GpuAccel {
        flatten(scene, &SceneAccel::build(scene, opts))
    }

    /// Bytes of the four GPU arrays.
    pub fn byte_size(&self) -> usize {
        std::mem::size_of_val(self.blas_nodes.as_slice())
            + std::mem::size_of_val(self.triangles.as_slice())
            + std::mem::size_of_val(self.tlas_nodes.as_slice())
            + std::mem::size_of_val(self.instances.as_slice())
    }
}

/// The node of an empty tree: a never-entered leaf of one padding primitive at `first`.
pub(crate) fn empty_node(first: u32) -> GpuBvhNode {
    GpuBvhNode { min: EMPTY_BOX_MIN, left_or_first: first, max: EMPTY_BOX_MAX, count: 1 }
}

/// Absolute part of the outward widening of every node box, see [`widen_down`].
pub(crate) const BOX_PAD_ABS: f32 = 1e-20;

/// `x` moved outward (down) by one ulp past `x - BOX_PAD_ABS`. The traversal replaces a zero
/// direction component by `+-2^-80`, which moves a ray that lies exactly in a box face plane by
/// `2^-80 * t` across that plane; widening every box by more than that (for `t < 1e4`) keeps
/// such a ray inside, so it still reaches a triangle edge lying in that plane.
pub fn widen_down(x: f32) -> f32 {
    (x - BOX_PAD_ABS).next_down()
}

/// `x` moved outward (up), the mirror of [`widen_down`].
pub fn widen_up(x: f32) -> f32 {
    (x + BOX_PAD_ABS).next_up()
}

fn box_arrays(b: &Aabb) -> ([f32; 3], [f32; 3]) {
    // Non-empty trees have finite boxes; an empty (or, defensively, non-finite) one becomes the
    // inverted placeholder so that no NaN or infinity reaches the GPU.
    if b.is_empty() || !b.is_finite() {
        (EMPTY_BOX_MIN, EMPTY_BOX_MAX)
    } else {
        let (min, max) = (b.min.to_array().map(widen_down), b.max.to_array().map(widen_up));
        if min.iter().chain(&max).all(|x| x.is_finite()) {
            (min, max)
        } else {
            (b.min.to_array(), b.max.to_array())
        }
    }
}

/// Appends `bvh`'s nodes to `out` with interior indices shifted by `node_base` and leaf indices
/// by `prim_base`.
fn push_nodes(out: &mut Vec<GpuBvhNode>, bvh: &Bvh, node_base: u32, prim_base: u32) {
    out.extend(bvh.nodes.iter().map(|n| {
        let (min, max) = box_arrays(&n.bounds);
        let left_or_first = if n.is_leaf() { n.left_or_first + prim_base } else { n.left_or_first + node_base };
        GpuBvhNode { min, left_or_first, max, count: n.count }
    }));
}

/// Row-major 3x4 rows of an affine map.
pub fn affine_rows(a: &DAffine3) -> [[f32; 4]; 3] {
    let m = a.matrix3;
    let t = a.translation;
    [0, 1, 2].map(|r| [m.x_axis[r] as f32, m.y_axis[r] as f32, m.z_axis[r] as f32, t[r] as f32])
}

/// Flattens `accel` (built from `scene`) into the GPU layout.
pub fn flatten(scene: &Scene, accel: &SceneAccel) -> GpuAccel {
    let mut out = flatten_meshes(scene.meshes(), accel);
    for inst in &mut out.instances {
        if inst.instance_id != NO_INSTANCE && super::alpha::instance_tested(scene, inst.instance_id as usize) {
            inst.flags = INSTANCE_ALPHA;
        }
    }
    out
}

/// [`flatten`] with the meshes the BLASes were built from.
fn flatten_meshes<M: std::borrow::Borrow<Mesh>>(meshes: &[M], accel: &SceneAccel) -> GpuAccel {
    let mut out = GpuAccel::default();
    let mut empty_blas_nodes = Vec::new();
    for (blas, mesh) in accel.blases.iter().zip(&accel.blas_mesh) {
        let node_base = out.blas_nodes.len() as u32;
        out.blas_roots.push(node_base);
        let mesh = mesh.and_then(|m| meshes.get(m)).map(|m| m.borrow());
        match mesh {
            Some(mesh) if !blas.is_empty() => {
                let tri_base = out.triangles.len() as u32;
                push_nodes(&mut out.blas_nodes, &blas.bvh, node_base, tri_base);
                out.triangles.extend(blas.bvh.prim_order.iter().map(|&prim| {
                    // The mesh is the one the BLAS was built from; a bad index (a mesh edited
                    // behind our back) becomes a zero, never-hit triangle.
                    let v = mesh_triangle(mesh, prim as usize).unwrap_or([glam::Vec3::ZERO; 3]);
                    GpuTriangle { v0: v[0].to_array(), prim, v1: v[1].to_array(), instance: 0, v2: v[2].to_array(), flags: 0 }
                }));
            }
            _ => {
                empty_blas_nodes.push(node_base as usize);
                out.blas_nodes.push(empty_node(0));
            }
        }
    }

    // TLAS.
    let tlas = &accel.tlas.bvh;
    if !tlas.is_empty() {
        push_nodes(&mut out.tlas_nodes, tlas, 0, 0);
        for &i in &tlas.prim_order {
            let i = i as usize;
            let root = accel.instance_blas.get(i).copied().flatten().and_then(|b| out.blas_roots.get(b as usize).copied());
            match (accel.instance_transforms.get(i).copied().flatten(), root) {
                (Some(xf), Some(root)) => out.instances.push(GpuInstance {
                    world_to_object: affine_rows(&xf.inverse()),
                    object_to_world: affine_rows(&xf),
                    blas_root: root,
                    instance_id: i as u32,
                    mask: INSTANCE_MASK_ALL,
                    flags: 0,
                }),
                // Unreachable for an accel built from `scene`; keep the slot as padding.
                _ => {
                    let pad = padding_instance(&mut out, &mut empty_blas_nodes);
                    out.instances.push(pad);
                }
            }
        }
    } else {
        out.tlas_nodes.push(empty_node(0));
        let pad = padding_instance(&mut out, &mut empty_blas_nodes);
        out.instances.push(pad);
    }

    // The padding triangle for the empty BLAS leaves (and so that `triangles` is never empty).
    if !empty_blas_nodes.is_empty() || out.triangles.is_empty() {
        let pad = out.triangles.len() as u32;
        out.triangles.push(GpuTriangle { prim: NO_PRIM, ..Default::default() });
        for n in empty_blas_nodes {
            out.blas_nodes[n].left_or_first = pad;
        }
    }
    // The WGSL keeps one stack for both levels: a BLAS's entries go on top of the TLAS's.
    let depth = accel.blases.iter().map(|b| b.bvh.depth()).max().unwrap_or(0) + tlas.depth();
    if depth >= TRAVERSAL_STACK_SIZE {
        log::warn!("accel: TLAS and BLAS together are {depth} levels deep; the {TRAVERSAL_STACK_SIZE}-entry traversal stack may overflow and miss hits");
    }
    out
}

/// A never-hit instance pointing at an empty BLAS (appended if there is none yet).
fn padding_instance(out: &mut GpuAccel, empty_blas_nodes: &mut Vec<usize>) -> GpuInstance {
    let root = match empty_blas_nodes.first() {
        Some(&n) => n as u32,
        None => {
            let n = out.blas_nodes.len();
            out.blas_nodes.push(empty_node(0));
            empty_blas_nodes.push(n);
            n as u32
        }
    };
    let identity = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
    GpuInstance { world_to_object: identity, object_to_world: identity, blas_root: root, instance_id: NO_INSTANCE, mask: 0, flags: 0 }
}

/// Where a triangle of a merged mesh came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriangleOrigin {
    /// The scene instance.
    pub instance: u32,
    /// The triangle's index in the instance's mesh.
    pub prim: u32,
    /// The instance's transform mirrors (the winding flips).
    pub mirrored: bool,
    /// The instance is alpha-tested ([`TRI_ALPHA`]).
    pub alpha: bool,
}

/// All instances' triangles in world space as one mesh: the merged layout of a static scene,
/// where a ray traverses one BVH instead of every instance whose box it crosses. Positions are
/// transformed in f64 and rounded once, so a vertex shared by two triangles of an instance
/// stays shared (the watertight test needs that). Instances with an unusable transform or mesh
/// are left out; a triangle with an out-of-range index keeps an out-of-range index.
pub fn merge_instances(scene: &Scene) -> (Mesh, Vec<TriangleOrigin>) {
    let mut mesh = Mesh { name: format!("{} (merged)", scene.name()), vertices: Vec::new(), indices: Vec::new(), tangents: None, extras: None };
    let mut origin = Vec::new();
    for (i, inst) in scene.instances().iter().enumerate() {
        let (Some(src), Some(xf)) = (scene.meshes().get(inst.mesh), instance_transform(&inst.transform)) else { continue };
        let base = mesh.vertices.len() as u64;
        mesh.vertices.extend(src.vertices.iter().map(|v| {
            let p = xf.transform_point3(glam::DVec3::from(v.position.map(f64::from)));
            crate::scene::Vertex { position: p.as_vec3().to_array(), ..*v }
        }));
        let mirrored = xf.matrix3.determinant() < 0.0;
        let alpha = super::alpha::instance_tested(scene, i);
        for (t, tri) in src.indices.chunks_exact(3).enumerate() {
            let in_range = tri.iter().all(|&k| (k as usize) < src.vertices.len());
            mesh.indices.extend(tri.iter().map(|&k| if in_range { u32::try_from(base + k as u64).unwrap_or(u32::MAX) } else { u32::MAX }));
            origin.push(TriangleOrigin { instance: i as u32, prim: t as u32, mirrored, alpha });
        }
    }
    (mesh, origin)
}

/// The merged layout around a BLAS built elsewhere (the GPU builder): `blas_nodes` (root at 0)
/// and `triangles` in its leaf order under a one-leaf TLAS with the root's box and the one
/// identity instance [`merge`] makes.
pub fn merged_accel(blas_nodes: Vec<GpuBvhNode>, triangles: Vec<GpuTriangle>) -> GpuAccel {
    let root = blas_nodes.first().copied().unwrap_or_else(|| empty_node(0));
    let identity = affine_rows(&DAffine3::IDENTITY);
    GpuAccel {
        tlas_nodes: vec![GpuBvhNode { min: root.min, left_or_first: 0, max: root.max, count: 1 }],
        instances: vec![GpuInstance {
            world_to_object: identity,
            object_to_world: identity,
            blas_root: 0,
            instance_id: MERGED_INSTANCE,
            mask: INSTANCE_MASK_ALL,
            flags: 0,
        }],
        blas_nodes,
        triangles,
        blas_roots: vec![0],
    }
}

/// The GPU layout of a merged scene: one BLAS over [`merge_instances`]'s mesh under a TLAS of
/// one identity instance (`MERGED_INSTANCE`), each triangle carrying its scene instance.
pub fn merge(merged: &Mesh, origin: &[TriangleOrigin], blas: Blas) -> GpuAccel {
    let bounds = blas.bounds();
    let usable = !blas.is_empty();
    let accel = SceneAccel {
        blases: vec![blas],
        blas_mesh: vec![Some(0)],
        instance_blas: vec![usable.then_some(0)],
        instance_transforms: vec![usable.then_some(DAffine3::IDENTITY)],
        tlas: Tlas::build(&[if usable { bounds } else { Aabb::EMPTY }], &crate::accel::bvh::BuildConfig::default()),
        dedup: true,
        build_time: std::time::Duration::ZERO,
    };
    let mut out = flatten_meshes(std::slice::from_ref(merged), &accel);
    if usable {
        out.instances[0].instance_id = MERGED_INSTANCE;
    }
    for tri in &mut out.triangles {
        if let Some(o) = origin.get(tri.prim as usize) {
            tri.prim = o.prim;
            tri.instance = o.instance;
            tri.flags = merged_flags(o);
        }
    }
    out
}
