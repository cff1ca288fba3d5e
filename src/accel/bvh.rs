//! Binned-SAH BVH builder (parallel with rayon), SAH cost, refit, and the two levels built
//! with it: [`Blas`] (one per mesh, over its triangles, in object space) and [`Tlas`] (over
//! the instances' world-space boxes), tied together by [`SceneAccel`].
//!
//! # Tree shape
//!
//! A [`Bvh`] is a flat array of [`BvhNode`]s with the root at index 0. An interior node has
//! `count == 0` and its two children at `left_or_first` and `left_or_first + 1` (siblings are
//! adjacent, and a child's index is always greater than its parent's); a leaf has
//! `1 <= count <= max_leaf_size` primitives starting at `left_or_first` in
//! [`Bvh::prim_order`]. An empty input gives a tree with no nodes at all (the GPU layout turns
//! that into a never-hit placeholder, see [`crate::accel::layout`]).
//!
//! # Splitting
//!
//! Each node bins its primitives' *centroids* into [`BuildConfig::bins`] equal-width bins on
//! each of the three axes and evaluates the surface-area heuristic at every bin boundary:
//!
//! ```text
//! cost(split) = C_trav * A(node) + C_isect * (A(left) * N(left) + A(right) * N(right))
//! cost(leaf)  = C_isect * A(node) * N(node)
//! ```
//!
//! with `TRAVERSAL_COST` `C_trav = 1` and `INTERSECTION_COST` `C_isect = 1` (a box test and
//! a primitive test cost about the same in a compute-shader traversal; only the ratio matters).
//! A node becomes a leaf when it holds at most `max_leaf_size` (4) primitives and the leaf is no
//! more expensive than the best split. Nodes of at least `FINE_BINNING_PRIMS` primitives use
//! `bins` (48) bins, smaller nodes at most `SMALL_NODE_BINS` (16), and nodes of fewer
//! primitives than that as many bins as primitives: the large nodes near the root decide most
//! of the tree's cost, and there are few of them. Nodes of at most `EXACT_SPLIT_PRIMS` (8)
//! primitives, most nodes of a tree, skip the bins and evaluate every object split (primitives
//! sorted by centroid on each axis). When all centroids coincide, and for every node at depth
//! `MEDIAN_FALLBACK_DEPTH` (24) or deeper, the node is split at the object median of its
//! longest centroid axis instead. That bounds the split tree's depth by
//! `24 + ceil(log2(n / 4))`: 46 for 2^24 primitives, 54 for 2^32, so a traversal stack of
//! [`MAX_TREE_DEPTH`] (64) entries always suffices. (SAH trees of real scenes are far
//! shallower: the 262k triangles of the atrium in one BLAS are 24 deep.)
//!
//! # Reinsertion
//!
//! A binned-SAH tree is then optimised by [`BuildConfig::reinsertion_passes`] (2) passes of
//! [`crate::accel::reinsert`]: subtrees move to where they lower the SAH cost (the atrium's by
//! 4.6%). Leaves keep their primitives and the node count stays; the layout is the one above.
//! Moves can deepen the tree (the atrium's to 28 levels), but none that would reach
//! [`MAX_TREE_DEPTH`] is made, so the 64-entry stack still suffices (a 48-entry one no longer
//! does for every input).
//!
//! Subtrees with at least [`BuildConfig::parallel_threshold`] primitives are built with
//! `rayon::join` and concatenated; smaller ones are built sequentially into one array. Nodes of
//! more than 16k primitives also bin in parallel, and [`SceneAccel::build`] builds the BLASes of
//! all meshes in parallel. A node touches its primitives twice (bin, partition): the partition
//! measures each side's centroid bounds on the way, and each side's box is the union of its
//! bins' boxes. Work items are 32 bytes (box corners, the id in a spare lane), and the node
//! array is written once at the end rather than concatenated at every parallel level.
//!
//! Measured on the 2-core development machine (`raygraph bench build`, `cpu_build.md`; PERF.md
//! "Builds"): all 262k instanced triangles of the atrium baked into one BLAS in 68–76 ms
//! (median of 9, after a first build), before reinsertion; its two passes take about 120 ms more
//! (about 1.4 s more for the 1.9M triangles of the helmet copied 5×5×5).

use crate::accel::reinsert::{self, Bounds, TreeNode};
use crate::scene::{Mesh, Scene};
use glam::{DAffine3, DMat3, DVec3, Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;
use std::time::Duration;
use web_time::Instant;

/// SAH cost of visiting an interior node (testing its two children's boxes).
pub(crate) const TRAVERSAL_COST: f32 = 1.0;
/// SAH cost of one ray-primitive test.
pub(crate) const INTERSECTION_COST: f32 = 1.0;
/// Default maximum number of primitives in a leaf.
pub(crate) const MAX_LEAF_SIZE: usize = 4;
/// Largest `max_leaf_size` the builder accepts: the GPU traversal packs a node's primitive
/// count into 3 bits (see `crate::accel::layout`).
pub(crate) const MAX_LEAF_LIMIT: usize = 7;
/// Default number of SAH bins per axis of nodes of at least [`FINE_BINNING_PRIMS`] primitives.
pub(crate) const DEFAULT_BINS: usize = 48;
/// Most SAH bins per axis of a node of fewer than [`FINE_BINNING_PRIMS`] primitives.
pub(crate) const SMALL_NODE_BINS: usize = 16;
/// Nodes of at least this many primitives get all of [`BuildConfig::bins`].
pub(crate) const FINE_BINNING_PRIMS: usize = 1024;
/// Nodes at this depth or deeper are split at the object median instead of by SAH.
pub(crate) const MEDIAN_FALLBACK_DEPTH: usize = 24;
/// Default [`BuildConfig::reinsertion_passes`].
pub(crate) const REINSERTION_PASSES: usize = 2;
/// Upper bound on the depth (root = 0) of any tree this builder makes; a nearer-first
/// traversal pushes at most one node per level, so a stack of this many entries suffices.
pub const MAX_TREE_DEPTH: usize = 64;

/// An axis-aligned box. The empty box has `min = +inf`, `max = -inf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The smallest corner.
    pub(crate) min: Vec3,
    /// The largest corner.
    pub(crate) max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box: growing it by a point gives that point.
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// The box from `min` to `max`.
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The box of `points`; [`Aabb::EMPTY`] if any coordinate is not finite.
    pub fn from_points(points: &[Vec3]) -> Self {
        let mut b = Aabb::EMPTY;
        for p in points {
            if !p.is_finite() {
                return Aabb::EMPTY;
            }
            b.grow(*p);
        }
        b
    }

    /// True if the box contains no point (min > max on some axis, or NaN).
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// Whether both corners are finite.
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// Grows the box to contain `p`.
    pub(crate) fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The box containing both.
    pub(crate) fn union(&self, o: &Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// The centre point.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area; 0 for an empty box.
    pub(crate) fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.max - self.min;
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// True if `o` lies inside `self` (an empty `o` lies inside anything).
    pub fn contains(&self, o: &Aabb) -> bool {
        o.is_empty() || (self.min.cmple(o.min).all() && o.max.cmple(self.max).all())
    }
}

/// One primitive handed to the builder: its box (binned by its centre) and an id that the
/// builder carries into [`Bvh::prim_order`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildPrim {
    /// The primitive's box.
    pub bounds: Aabb,
    /// The id the builder carries into [`Bvh::prim_order`].
    pub id: u32,
}

impl BuildPrim {
    /// A primitive from its box and id.
    pub fn new(bounds: Aabb, id: u32) -> Self {
        Self { bounds, id }
    }
}

/// How nodes are split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplitMethod {
    /// Binned surface-area heuristic (the default).
    BinnedSah,
    /// Object median of the longest centroid axis (a naive baseline for comparisons).
    Median,
}

/// Builder settings.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildConfig {
    /// How nodes are split.
    pub method: SplitMethod,
    /// SAH bins per axis of nodes of at least `FINE_BINNING_PRIMS` primitives (clamped to
    /// 2..=`MAX_BINS`); smaller nodes use at most `SMALL_NODE_BINS` of them.
    pub bins: usize,
    /// Maximum primitives per leaf (clamped to 1..=`MAX_LEAF_LIMIT`).
    pub max_leaf_size: usize,
    /// Subtrees with at least this many primitives are built in parallel.
    pub parallel_threshold: usize,
    /// Most passes of the insertion-based optimisation after a binned-SAH build
    /// ([`crate::accel::reinsert`]); 0 keeps the tree as split. The median split is never
    /// optimised (it is the naive baseline).
    pub reinsertion_passes: usize,
}

impl Default for BuildConfig {
    fn default() -> Self {
        Self {
            method: SplitMethod::BinnedSah,
            bins: DEFAULT_BINS,
            max_leaf_size: MAX_LEAF_SIZE,
            parallel_threshold: 4096,
            reinsertion_passes: REINSERTION_PASSES,
        }
    }
}

/// A BVH node (CPU form of [`crate::accel::layout::GpuBvhNode`], with indices local to its
/// tree): interior if `count == 0` (children at `left_or_first`, `left_or_first + 1`), else a
/// leaf of `count` primitives from `left_or_first` in [`Bvh::prim_order`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BvhNode {
    /// The node's box.
    pub bounds: Aabb,
    /// Interior: index of the left child (the right one follows); leaf: first entry in [`Bvh::prim_order`].
    pub left_or_first: u32,
    /// Primitives of a leaf; 0 for an interior node.
    pub count: u32,
}

impl BvhNode {
    /// Whether the node is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A built tree: nodes (root at 0; empty if there were no usable primitives) and the ids of
/// the primitives in leaf order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    /// The nodes, root first.
    pub nodes: Vec<BvhNode>,
    /// Primitive ids in leaf order.
    pub prim_order: Vec<u32>,
}

impl Bvh {
    /// Builds a tree over `prims`. Primitives whose box is empty or not finite, or whose
    /// centre is not finite (the box spans more than `f32::MAX`), are left out (callers filter
    /// them first and count them).
    pub fn build(prims: &[BuildPrim], cfg: &BuildConfig) -> Bvh {
        let work: Vec<Work> = prims.iter().filter(|p| Work::usable(&p.bounds)).map(|p| Work::new(&p.bounds, p.id)).collect();
        Self::build_work(work, cfg)
    }

    /// [`Self::build`] over primitives already filtered by [`Work::usable`].
    fn build_work(mut work: Vec<Work>, cfg: &BuildConfig) -> Bvh {
        if work.is_empty() {
            return Bvh::default();
        }
        let cfg = BuildConfig {
            method: cfg.method,
            bins: cfg.bins.clamp(2, MAX_BINS),
            max_leaf_size: cfg.max_leaf_size.clamp(1, MAX_LEAF_LIMIT),
            parallel_threshold: cfg.parallel_threshold.max(2),
            reinsertion_passes: cfg.reinsertion_passes,
        };
        let (bounds, centroids) = union_bounds_par(&work, &cfg);
        let nodes = build_subtree(&mut work, 0, 0, &cfg, bounds, centroids).into_nodes();
        let built = Bvh { nodes, prim_order: work.iter().map(Work::id).collect() };
        match cfg.method {
            SplitMethod::BinnedSah => built.reinserted(cfg.reinsertion_passes),
            SplitMethod::Median => built,
        }
    }

    /// The tree after at most `passes` passes of [`crate::accel::reinsert`], leaves and their
    /// primitives moved along; as it is if that is not cheaper or reaches [`MAX_TREE_DEPTH`].
    fn reinserted(self, passes: usize) -> Bvh {
        let input: Vec<TreeNode> = self
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| TreeNode {
                bounds: Bounds { min: n.bounds.min, max: n.bounds.max },
                first_child: (!n.is_leaf()).then_some(n.left_or_first),
                source: i as u32,
            })
            .collect();
        let Some(order) = reinsert::optimize(&input, passes, MAX_TREE_DEPTH) else { return self };
        let mut prim_order = Vec::with_capacity(self.prim_order.len());
        let mut node_of = |t: &TreeNode| match t.first_child {
            Some(first) => BvhNode { bounds: Aabb::new(t.bounds.min, t.bounds.max), left_or_first: first, count: 0 },
            None => {
                let leaf = self.nodes[t.source as usize];
                let first = leaf.left_or_first as usize;
                let at = prim_order.len() as u32;
                prim_order.extend_from_slice(&self.prim_order[first..first + leaf.count as usize]);
                BvhNode { left_or_first: at, ..leaf }
            }
        };
        let nodes = order.iter().map(&mut node_of).collect();
        let optimized = Bvh { nodes, prim_order };
        if optimized.depth() < MAX_TREE_DEPTH && optimized.sah_cost() <= self.sah_cost() {
            optimized
        } else {
            self
        }
    }

    /// Whether the tree has no nodes (no usable primitives).
    pub(crate) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Bounds of the root; [`Aabb::EMPTY`] for an empty tree.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// The SAH cost of the tree, normalised by the root's surface area:
    ///
    /// ```text
    /// sum over interior nodes n: TRAVERSAL_COST * A(n) / A(root)            (1 per node)
    /// sum over leaves l:         INTERSECTION_COST * count(l) * A(l) / A(root)  (1 per primitive)
    /// ```
    ///
    /// It is the expected number of node visits and primitive tests of a random ray that hits
    /// the root box. 0 for an empty tree; a root of zero area counts every node with weight 1.
    pub fn sah_cost(&self) -> f32 {
        let Some(root) = self.nodes.first() else { return 0.0 };
        let root_area = root.bounds.surface_area() as f64;
        let mut cost = 0.0f64;
        for n in &self.nodes {
            let rel = if root_area > 0.0 { n.bounds.surface_area() as f64 / root_area } else { 1.0 };
            cost += rel * if n.is_leaf() { INTERSECTION_COST as f64 * n.count as f64 } else { TRAVERSAL_COST as f64 };
        }
        cost as f32
    }

    /// Depth of the deepest leaf (root = 0); 0 for an empty tree.
    pub fn depth(&self) -> usize {
        let mut depth = vec![0usize; self.nodes.len()];
        let mut max = 0;
        for (i, n) in self.nodes.iter().enumerate() {
            if !n.is_leaf() {
                let child_depth = depth[i] + 1;
                for c in [n.left_or_first as usize, n.left_or_first as usize + 1] {
                    if let Some(d) = depth.get_mut(c) {
                        *d = child_depth;
                        max = max.max(child_depth);
                    }
                }
            }
        }
        max
    }

    /// Recomputes every node's box bottom-up from `bounds_of(id)` of its primitives, keeping
    /// the topology (moved primitives, same set). Relies on children following their parent.
    pub fn refit(&mut self, bounds_of: impl Fn(u32) -> Aabb) {
        for i in (0..self.nodes.len()).rev() {
            let n = self.nodes[i];
            let first = n.left_or_first as usize;
            let b = if n.is_leaf() {
                let mut b = Aabb::EMPTY;
                for &id in self.prim_order.get(first..first + n.count as usize).unwrap_or(&[]) {
                    let pb = bounds_of(id);
                    if !pb.is_empty() && pb.is_finite() {
                        b = b.union(&pb);
                    }
                }
                b
            } else {
                let l = self.nodes.get(first).map_or(Aabb::EMPTY, |c| c.bounds);
                let r = self.nodes.get(first + 1).map_or(Aabb::EMPTY, |c| c.bounds);
                l.union(&r)
            };
            self.nodes[i].bounds = b;
        }
    }
}

/// A primitive as the builder works on it, in 32 bytes: its box's corners as SIMD vectors,
/// with the id's bits in the `w` lane of the lower corner. The builder bins by the *doubled*
/// centroid `min + max` (one addition; the 1/2 is folded into the bin mapping), so every
/// "centroid" bound below is of doubled centroids.
#[derive(Debug, Clone, Copy)]
struct Work {
    min: Vec4,
    max: Vec4,
}

impl Work {
    fn new(b: &Aabb, id: u32) -> Self {
        Self { min: b.min.extend(f32::from_bits(id)), max: b.max.extend(0.0) }
    }

    /// A box the builder can place: not empty, finite, with a finite centre.
    fn usable(b: &Aabb) -> bool {
        !b.is_empty() && b.is_finite() && (b.min + b.max).is_finite()
    }

    fn id(&self) -> u32 {
        self.min.w.to_bits()
    }

    fn bounds(&self) -> Box3A {
        Box3A { min: Vec3A::from_vec4(self.min), max: Vec3A::from_vec4(self.max) }
    }

    /// `min + max`: twice the centroid.
    fn centroid(&self) -> Vec3A {
        Vec3A::from_vec4(self.min + self.max)
    }
}

/// [`Aabb`] with 16-byte SIMD vectors, for the builder's inner loops.
#[derive(Debug, Clone, Copy)]
struct Box3A {
    min: Vec3A,
    max: Vec3A,
}

impl Box3A {
    const EMPTY: Box3A = Box3A { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };

    fn union(&self, o: &Box3A) -> Box3A {
        Box3A { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    fn grow(&mut self, p: Vec3A) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn surface_area(&self) -> f32 {
        2.0 * self.half_area()
    }

    /// Half the surface area, without branches; 0 for an empty box.
    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3A::ZERO);
        d.x * (d.y + d.z) + d.y * d.z
    }

    fn to_aabb(self) -> Aabb {
        Aabb { min: self.min.into(), max: self.max.into() }
    }
}

fn union_bounds(prims: &[Work]) -> (Box3A, Box3A) {
    let mut b = Box3A::EMPTY;
    let mut c = Box3A::EMPTY;
    for p in prims {
        b = b.union(&p.bounds());
        c.grow(p.centroid());
    }
    (b, c)
}

fn union_bounds_par(prims: &[Work], cfg: &BuildConfig) -> (Box3A, Box3A) {
    if prims.len() < cfg.parallel_threshold.saturating_mul(4) {
        return union_bounds(prims);
    }
    prims.par_chunks(cfg.parallel_threshold).map(union_bounds).reduce(|| (Box3A::EMPTY, Box3A::EMPTY), |a, b| (a.0.union(&b.0), a.1.union(&b.1)))
}

/// A built subtree before its nodes are laid out in one array: the sequentially built parts
/// keep their node vectors (root at 0, child indices local to the vector), and the parallel
/// splits above them are written out once, by [`Subtree::into_nodes`], instead of being
/// concatenated at every level.
enum Subtree {
    Nodes(Vec<BvhNode>),
    Split { bounds: Aabb, children: Box<[Subtree; 2]>, len: usize },
}

impl Subtree {
    fn len(&self) -> usize {
        match self {
            Subtree::Nodes(nodes) => nodes.len(),
            Subtree::Split { len, .. } => *len,
        }
    }

    /// The root, its child index moved by `shift` (a leaf's primitive range stays).
    fn root(&self, shift: u32) -> BvhNode {
        match self {
            Subtree::Nodes(nodes) => shifted(&nodes[0], shift),
            Subtree::Split { bounds, .. } => BvhNode { bounds: *bounds, left_or_first: 1 + shift, count: 0 },
        }
    }

    /// Writes every node but the root into `dst` (`len - 1` long), in the layout
    /// `[root, left root, right root, left descendants..., right descendants...]` of each
    /// split, child indices moved by `shift`.
    fn write_rest(&self, dst: &mut [BvhNode], shift: u32) {
        match self {
            Subtree::Nodes(nodes) => {
                for (d, n) in dst.iter_mut().zip(&nodes[1..]) {
                    *d = shifted(n, shift);
                }
            }
            Subtree::Split { children, .. } => {
                let [l, r] = &**children;
                let (l_shift, r_shift) = (shift + 2, shift + 1 + l.len() as u32);
                dst[0] = l.root(l_shift);
                dst[1] = r.root(r_shift);
                let (ld, rd) = dst[2..].split_at_mut(l.len() - 1);
                rayon::join(|| l.write_rest(ld, l_shift), || r.write_rest(rd, r_shift));
            }
        }
    }

    fn into_nodes(self) -> Vec<BvhNode> {
        if let Subtree::Nodes(nodes) = self {
            return nodes;
        }
        let mut nodes = vec![BvhNode { bounds: Aabb::EMPTY, left_or_first: 0, count: 0 }; self.len()];
        nodes[0] = self.root(0);
        self.write_rest(&mut nodes[1..], 0);
        nodes
    }
}

/// `n` with its child index moved by `shift` if it is an interior node.
fn shifted(n: &BvhNode, shift: u32) -> BvhNode {
    if n.is_leaf() {
        *n
    } else {
        BvhNode { left_or_first: n.left_or_first + shift, ..*n }
    }
}

/// Builds the subtree over `prims` (which start at `first` in the final primitive order, and
/// whose boxes and centroids span `bounds` and `centroids`).
fn build_subtree(prims: &mut [Work], first: u32, depth: usize, cfg: &BuildConfig, bounds: Box3A, centroids: Box3A) -> Subtree {
    if prims.len() < cfg.parallel_threshold {
        let mut nodes = Vec::with_capacity(prims.len());
        nodes.push(BvhNode { bounds: Aabb::EMPTY, left_or_first: 0, count: 0 });
        let mut scratch = Box::new(Bins::new());
        build_sequential(&mut nodes, 0, prims, first, depth, cfg, (bounds, centroids), &mut scratch);
        return Subtree::Nodes(nodes);
    }
    let mut scratch = Box::new(Bins::new());
    let Some(sp) = split(prims, &bounds, &centroids, depth, cfg, &mut scratch) else {
        return Subtree::Nodes(vec![BvhNode { bounds: bounds.to_aabb(), left_or_first: first, count: prims.len() as u32 }]);
    };
    let mid = sp.mid;
    let (l, r) = prims.split_at_mut(mid);
    let (ln, rn) = rayon::join(
        || build_subtree(l, first, depth + 1, cfg, sp.left.0, sp.left.1),
        || build_subtree(r, first + mid as u32, depth + 1, cfg, sp.right.0, sp.right.1),
    );
    let len = 1 + ln.len() + rn.len();
    Subtree::Split { bounds: bounds.to_aabb(), children: Box::new([ln, rn]), len }
}

/// `span`: the boxes' and the centroids' bounds of `prims`.
#[allow(clippy::too_many_arguments)]
fn build_sequential(
    nodes: &mut Vec<BvhNode>,
    idx: usize,
    prims: &mut [Work],
    first: u32,
    depth: usize,
    cfg: &BuildConfig,
    span: (Box3A, Box3A),
    scratch: &mut Bins,
) {
    let (bounds, centroids) = span;
    match split(prims, &bounds, &centroids, depth, cfg, scratch) {
        None => nodes[idx] = BvhNode { bounds: bounds.to_aabb(), left_or_first: first, count: prims.len() as u32 },
        Some(sp) => {
            let left = nodes.len();
            nodes[idx] = BvhNode { bounds: bounds.to_aabb(), left_or_first: left as u32, count: 0 };
            nodes.push(BvhNode { bounds: Aabb::EMPTY, left_or_first: 0, count: 0 });
            nodes.push(BvhNode { bounds: Aabb::EMPTY, left_or_first: 0, count: 0 });
            let (l, r) = prims.split_at_mut(sp.mid);
            build_sequential(nodes, left, l, first, depth + 1, cfg, sp.left, scratch);
            build_sequential(nodes, left + 1, r, first + sp.mid as u32, depth + 1, cfg, sp.right, scratch);
        }
    }
}

/// A decided split: `prims[..mid]` go left; each side's (box bounds, centroid bounds).
struct Split {
    mid: usize,
    left: (Box3A, Box3A),
    right: (Box3A, Box3A),
}

/// Upper bound of [`BuildConfig::bins`].
pub(crate) const MAX_BINS: usize = 64;

/// Nodes with at least this many primitives bin them in parallel.
const PARALLEL_BINNING: usize = 16 * 1024;

/// Runs of at least twice this many primitives bin into two sets of bins.
const PAIRED_BINNING: usize = 128;

/// Per-axis bin counts and boxes.
#[derive(Clone, Copy)]
struct Bins {
    count: [[u32; MAX_BINS]; 3],
    bounds: [[Box3A; MAX_BINS]; 3],
}

impl Bins {
    fn new() -> Self {
        Self { count: [[0; MAX_BINS]; 3], bounds: [[Box3A::EMPTY; MAX_BINS]; 3] }
    }

    /// Empties the first `bins` bins of every axis.
    fn reset(&mut self, bins: usize) {
        for axis in 0..3 {
            self.count[axis][..bins].fill(0);
            self.bounds[axis][..bins].fill(Box3A::EMPTY);
        }
    }

    fn add_one(&mut self, p: &Work, map: &BinMap) {
        let b = map.bins_of(p);
        for axis in 0..3 {
            let b = b[axis];
            self.count[axis][b] += 1;
            self.bounds[axis][b] = self.bounds[axis][b].union(&p.bounds());
        }
    }

    /// Adds `prims` to the first `bins` bins. Long runs alternate between two sets of bins:
    /// neighbouring primitives often fall into the same bin, and one set would chain their
    /// read-modify-writes.
    fn add(&mut self, prims: &[Work], map: &BinMap, bins: usize) {
        if prims.len() < 2 * PAIRED_BINNING {
            for p in prims {
                self.add_one(p, map);
            }
            return;
        }
        let mut other = Box::new(Bins::new());
        let pairs = prims.chunks_exact(2);
        if let [p] = pairs.remainder() {
            self.add_one(p, map);
        }
        for pair in pairs {
            self.add_one(&pair[0], map);
            other.add_one(&pair[1], map);
        }
        for axis in 0..3 {
            for b in 0..bins {
                self.count[axis][b] += other.count[axis][b];
                self.bounds[axis][b] = self.bounds[axis][b].union(&other.bounds[axis][b]);
            }
        }
    }

    fn absorb(&mut self, o: &Bins) {
        for axis in 0..3 {
            for b in 0..MAX_BINS {
                self.count[axis][b] += o.count[axis][b];
                self.bounds[axis][b] = self.bounds[axis][b].union(&o.bounds[axis][b]);
            }
        }
    }
}

/// Decides how to split `prims` and partitions them in place: `None` for a leaf, else the
/// split (always `0 < mid < len`). `scratch` is reused for the bins of small nodes.
fn split(prims: &mut [Work], bounds: &Box3A, centroids: &Box3A, depth: usize, cfg: &BuildConfig, scratch: &mut Bins) -> Option<Split> {
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    if cfg.method == SplitMethod::Median || depth >= MEDIAN_FALLBACK_DEPTH {
        return leaf_or_median(prims, centroids, cfg.max_leaf_size);
    }
    if n <= EXACT_SPLIT_PRIMS {
        return exact_split(prims, bounds, centroids, cfg.max_leaf_size);
    }
    // Small nodes get fewer bins: at most SMALL_NODE_BINS, and as many as primitives (at
    // least 4) is plenty there.
    let bins = if n >= FINE_BINNING_PRIMS { cfg.bins } else { cfg.bins.min(SMALL_NODE_BINS) }.min(n.max(4));
    let maps = [0, 1, 2].map(|axis| bin_mapping(centroids, axis, bins));
    let map = BinMap::new(&maps, bins);
    if maps.iter().all(Option::is_none) {
        // All centroids coincide: no plane separates them.
        return leaf_or_median(prims, centroids, cfg.max_leaf_size);
    }
    let parallel: Box<Bins>;
    let binned: &Bins = if n >= PARALLEL_BINNING {
        parallel = bin_in_parallel(prims, &map, bins);
        &parallel
    } else {
        scratch.reset(bins);
        scratch.add(prims, &map, bins);
        scratch
    };
    let Some((best_cost, axis, plane)) = cheapest_plane(binned, &maps, bins) else {
        return leaf_or_median(prims, centroids, cfg.max_leaf_size);
    };
    let node_area = bounds.surface_area();
    let cost = TRAVERSAL_COST * node_area + INTERSECTION_COST * 2.0 * best_cost;
    let leaf_cost = INTERSECTION_COST * node_area * n as f32;
    if n <= cfg.max_leaf_size && leaf_cost <= cost {
        return None;
    }
    if maps[axis].is_none() {
        return Some(median_split(prims, centroids));
    }
    Some(partition_at_plane(prims, centroids, (&map, binned, bins), axis, plane))
}

/// A leaf when `prims` fit in one, else the object median split.
fn leaf_or_median(prims: &mut [Work], centroids: &Box3A, max_leaf_size: usize) -> Option<Split> {
    if prims.len() <= max_leaf_size {
        None
    } else {
        Some(median_split(prims, centroids))
    }
}

/// `prims` binned by `map` into `bins` bins, in chunks binned in parallel and then added up.
fn bin_in_parallel(prims: &[Work], map: &BinMap, bins: usize) -> Box<Bins> {
    // On the heap (7 KB a set): rayon's joins and work stealing nest the frames of many
    // nodes' builds on one worker's stack, whose default 2 MiB overflowed on 7.1M
    // triangles with 16 workers.
    prims
        .par_chunks(PARALLEL_BINNING / 4)
        .map(|c| {
            let mut b = Box::new(Bins::new());
            b.add(c, map, bins);
            b
        })
        .reduce(
            || Box::new(Bins::new()),
            |mut a, b| {
                a.absorb(&b);
                a
            },
        )
}

/// The cheapest plane between bins over the axes with a mapping: (cost of the children with
/// half areas, axis, number of bins on the left); `None` when no plane leaves primitives on
/// both sides. The traversal term is the same for every split and is left to the caller.
fn cheapest_plane(binned: &Bins, maps: &[Option<(f32, f32)>; 3], bins: usize) -> Option<(f32, usize, usize)> {
    let (mut best_cost, mut best_axis, mut best_plane) = (f32::INFINITY, usize::MAX, 0);
    let mut right_cost = [0.0f32; MAX_BINS];
    let total = binned.count[0][..bins].iter().sum::<u32>();
    for axis in (0..3).filter(|&a| maps[a].is_some()) {
        let (count, boxes) = (&binned.count[axis], &binned.bounds[axis]);
        // Suffix sweep: right_cost[i] = half area * primitives of bins i..bins.
        let (mut acc_box, mut acc_n) = (Box3A::EMPTY, 0u32);
        for i in (1..bins).rev() {
            acc_box = acc_box.union(&boxes[i]);
            acc_n += count[i];
            right_cost[i] = acc_box.half_area() * acc_n as f32;
        }
        let (mut acc_box, mut acc_n) = (Box3A::EMPTY, 0u32);
        for i in 1..bins {
            acc_box = acc_box.union(&boxes[i - 1]);
            acc_n += count[i - 1];
            let cost = acc_box.half_area() * acc_n as f32 + right_cost[i];
            // Both sides must hold primitives.
            if cost < best_cost && acc_n != 0 && acc_n != total {
                (best_cost, best_axis, best_plane) = (cost, axis, i);
            }
        }
    }
    (best_axis != usize::MAX).then_some((best_cost, best_axis, best_plane))
}

/// Partitions `prims` at `plane` on `axis` with the same bins as the binning pass (`binning`:
/// the mapping, the bins and their number), so each side gets exactly the primitives counted,
/// and each side's box is the union of its bins' boxes.
fn partition_at_plane(prims: &mut [Work], centroids: &Box3A, binning: (&BinMap, &Bins, usize), axis: usize, plane: usize) -> Split {
    let (map, binned, bins) = binning;
    let n = prims.len();
    let (mid, left_centroids, right_centroids) = partition(prims, |p| map.bin_of(p, axis) < plane);
    if mid == 0 || mid == n {
        // Cannot happen with the same mapping as the binning pass; stay safe anyway.
        return median_split(prims, centroids);
    }
    let side = |bins: &[Box3A]| bins.iter().fold(Box3A::EMPTY, |a, b| a.union(b));
    let boxes = &binned.bounds[axis];
    Split { mid, left: (side(&boxes[..plane]), left_centroids), right: (side(&boxes[plane..bins]), right_centroids) }
}

/// Nodes of at most this many primitives evaluate the SAH at every boundary between their
/// primitives sorted by centroid, on each axis, instead of binning: exact, and cheaper than
/// setting up bins for a handful of primitives (most nodes of a tree are this small).
pub(crate) const EXACT_SPLIT_PRIMS: usize = 8;

/// Stable insertion sort of `order[..keys.len()]` (indices into `keys`) by key.
fn sorted_order(keys: &[f32], order: &mut [u8; EXACT_SPLIT_PRIMS]) {
    for i in 0..keys.len() {
        order[i] = i as u8;
        let mut j = i;
        while j > 0 && keys[order[j - 1] as usize] > keys[order[j] as usize] {
            order.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// [`split`] for nodes of 2..=[`EXACT_SPLIT_PRIMS`] primitives: every object split on every
/// axis along which the centroids spread.
fn exact_split(prims: &mut [Work], bounds: &Box3A, centroids: &Box3A, max_leaf_size: usize) -> Option<Split> {
    let n = prims.len();
    let spread = centroids.max - centroids.min;
    let (mut best_cost, mut best_axis, mut best_mid) = (f32::INFINITY, usize::MAX, 0);
    let (mut keys, mut order, mut right_cost) = ([0.0f32; EXACT_SPLIT_PRIMS], [0u8; EXACT_SPLIT_PRIMS], [0.0f32; EXACT_SPLIT_PRIMS]);
    for axis in (0..3).filter(|&a| spread[a] > 0.0) {
        for (k, p) in keys.iter_mut().zip(prims.iter()) {
            *k = p.centroid()[axis];
        }
        sorted_order(&keys[..n], &mut order);
        let mut acc = Box3A::EMPTY;
        for i in (1..n).rev() {
            acc = acc.union(&prims[order[i] as usize].bounds());
            right_cost[i] = acc.half_area() * (n - i) as f32;
        }
        let mut acc = Box3A::EMPTY;
        for i in 1..n {
            acc = acc.union(&prims[order[i - 1] as usize].bounds());
            let cost = acc.half_area() * i as f32 + right_cost[i];
            if cost < best_cost {
                (best_cost, best_axis, best_mid) = (cost, axis, i);
            }
        }
    }
    if best_axis == usize::MAX {
        // All centroids coincide: no plane separates them.
        return leaf_or_median(prims, centroids, max_leaf_size);
    }
    let node_area = bounds.surface_area();
    let cost = TRAVERSAL_COST * node_area + INTERSECTION_COST * 2.0 * best_cost;
    if n <= max_leaf_size && INTERSECTION_COST * node_area * n as f32 <= cost {
        return None;
    }
    // The best axis's order again (the same stable sort, so the same sides as evaluated).
    for (k, p) in keys.iter_mut().zip(prims.iter()) {
        *k = p.centroid()[best_axis];
    }
    sorted_order(&keys[..n], &mut order);
    let copy: [Work; EXACT_SPLIT_PRIMS] = std::array::from_fn(|i| prims[order[i.min(n - 1)] as usize]);
    prims.copy_from_slice(&copy[..n]);
    Some(Split { mid: best_mid, left: union_bounds(&prims[..best_mid]), right: union_bounds(&prims[best_mid..]) })
}

/// `(lo, bins / extent)` for binning centroids along `axis`, or `None` if they do not spread.
fn bin_mapping(centroids: &Box3A, axis: usize, bins: usize) -> Option<(f32, f32)> {
    let (lo, hi) = (centroids.min[axis], centroids.max[axis]);
    let extent = hi - lo;
    let scale = bins as f32 / extent;
    (extent > 0.0 && scale.is_finite()).then_some((lo, scale))
}

/// Bin of a primitive's centroid along each axis, `(c - lo) * bins / extent` truncated and
/// clamped to `0..bins`; an axis whose centroids do not spread maps everything to bin 0 (and is
/// not swept). Binning and partitioning use this same mapping, so each side gets exactly the
/// primitives counted.
struct BinMap {
    lo: Vec3A,
    scale: Vec3A,
    last: Vec3A,
}

impl BinMap {
    fn new(maps: &[Option<(f32, f32)>; 3], bins: usize) -> Self {
        Self {
            lo: Vec3A::from_array(maps.map(|m| m.map_or(0.0, |m| m.0))),
            scale: Vec3A::from_array(maps.map(|m| m.map_or(0.0, |m| m.1))),
            last: Vec3A::splat((bins - 1) as f32),
        }
    }

    /// All three axes with one SIMD expression; the mask (`bins <= MAX_BINS`, a power of two)
    /// only spares the bounds checks where the index is used.
    fn bins_of(&self, p: &Work) -> [usize; 3] {
        let b = ((p.centroid() - self.lo) * self.scale).min(self.last).max(Vec3A::ZERO).as_uvec3() & glam::UVec3::splat(MAX_BINS as u32 - 1);
        [b.x as usize, b.y as usize, b.z as usize]
    }

    /// One axis (the partition's), bit for bit that lane of [`Self::bins_of`].
    fn bin_of(&self, p: &Work, axis: usize) -> usize {
        let b = ((p.centroid()[axis] - self.lo[axis]) * self.scale[axis]).min(self.last.x).max(0.0) as u32;
        (b & (MAX_BINS as u32 - 1)) as usize
    }
}

/// Moves the primitives for which `left` holds to the front, measuring both sides' centroid
/// bounds on the way: `(number on the left, left centroids, right centroids)`.
fn partition(prims: &mut [Work], left: impl Fn(&Work) -> bool) -> (usize, Box3A, Box3A) {
    let (mut lc, mut rc) = (Box3A::EMPTY, Box3A::EMPTY);
    let mut i = 0;
    let mut j = prims.len();
    while i < j {
        let p = prims[i];
        if left(&p) {
            lc.grow(p.centroid());
            i += 1;
        } else {
            rc.grow(p.centroid());
            j -= 1;
            prims.swap(i, j);
        }
    }
    (i, lc, rc)
}

fn median_split(prims: &mut [Work], centroids: &Box3A) -> Split {
    let d = centroids.max - centroids.min;
    let axis = if d.x >= d.y && d.x >= d.z {
        0
    } else if d.y >= d.z {
        1
    } else {
        2
    };
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.centroid()[axis].total_cmp(&b.centroid()[axis]));
    Split { mid, left: union_bounds(&prims[..mid]), right: union_bounds(&prims[mid..]) }
}

// ---------------------------------------------------------------------------------------------
// Triangles and instances
// ---------------------------------------------------------------------------------------------

/// Why a triangle is or is not in a BLAS.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TriangleStatus {
    /// The triangle is in the BLAS.
    Valid,
    /// An index is out of range of the vertex array.
    BadIndex,
    /// A vertex coordinate is NaN or infinite.
    NonFinite,
    /// `(v1 - v0) x (v2 - v0)` evaluated in f32 is zero (or overflows): no area in f32.
    Degenerate,
}

/// Classifies the triangle of object-space vertices `v`.
pub(crate) fn triangle_status(v: &[Vec3; 3]) -> TriangleStatus {
    if !(v[0].is_finite() && v[1].is_finite() && v[2].is_finite()) {
        return TriangleStatus::NonFinite;
    }
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    if n == Vec3::ZERO || !n.is_finite() {
        return TriangleStatus::Degenerate;
    }
    TriangleStatus::Valid
}

/// Object-space vertices of triangle `tri` (index/3) of `mesh`, or `None` if an index is out of
/// range.
pub fn mesh_triangle(mesh: &Mesh, tri: usize) -> Option<[Vec3; 3]> {
    let idx = mesh.indices.get(3 * tri..3 * tri + 3)?;
    let p = |i: u32| mesh.vertices.get(i as usize).map(|v| Vec3::from(v.position));
    Some([p(idx[0])?, p(idx[1])?, p(idx[2])?])
}

/// The vertices and status of triangle `tri` of `mesh` (zero vertices when an index is bad).
pub fn classify_mesh_triangle(mesh: &Mesh, tri: usize) -> ([Vec3; 3], TriangleStatus) {
    match mesh_triangle(mesh, tri) {
        Some(v) => (v, triangle_status(&v)),
        None => ([Vec3::ZERO; 3], TriangleStatus::BadIndex),
    }
}

/// An instance transform as an f64 affine map, or `None` if it cannot be used: a non-finite
/// entry, a singular (or non-finite-inverse) 3x3 part. Only the affine 3x4 part of the matrix is
/// used; a projective last row is ignored.
pub fn instance_transform(m: &Mat4) -> Option<DAffine3> {
    if !m.is_finite() {
        return None;
    }
    let d = m.as_dmat4();
    let a = DAffine3 { matrix3: DMat3::from_cols(d.x_axis.truncate(), d.y_axis.truncate(), d.z_axis.truncate()), translation: d.w_axis.truncate() };
    let det = a.matrix3.determinant();
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = a.inverse();
    (inv.matrix3.is_finite() && inv.translation.is_finite()).then_some(a)
}

/// The world-space box of object box `b` under `xf`, computed in f64 from the 8 corners and
/// widened by a relative 1e-5 so that it conservatively contains the f32 traversal's view of
/// the instance. [`Aabb::EMPTY`] for an empty or non-finite box.
pub(crate) fn instance_world_bounds(b: &Aabb, xf: &DAffine3) -> Aabb {
    if b.is_empty() || !b.is_finite() {
        return Aabb::EMPTY;
    }
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x } as f64,
            if i & 2 == 0 { b.min.y } else { b.max.y } as f64,
            if i & 4 == 0 { b.min.z } else { b.max.z } as f64,
        );
        let w = xf.transform_point3(c);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    let pad = 1e-5 * lo.abs().max(hi.abs()).max_element() + 1e-30;
    let (lo, hi) = ((lo - pad).as_vec3(), (hi + pad).as_vec3());
    if !(lo.is_finite() && hi.is_finite()) {
        return Aabb::EMPTY;
    }
    Aabb { min: lo, max: hi }
}

/// Errors of refitting an acceleration structure whose inputs changed too much.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum AccelError {
    /// The scene's instance count differs from the structure's.
    #[error("the scene has {found} instances but the acceleration structure was built for {expected}; rebuild it")]
    InstanceCountChanged {
        /// Instances when built.
        expected: usize,
        /// Instances now.
        found: usize,
    },
    /// An instance changed its mesh or its usability.
    #[error("instance {0} changed its mesh or became (un)usable; rebuild instead of refitting")]
    InstanceChanged(usize),
    /// The scene's mesh count differs from the structure's.
    #[error("the scene has {found} meshes but the acceleration structure was built for {expected}; rebuild it")]
    MeshCountChanged {
        /// Meshes when built.
        expected: usize,
        /// Meshes now.
        found: usize,
    },
    /// A mesh's triangle count differs from its BLAS's.
    #[error("mesh {mesh} has {found} triangles but its BLAS was built for {expected}; rebuild it")]
    MeshChanged {
        /// The mesh's index.
        mesh: usize,
        /// Triangles when built.
        expected: usize,
        /// Triangles now.
        found: usize,
    },
}

/// A bottom-level BVH over one mesh's triangles in object space. Primitive ids in
/// `bvh.prim_order` are triangle indices (index / 3) in the mesh. Triangles that are
/// degenerate, non-finite or have a bad index are left out and counted.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Blas {
    /// The tree; primitive ids are triangle indices.
    pub bvh: Bvh,
    /// Triangles in the mesh when built (`indices.len() / 3`).
    pub triangle_count: usize,
    /// Zero-area triangles left out.
    pub dropped_degenerate: u32,
    /// Triangles with a non-finite vertex left out.
    pub dropped_non_finite: u32,
    /// Triangles with an index out of range left out.
    pub dropped_bad_index: u32,
}

impl Blas {
    /// Builds the BLAS of `mesh`'s triangles.
    pub fn build(mesh: &Mesh, cfg: &BuildConfig) -> Blas {
        let tris = mesh.triangle_count();
        // The builder's work items straight from the triangles; the rare dropped ones are
        // classified again below to count them by reason.
        let work_item = |t: usize| {
            let (v, status) = classify_mesh_triangle(mesh, t);
            let b = Aabb::from_points(&v);
            (status == TriangleStatus::Valid && Work::usable(&b)).then(|| Work::new(&b, t as u32))
        };
        let work: Vec<Work> =
            if tris >= cfg.parallel_threshold { (0..tris).into_par_iter().filter_map(work_item).collect() } else { (0..tris).filter_map(work_item).collect() };
        let mut blas = Blas { triangle_count: tris, ..Default::default() };
        if work.len() < tris {
            for t in 0..tris {
                let (v, status) = classify_mesh_triangle(mesh, t);
                match status {
                    // A box whose centre overflows f32 cannot be placed: no area in f32 either.
                    TriangleStatus::Valid => blas.dropped_degenerate += u32::from(!Work::usable(&Aabb::from_points(&v))),
                    TriangleStatus::Degenerate => blas.dropped_degenerate += 1,
                    TriangleStatus::NonFinite => blas.dropped_non_finite += 1,
                    TriangleStatus::BadIndex => blas.dropped_bad_index += 1,
                }
            }
        }
        blas.bvh = Bvh::build_work(work, cfg);
        blas
    }

    /// Triangles left out of the tree.
    pub fn dropped(&self) -> u32 {
        self.dropped_degenerate + self.dropped_non_finite + self.dropped_bad_index
    }

    /// Whether no triangle is in the tree.
    pub(crate) fn is_empty(&self) -> bool {
        self.bvh.is_empty()
    }

    /// The object-space box of the tree.
    pub(crate) fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Refits the boxes to `mesh`'s current vertex positions (same triangles, moved vertices).
    /// A triangle that has become non-finite gets an empty box (it can still be tested; the
    /// watertight test never reports a NaN hit).
    pub fn refit(&mut self, mesh: &Mesh, mesh_index: usize) -> Result<(), AccelError> {
        if mesh.triangle_count() != self.triangle_count {
            return Err(AccelError::MeshChanged { mesh: mesh_index, expected: self.triangle_count, found: mesh.triangle_count() });
        }
        self.bvh.refit(|id| mesh_triangle(mesh, id as usize).map_or(Aabb::EMPTY, |v| Aabb::from_points(&v)));
        Ok(())
    }
}

/// A top-level BVH over instances. Primitive ids are indices into `Scene::instances`;
/// instances that cannot be hit (bad mesh index, unusable transform, empty BLAS) are left out.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tlas {
    /// The tree; primitive ids are instance indices.
    pub bvh: Bvh,
    /// World-space box of every scene instance ([`Aabb::EMPTY`] for one left out).
    pub instance_bounds: Vec<Aabb>,
    /// Instances left out.
    pub dropped_instances: u32,
}

impl Tlas {
    /// Builds over `instance_bounds` (one per scene instance; empty boxes are left out).
    pub fn build(instance_bounds: &[Aabb], cfg: &BuildConfig) -> Tlas {
        let prims: Vec<BuildPrim> =
            instance_bounds.iter().enumerate().filter(|(_, b)| !b.is_empty() && b.is_finite()).map(|(i, b)| BuildPrim::new(*b, i as u32)).collect();
        let dropped = (instance_bounds.len() - prims.len()) as u32;
        // No reinsertion: a TLAS is rebuilt whenever instances move, on the frame's wall time,
        // where the optimisation's 3-4x the build would count; the BLASes it points to have it.
        let cfg = BuildConfig { reinsertion_passes: 0, ..cfg.clone() };
        Tlas { bvh: Bvh::build(&prims, &cfg), instance_bounds: instance_bounds.to_vec(), dropped_instances: dropped }
    }

    /// Refits to new instance boxes (same instances, moved). Fails if the set of usable
    /// instances changed.
    pub fn refit(&mut self, instance_bounds: &[Aabb]) -> Result<(), AccelError> {
        if instance_bounds.len() != self.instance_bounds.len() {
            return Err(AccelError::InstanceCountChanged { expected: self.instance_bounds.len(), found: instance_bounds.len() });
        }
        for (i, (old, new)) in self.instance_bounds.iter().zip(instance_bounds).enumerate() {
            let usable = |b: &Aabb| !b.is_empty() && b.is_finite();
            if usable(old) != usable(new) {
                return Err(AccelError::InstanceChanged(i));
            }
        }
        self.instance_bounds = instance_bounds.to_vec();
        let bounds = &self.instance_bounds;
        self.bvh.refit(|id| bounds.get(id as usize).copied().unwrap_or(Aabb::EMPTY));
        Ok(())
    }
}

/// Options of [`SceneAccel::build`].
#[derive(Debug, Clone, PartialEq)]
pub struct AccelOptions {
    /// One BLAS per mesh, shared by its instances (true, the default), or one per instance.
    pub dedup: bool,
    /// The builder's settings.
    pub build: BuildConfig,
}

impl Default for AccelOptions {
    fn default() -> Self {
        Self { dedup: true, build: BuildConfig::default() }
    }
}

/// Both levels for a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneAccel {
    /// With `dedup`, BLAS `i` is mesh `i`'s; without, BLAS `i` belongs to instance `i`.
    pub blases: Vec<Blas>,
    /// The mesh each BLAS was built from (`None`: an instance whose mesh index is out of range;
    /// its BLAS is empty).
    pub blas_mesh: Vec<Option<usize>>,
    /// Per scene instance: its BLAS, or `None` when the instance is left out of the TLAS.
    pub instance_blas: Vec<Option<u32>>,
    /// Per scene instance: its affine transform, when usable.
    pub instance_transforms: Vec<Option<DAffine3>>,
    /// The top level over the instances.
    pub tlas: Tlas,
    /// Whether BLASes are shared per mesh ([`AccelOptions::dedup`]).
    pub dedup: bool,
    /// Wall time of [`SceneAccel::build`].
    pub build_time: Duration,
}

impl SceneAccel {
    /// Builds both levels for `scene`.
    pub fn build(scene: &Scene, opts: &AccelOptions) -> SceneAccel {
        let start = Instant::now();
        let mesh_blases: Vec<Blas> = scene.meshes().par_iter().map(|m| Blas::build(m, &opts.build)).collect();
        let (blases, blas_mesh): (Vec<Blas>, Vec<Option<usize>>) = if opts.dedup {
            (mesh_blases, (0..scene.meshes().len()).map(Some).collect())
        } else {
            scene
                .instances()
                .iter()
                .map(|inst| match mesh_blases.get(inst.mesh) {
                    Some(b) => (b.clone(), Some(inst.mesh)),
                    None => (Blas::default(), None),
                })
                .unzip()
        };
        let mut accel = SceneAccel {
            blases,
            blas_mesh,
            instance_blas: Vec::new(),
            instance_transforms: Vec::new(),
            tlas: Tlas::default(),
            dedup: opts.dedup,
            build_time: Duration::ZERO,
        };
        accel.instance_transforms = scene.instances().iter().map(|i| instance_transform(&i.transform)).collect();
        accel.instance_blas = (0..scene.instances().len())
            .map(|i| {
                let b = if accel.dedup { scene.instances()[i].mesh } else { i };
                let usable = accel.instance_transforms[i].is_some() && accel.blases.get(b).is_some_and(|bl| !bl.is_empty());
                usable.then_some(b as u32)
            })
            .collect();
        let bounds = accel.instance_world_bounds();
        accel.tlas = Tlas::build(&bounds, &opts.build);
        accel.build_time = start.elapsed();
        log::debug!(
            "accel: {} BLAS ({} nodes), TLAS over {} instances ({} left out), built in {:?}",
            accel.blases.len(),
            accel.blases.iter().map(|b| b.bvh.nodes.len()).sum::<usize>(),
            accel.tlas.bvh.prim_order.len(),
            accel.tlas.dropped_instances,
            accel.build_time
        );
        accel
    }

    fn instance_world_bounds(&self) -> Vec<Aabb> {
        self.instance_blas
            .iter()
            .zip(&self.instance_transforms)
            .map(|(b, xf)| match (b, xf) {
                (Some(b), Some(xf)) => self.blases.get(*b as usize).map_or(Aabb::EMPTY, |bl| instance_world_bounds(&bl.bounds(), xf)),
                _ => Aabb::EMPTY,
            })
            .collect()
    }

    /// Refits the TLAS after instances moved (same instances and meshes, new transforms).
    pub fn refit_instances(&mut self, scene: &Scene) -> Result<(), AccelError> {
        if scene.instances().len() != self.instance_blas.len() {
            return Err(AccelError::InstanceCountChanged { expected: self.instance_blas.len(), found: scene.instances().len() });
        }
        let mut transforms = Vec::with_capacity(scene.instances().len());
        for (i, inst) in scene.instances().iter().enumerate() {
            let xf = instance_transform(&inst.transform);
            let expected_blas = if self.dedup { inst.mesh } else { i };
            if xf.is_some() != self.instance_transforms[i].is_some()
                || self.instance_blas[i].is_some_and(|b| b as usize != expected_blas)
                || (!self.dedup && self.blas_mesh.get(i).copied().flatten() != Some(inst.mesh))
            {
                return Err(AccelError::InstanceChanged(i));
            }
            transforms.push(xf);
        }
        let old = std::mem::replace(&mut self.instance_transforms, transforms);
        let bounds = self.instance_world_bounds();
        if let Err(e) = self.tlas.refit(&bounds) {
            self.instance_transforms = old;
            return Err(e);
        }
        Ok(())
    }

    /// Refits every BLAS to its mesh's current vertices, then the TLAS (moved vertices and
    /// instances, same triangles).
    pub fn refit_meshes(&mut self, scene: &Scene) -> Result<(), AccelError> {
        if self.dedup && scene.meshes().len() != self.blases.len() {
            return Err(AccelError::MeshCountChanged { expected: self.blases.len(), found: scene.meshes().len() });
        }
        for (blas, mesh) in self.blases.iter().zip(&self.blas_mesh) {
            if let Some(m) = mesh {
                let found = scene.meshes().get(*m).map_or(0, |m| m.triangle_count());
                if found != blas.triangle_count {
                    return Err(AccelError::MeshChanged { mesh: *m, expected: blas.triangle_count, found });
                }
            }
        }
        let results: Vec<Result<(), AccelError>> = self
            .blases
            .par_iter_mut()
            .zip(&self.blas_mesh)
            .map(|(blas, mesh)| match mesh.and_then(|m| scene.meshes().get(m).map(|mm| (m, mm))) {
                Some((m, mm)) => blas.refit(mm, m),
                None => Ok(()),
            })
            .collect();
        results.into_iter().collect::<Result<(), AccelError>>()?;
        self.refit_instances(scene)
    }

    /// Dropped triangles over the distinct meshes: (degenerate, non-finite, bad index).
    pub fn dropped_triangles(&self) -> (u32, u32, u32) {
        let mut seen = std::collections::HashSet::new();
        let mut d = (0, 0, 0);
        for (b, m) in self.blases.iter().zip(&self.blas_mesh) {
            if let Some(m) = m {
                if seen.insert(*m) {
                    d.0 += b.dropped_degenerate;
                    d.1 += b.dropped_non_finite;
                    d.2 += b.dropped_bad_index;
                }
            }
        }
        d
    }
}

/// A mesh's triangles as the driver's back-ends (`ray-query`, `rt-pipeline`) build them: the
/// mesh's own indices, a triangle the compute back-end leaves out (degenerate, non-finite, bad
/// index) as (0, 0, 0), so primitive indices stay the mesh's own; non-finite positions zeroed.
/// `None` if no triangle is valid.
pub(crate) fn driver_triangles(mesh: &Mesh) -> Option<(Vec<[f32; 3]>, Vec<u32>)> {
    let tris = mesh.triangle_count();
    let mut indices = Vec::with_capacity(tris * 3);
    let mut valid = 0;
    for t in 0..tris {
        if classify_mesh_triangle(mesh, t).1 == TriangleStatus::Valid {
            indices.extend_from_slice(&mesh.indices[3 * t..3 * t + 3]);
            valid += 1;
        } else {
            indices.extend_from_slice(&[0, 0, 0]);
        }
    }
    if valid == 0 {
        return None;
    }
    let positions = mesh.vertices.iter().map(|v| if v.position.iter().all(|c| c.is_finite()) { v.position } else { [0.0; 3] }).collect();
    Some((positions, indices))
}
