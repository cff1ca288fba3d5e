//! What a ray of the scene workload and of Stress would visit in an 8-wide tree (or WIDTH-wide)
//! collapsed from the merged layout's binary one (PERF.md steps 47 and 60), against what it
//! visits in the binary tree (the CPU mirror's counts):
//! `cargo run --release --example wide_count -- SCENE STRIDE AO_RAYS [WIDTH]`.
//!
//! The wide tree is examples/common/wide_tree.rs's; an AO lane starts at the wide node rooted at
//! the binary tree's start. A ray's steps: interior nodes and leaves in the binary tree; wide
//! nodes and rounds of their leaf children's triangles in the wide one.

#[path = "common/wide_tree.rs"]
mod wide_tree;

use raygraph::accel::cpu_traverse::{CpuTraverser, Ray, TraceStart, TraversalCounts};
use raygraph::bench::rays::STRESS_PRESET;
use raygraph::bench::roofline::{merged_layout, scene_workload_rays, WorkloadRay};
use raygraph::scene::{self, LoadOptions};
use wide_tree::{WideCounts, WideTree};

fn report(label: &str, binary: &TraversalCounts, rays: u64, (width, wide): (usize, &WideCounts)) {
    let n = rays.max(1) as f64;
    println!(
        "{label}: {rays} rays | binary: {:.2} interior, {:.2} child boxes, {:.2} leaves, {:.2} triangles, {:.2} steps a ray | {width}-wide: {:.2} nodes, {:.2} child boxes, {:.2} children hit, {:.2} triangles, {:.2} steps a ray",
        binary.interior as f64 / n,
        2.0 * binary.interior as f64 / n,
        binary.leaves as f64 / n,
        binary.triangles as f64 / n,
        (binary.interior + binary.leaves) as f64 / n,
        wide.nodes as f64 / n,
        wide.child_boxes as f64 / n,
        wide.child_hits as f64 / n,
        wide.triangles as f64 / n,
        wide.steps() as f64 / n,
    );
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(name), Some(stride), Some(ao)) = (args.get(1), args.get(2), args.get(3)) else {
        anyhow::bail!("usage: wide_count SCENE STRIDE AO_RAYS [WIDTH]");
    };
    let width: usize = args.get(4).map_or(Ok(8), |w| w.parse())?;
    let (s, _) = scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
    let accel = merged_layout(&s);
    let tracer = CpuTraverser::new(&accel);
    let root = accel.instances[0].blas_root;
    let mut wide = WideTree::new(&accel, width);
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
    report("primary and shadow", &b, w.rays, (width, &w));
    report("AO", &ao_b, ao_w.rays, (width, &ao_w));
    if let Ok(camera) = s.preset(STRESS_PRESET) {
        let (mut sb, mut sw) = (TraversalCounts::default(), WideCounts::default());
        for d in camera.ray_dirs((2560, 1440), stride.parse()?) {
            let r = Ray::new(camera.position, d);
            _ = (tracer.counted(&r, false, &mut sb), wide.trace(&r, root, false, &mut sw));
        }
        report("Stress", &sb, sw.rays, (width, &sw));
    }
    Ok(())
}
