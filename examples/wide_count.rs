//! What a ray of the scene workload and of Stress would visit in an 8-wide tree collapsed from
//! the merged layout's binary one (PERF.md step 47), against what it visits in the binary tree
//! (the CPU mirror's counts): `cargo run --release --example wide_count -- SCENE STRIDE AO_RAYS`.
//!
//! A wide node is a binary interior node with its subtree opened, largest surface area first,
//! until it has 8 children (leaves stay leaves); a ray tests every child's box of each wide
//! node it visits, visits the children it hits nearest first (interior ones pushed, leaves'
//! triangles tested at once, as a compressed wide node's traversal does), and an AO lane
//! starts at the wide node rooted at the binary tree's start.

use glam::Vec3;
use raygraph::accel::bvh::{Blas, BuildConfig};
use raygraph::accel::cpu_traverse::{CpuTraverser, Ray, TraceStart, TraversalCounts, WatertightRay};
use raygraph::accel::layout::{merge, merge_instances, GpuAccel, GpuBvhNode};
use raygraph::bench::rays::STRESS_PRESET;
use raygraph::bench::roofline::{scene_workload_rays, WorkloadRay};
use raygraph::scene::{self, LoadOptions};
use std::collections::HashMap;

const WIDTH: usize = 8;

/// What a wide traversal touched.
#[derive(Default, Clone, Copy)]
struct WideCounts {
    nodes: u64,
    child_boxes: u64,
    child_hits: u64,
    triangles: u64,
    rays: u64,
}

struct WideTree<'a> {
    accel: &'a GpuAccel,
    children: HashMap<u32, Vec<u32>>,
}

fn area(n: &GpuBvhNode) -> f32 {
    let d = Vec3::from(n.max) - Vec3::from(n.min);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The children of the wide node rooted at binary interior node `n` of `nodes`, made once.
fn wide_children<'m>(memo: &'m mut HashMap<u32, Vec<u32>>, nodes: &[GpuBvhNode], n: u32) -> &'m [u32] {
    memo.entry(n).or_insert_with(|| {
        let first = nodes[n as usize].left_or_first;
        let mut open = vec![first, first + 1];
        while open.len() < WIDTH {
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

impl WideTree<'_> {
    /// Traces `ray` from the wide node rooted at binary node `root` (a leaf: its triangles).
    fn trace(&mut self, ray: &Ray, root: u32, any_hit: bool, c: &mut WideCounts) -> bool {
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
                let kids = wide_children(&mut self.children, nodes, n);
                c.child_boxes += kids.len() as u64;
                let mut h: Vec<(f32, u32)> = kids.iter().filter_map(|&k| slab(ray.origin, inv, &nodes[k as usize], ray.t_min, best).map(|t| (t, k))).collect();
                h.sort_by(|a, b| a.0.total_cmp(&b.0));
                c.child_hits += h.len() as u64;
                h
            };
            for &(_, k) in interior_farthest_first(&hits, self.accel) {
                stack.push(k);
            }
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

fn report(label: &str, binary: &TraversalCounts, rays: u64, wide: &WideCounts) {
    let n = rays.max(1) as f64;
    println!(
        "{label}: {rays} rays | binary: {:.2} interior, {:.2} child boxes, {:.2} leaves, {:.2} triangles a ray | 8-wide: {:.2} nodes, {:.2} child boxes, {:.2} children hit, {:.2} triangles a ray",
        binary.interior as f64 / n,
        2.0 * binary.interior as f64 / n,
        binary.leaves as f64 / n,
        binary.triangles as f64 / n,
        wide.nodes as f64 / n,
        wide.child_boxes as f64 / n,
        wide.child_hits as f64 / n,
        wide.triangles as f64 / n,
    );
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(name), Some(stride), Some(ao)) = (args.get(1), args.get(2), args.get(3)) else {
        anyhow::bail!("usage: wide_count SCENE STRIDE AO_RAYS");
    };
    let (s, _) = scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
    let (mesh, origin) = merge_instances(&s);
    let accel = merge(&mesh, &origin, Blas::build(&mesh, &BuildConfig::default()));
    let tracer = CpuTraverser::new(&accel);
    let root = accel.instances[0].blas_root;
    let mut wide = WideTree { accel: &accel, children: HashMap::new() };
    let (mut b, mut w, mut start) = (TraversalCounts::default(), WideCounts::default(), TraceStart::Root);
    let (mut ao_b, mut ao_w) = (TraversalCounts::default(), WideCounts::default());
    scene_workload_rays(&s, stride.parse()?, ao.parse()?, |ray| match ray {
        WorkloadRay::Primary(r) => {
            wide.trace(&r, root, false, &mut w);
            tracer.counted(&r, false, &mut b)
        }
        WorkloadRay::Shadow(r) => {
            _ = (tracer.counted(&r, true, &mut b), wide.trace(&r, root, true, &mut w));
            None
        }
        WorkloadRay::LaneStart { origin, radius } => {
            start = tracer.start_within(origin, radius, &mut TraversalCounts::default());
            None
        }
        WorkloadRay::Ao(r) => {
            tracer.any_within(&r, &start, &mut ao_b);
            match start {
                TraceStart::Within { node: Some(n), .. } => _ = wide.trace(&r, n, true, &mut ao_w),
                // Nothing within reach: no traversal in either tree.
                TraceStart::Within { node: None, .. } => ao_w.rays += 1,
                TraceStart::Root => _ = wide.trace(&r, root, true, &mut ao_w),
            }
            None
        }
    });
    report("primary and shadow", &b, w.rays, &w);
    report("AO", &ao_b, ao_w.rays, &ao_w);
    if let Ok(camera) = s.preset(STRESS_PRESET) {
        let (mut sb, mut sw) = (TraversalCounts::default(), WideCounts::default());
        for d in camera.ray_dirs((2560, 1440), stride.parse()?) {
            let r = Ray::new(camera.position, d);
            _ = (tracer.counted(&r, false, &mut sb), wide.trace(&r, root, false, &mut sw));
        }
        report("Stress", &sb, sw.rays, &sw);
    }
    Ok(())
}
