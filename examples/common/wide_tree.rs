//! A wide tree collapsed from the merged layout's binary one, traced on the CPU, for the
//! examples that count what a wide layout would visit (`wide_count`, `lane_split_count`).
//!
//! A wide node is a binary interior node with its subtree opened, largest surface area first,
//! until it has `width` children (leaves stay leaves); a ray tests every child's box of each
//! wide node it visits, visits the children it hits nearest first (interior ones pushed,
//! leaves' triangles tested at once, as a compressed wide node's traversal does).

use glam::Vec3;
use raygraph::accel::cpu_traverse::{Ray, WatertightRay};
use raygraph::accel::layout::{GpuAccel, GpuBvhNode};
use std::collections::HashMap;

/// What a wide traversal touched.
#[derive(Default, Clone, Copy)]
pub struct WideCounts {
    /// Wide nodes visited.
    pub nodes: u64,
    /// Child boxes tested.
    pub child_boxes: u64,
    /// Child boxes the ray entered.
    pub child_hits: u64,
    /// Wide nodes with a leaf child entered: a round of triangle tests after the node's.
    pub leaf_rounds: u64,
    /// Triangles tested.
    pub triangles: u64,
    /// Rays traced.
    pub rays: u64,
}

impl WideCounts {
    /// Dependent steps: each wide node's boxes, and each round of its leaves' triangles.
    pub fn steps(&self) -> u64 {
        self.nodes + self.leaf_rounds
    }
}

/// A `width`-wide tree collapsed from the merged layout's binary one, made as it is visited.
pub struct WideTree<'a> {
    accel: &'a GpuAccel,
    width: usize,
    children: HashMap<u32, Vec<u32>>,
}

fn area(n: &GpuBvhNode) -> f32 {
    let d = Vec3::from(n.max) - Vec3::from(n.min);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The children of the wide node rooted at binary interior node `n` of `nodes`, made once.
fn wide_children<'m>(memo: &'m mut HashMap<u32, Vec<u32>>, nodes: &[GpuBvhNode], n: u32, width: usize) -> &'m [u32] {
    memo.entry(n).or_insert_with(|| {
        let first = nodes[n as usize].left_or_first;
        let mut open = vec![first, first + 1];
        while open.len() < width {
            let interior = open.iter().enumerate().filter(|(_, &k)| nodes[k as usize].count == 0);
            let Some((i, _)) = interior.max_by(|a, b| area(&nodes[*a.1 as usize]).total_cmp(&area(&nodes[*b.1 as usize]))) else { break };
            let k = open.swap_remove(i);
            let f = nodes[k as usize].left_or_first;
            open.extend([f, f + 1]);
        }
        open
    })
}

/// Entry distance of a ray from `origin` with reciprocal direction `inv` into `n` within
/// `(t_min, t_max]`, if it enters.
fn slab(origin: Vec3, inv: Vec3, n: &GpuBvhNode, t_min: f32, t_max: f32) -> Option<f32> {
    let t1 = (Vec3::from(n.min) - origin) * inv;
    let t2 = (Vec3::from(n.max) - origin) * inv;
    let near = t1.min(t2).max_element().max(t_min);
    let far = t1.max(t2).min_element().min(t_max) * 1.000_000_5;
    (near <= far).then_some(near)
}

impl<'a> WideTree<'a> {
    /// The `width`-wide tree of `accel`.
    pub fn new(accel: &'a GpuAccel, width: usize) -> Self {
        Self { accel, width, children: HashMap::new() }
    }

    /// Traces `ray` from the wide node rooted at binary node `root` (a leaf: its triangles).
    pub fn trace(&mut self, ray: &Ray, root: u32, any_hit: bool, c: &mut WideCounts) -> bool {
        c.rays += 1;
        let (inv, Some(watertight)) = (ray.dir.recip(), WatertightRay::new(ray.origin, ray.dir)) else { return false };
        let mut best = ray.t_max;
        let mut stack = vec![root];
        let mut found = false;
        while let Some(n) = stack.pop() {
            let node = self.accel.blas_nodes[n as usize];
            let hits = if node.count > 0 {
                vec![(0.0, n)]
            } else {
                c.nodes += 1;
                let nodes = &self.accel.blas_nodes;
                let kids = wide_children(&mut self.children, nodes, n, self.width);
                c.child_boxes += kids.len() as u64;
                let mut h: Vec<(f32, u32)> = kids.iter().filter_map(|&k| slab(ray.origin, inv, &nodes[k as usize], ray.t_min, best).map(|t| (t, k))).collect();
                h.sort_by(|a, b| a.0.total_cmp(&b.0));
                c.child_hits += h.len() as u64;
                h
            };
            for &(_, k) in interior_farthest_first(&hits, self.accel) {
                stack.push(k);
            }
            c.leaf_rounds += hits.iter().any(|(_, k)| self.accel.blas_nodes[*k as usize].count > 0) as u64;
            for &(_, k) in hits.iter().filter(|(_, k)| self.accel.blas_nodes[*k as usize].count > 0) {
                let leaf = self.accel.blas_nodes[k as usize];
                for t in &self.accel.triangles[leaf.left_or_first as usize..(leaf.left_or_first + leaf.count) as usize] {
                    c.triangles += 1;
                    if let Some((d, ..)) = watertight.intersect(t, ray.t_min, best) {
                        best = d;
                        found = true;
                        if any_hit {
                            return true;
                        }
                    }
                }
            }
        }
        found
    }
}

/// The interior children among `hits` (nearest first), farthest first: the order to push them.
fn interior_farthest_first<'h>(hits: &'h [(f32, u32)], accel: &GpuAccel) -> Vec<&'h (f32, u32)> {
    hits.iter().rev().filter(|(_, k)| accel.blas_nodes[*k as usize].count == 0).collect()
}
