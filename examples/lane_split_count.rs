//! How long the shadow pass's subgroups run when one ray's tree is split over several lanes
//! (PERF.md step 56): `cargo run --release --example lane_split_count -- SCENE SCALE [KIND [WARPS]]`.
//!
//! The scene's camera is moved SCALE times as far from its target (the `bench rays` coverage
//! rows name their scale); every pixel of 2560x1440 traces its primary ray and, where it hits,
//! the roofline's shadow ray (towards the scene's light, from the hit moved off the surface:
//! `bench::roofline::scene_workload_rays`) where the surface faces the light, an any-hit ray on
//! the merged layout with the alpha test (a BLEND surface stops it: the shader's transmittance
//! rays go on through it). With `lanes` = 1 a lane traces a pixel's ray from the root, as
//! `rt/shadow.wgsl` does; with `lanes` = 2, 4, 8 or 16 each lane traces it in one subtree of the
//! frontier log2(lanes) levels below the root (a leaf above that depth is a subtree of its own),
//! stopping at its own first hit, and the pixel's answer is whether any lane hit. A lane's steps
//! are the interior nodes and leaves it visits (one more for its subtree's box).
//!
//! Subgroups are 32 lanes over tiles of 32 / `lanes` pixels (8x4 for one lane a pixel, as the
//! 8x8 workgroups lay them out); a subgroup lasts as long as its longest lane. The pass's length
//! is modelled as the makespan of its subgroups (in steps) on WARPS slots (default 3168: 132 SMs
//! x 24 subgroups, the trace kernels' occupancy, PERF.md step 37), each subgroup given to the
//! slot that frees first, in the order of its tiles: a constant time a step, which holds where
//! the GPU is mostly idle (the step's latency) and not where it is full.
//!
//! Then the same rays at one lane a pixel in 4- and 8-wide trees collapsed from the binary one
//! (examples/common/wide_tree.rs; without the alpha test): a step there is a wide node's child
//! boxes, or a round of the triangles of its leaf children (PERF.md step 58). KIND `primary`:
//! the primary rays of the pixels whose ray enters the scene's box instead of the shadow rays
//! (closest hit), in the binary tree at one lane a pixel and in the wide trees. The binary rows
//! run the alpha test and the wide rows do not: on a scene with alpha-tested materials (the
//! pine) the two are not the same rays' work.

#[path = "common/wide_tree.rs"]
mod wide_tree;

use glam::Vec3;
use raygraph::accel::cpu_traverse::{CpuTraverser, Hit, Ray, TraceStart, TraversalCounts};
use raygraph::accel::layout::GpuAccel;
use raygraph::bench::roofline::{merged_layout, scene_workload_rays, WorkloadRay};
use raygraph::scene::{self, LoadOptions};
use std::collections::{BTreeMap, BinaryHeap};
use wide_tree::{WideCounts, WideTree};

const SIZE: (u32, u32) = (2560, 1440);
const LANES: [u32; 5] = [1, 2, 4, 8, 16];
const WIDTHS: [usize; 2] = [4, 8];

/// The merged BLAS's nodes `depth` levels below its root (leaves above that depth included).
fn frontier(accel: &GpuAccel, depth: u32) -> Vec<u32> {
    let mut level = vec![accel.instances[0].blas_root];
    for _ in 0..depth {
        level = level
            .iter()
            .flat_map(|&n| {
                let node = &accel.blas_nodes[n as usize];
                if node.count > 0 {
                    vec![n]
                } else {
                    vec![node.left_or_first, node.left_or_first + 1]
                }
            })
            .collect();
    }
    level
}

/// Steps (interior nodes and leaves) of a count.
fn steps(c: &TraversalCounts) -> u64 {
    c.interior + c.leaves
}

/// The steps of each lane of one pixel's ray split over `subtrees` (the root alone: one lane,
/// closest-hit where `any_hit` is off; split: any-hit), and whether any lane hit.
fn lane_steps(tracer: &CpuTraverser, ray: &Ray, subtrees: &[u32], any_hit: bool) -> (Vec<u64>, bool) {
    if subtrees.len() == 1 {
        let mut c = TraversalCounts::default();
        let hit = tracer.counted(ray, any_hit, &mut c).is_some();
        return (vec![steps(&c)], hit);
    }
    let mut any = false;
    let lanes = subtrees
        .iter()
        .map(|&node| {
            let start = TraceStart::Within { instance: 0, node: Some(node), lo: Vec3::splat(f32::NEG_INFINITY), hi: Vec3::splat(f32::INFINITY) };
            let mut c = TraversalCounts::default();
            any |= tracer.any_within(ray, &start, &mut c);
            1 + steps(&c)
        })
        .collect();
    (lanes, any)
}

/// Each subgroup's longest lane (steps), tiles of `tile` pixels in row-major tile order.
fn subgroup_lengths(pixels: &BTreeMap<(u32, u32), Vec<u64>>, tile: (u32, u32)) -> Vec<u64> {
    let mut longest: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for (&(x, y), lanes) in pixels {
        let key = (y / tile.1, x / tile.0);
        let l = longest.entry(key).or_default();
        *l = (*l).max(lanes.iter().copied().max().unwrap_or(0));
    }
    longest.into_values().collect()
}

/// The makespan of `jobs` (in order) on `slots` slots, each job to the slot that frees first.
fn makespan(jobs: &[u64], slots: usize) -> u64 {
    let mut free: BinaryHeap<std::cmp::Reverse<u64>> = (0..slots).map(|_| std::cmp::Reverse(0)).collect();
    let mut end = 0;
    for &j in jobs {
        let std::cmp::Reverse(t) = free.pop().unwrap_or(std::cmp::Reverse(0));
        end = end.max(t + j);
        free.push(std::cmp::Reverse(t + j));
    }
    end
}

fn percentile(sorted: &[u64], p: f64) -> u64 {
    sorted.get(((sorted.len() as f64 - 1.0) * p).round() as usize).copied().unwrap_or(0)
}

/// The geometric normal of the triangle `hit`, facing the ray `r` that hit it.
fn facing_normal(s: &scene::Scene, r: &Ray, hit: &Hit) -> Vec3 {
    let inst = &s.instances()[hit.instance_id as usize];
    let m = &s.meshes()[inst.mesh];
    let v: [Vec3; 3] = [0, 1, 2].map(|k| inst.transform.transform_point3(Vec3::from(m.vertices[m.indices[3 * hit.prim as usize + k] as usize].position)));
    let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
    if n.dot(r.dir) > 0.0 {
        -n
    } else {
        n
    }
}

/// The shadow rays of every covered pixel whose surface faces the light (the shader traces
/// none where it faces away: `light_transmittance`), by pixel.
fn shadow_rays(s: &scene::Scene, tracer: &CpuTraverser) -> BTreeMap<(u32, u32), Ray> {
    let mut pixel = 0u64;
    let mut rays = BTreeMap::new();
    let mut facing = Vec3::ZERO;
    scene_workload_rays(s, 1, 0, |w| match w {
        WorkloadRay::Primary(r) => {
            pixel += 1;
            let hit = tracer.closest(&r);
            facing = hit.as_ref().map_or(Vec3::ZERO, |h| facing_normal(s, &r, h));
            hit
        }
        WorkloadRay::Shadow(r) if facing.dot(r.dir) > 0.0 => {
            let p = pixel - 1;
            rays.insert(((p % SIZE.0 as u64) as u32, (p / SIZE.0 as u64) as u32), r);
            None
        }
        _ => None,
    });
    rays
}

/// The primary rays of the pixels whose ray enters the scene's box (the others take no step).
fn primary_rays(s: &scene::Scene, tracer: &CpuTraverser) -> BTreeMap<(u32, u32), Ray> {
    let mut rays = BTreeMap::new();
    for (p, (origin, dir)) in s.camera().rays(SIZE, 1).into_iter().enumerate() {
        let r = Ray::new(origin, dir);
        let mut c = TraversalCounts::default();
        tracer.counted(&r, false, &mut c);
        if steps(&c) > 0 {
            rays.insert(((p % SIZE.0 as usize) as u32, (p / SIZE.0 as usize) as u32), r);
        }
    }
    rays
}

/// One row of the table: the tree, the split, and what its rays did.
struct Row {
    tree: String,
    lanes: u32,
    subtrees: usize,
    hits: u64,
    total: u64,
    rays: usize,
}

/// Prints `row` with its subgroups' lengths: `pixels` holds each pixel's lanes' steps.
fn report(row: &Row, pixels: &BTreeMap<(u32, u32), Vec<u64>>, slots: usize) {
    let tile = match 32 / row.lanes {
        32 => (8, 4),
        16 => (4, 4),
        8 => (4, 2),
        4 => (2, 2),
        _ => (2, 1),
    };
    let jobs = subgroup_lengths(pixels, tile);
    let mut sorted = jobs.clone();
    sorted.sort_unstable();
    println!(
        "| {} | {} | {} | {} | {} | {:.1} | {} | {} | {} | {} | {} |",
        row.tree,
        row.lanes,
        row.subtrees,
        row.hits,
        jobs.len(),
        row.total as f64 / row.rays.max(1) as f64,
        sorted.last().copied().unwrap_or(0),
        percentile(&sorted, 0.99),
        percentile(&sorted, 0.5),
        jobs.iter().sum::<u64>(),
        makespan(&jobs, slots)
    );
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(name), Some(scale)) = (args.get(1), args.get(2)) else {
        anyhow::bail!("usage: lane_split_count SCENE SCALE [shadow|primary] [WARPS]");
    };
    let scale: f32 = scale.parse()?;
    let primary = args.get(3).is_some_and(|k| k == "primary");
    let slots: usize = args.get(4).map_or(Ok(132 * 24), |w| w.parse())?;
    let (mut s, _) = scene::open(name, &LoadOptions::default())?;
    let camera = s.camera_mut();
    camera.position = camera.target + (camera.position - camera.target) * scale;
    camera.far += (camera.position - camera.target).length();
    let accel = merged_layout(&s);
    let tracer = CpuTraverser::with_scene(&accel, &s);
    let rays = if primary { primary_rays(&s, &CpuTraverser::new(&accel)) } else { shadow_rays(&s, &tracer) };
    println!(
        "{name} x{scale}: {} {} rays ({:.2}% of the pixels), {slots} slots",
        rays.len(),
        if primary { "primary" } else { "shadow" },
        100.0 * rays.len() as f64 / (SIZE.0 * SIZE.1) as f64
    );
    println!("| tree | lanes a pixel | subtrees | hits | subgroups | lane steps a ray | longest subgroup | p99 | p50 | sum of subgroups | makespan |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    // Closest-hit rays are not split (a lane cannot stop at its own first hit).
    for lanes in LANES.into_iter().filter(|&l| l == 1 || !primary) {
        let subtrees = frontier(&accel, lanes.trailing_zeros());
        let (mut hits, mut total) = (0u64, 0u64);
        let pixels: BTreeMap<(u32, u32), Vec<u64>> = rays
            .iter()
            .map(|(&p, r)| {
                let (l, hit) = lane_steps(&tracer, r, &subtrees, !primary);
                hits += hit as u64;
                total += l.iter().sum::<u64>();
                (p, l)
            })
            .collect();
        let row = Row { tree: "binary".into(), lanes, subtrees: subtrees.len(), hits, total, rays: rays.len() };
        report(&row, &pixels, slots);
    }
    for width in WIDTHS {
        let mut wide = WideTree::new(&accel, width);
        let (mut hits, mut total) = (0u64, 0u64);
        let pixels: BTreeMap<(u32, u32), Vec<u64>> = rays
            .iter()
            .map(|(&p, r)| {
                let mut c = WideCounts::default();
                hits += wide.trace(r, accel.instances[0].blas_root, !primary, &mut c) as u64;
                total += c.steps();
                (p, vec![c.steps()])
            })
            .collect();
        let row = Row { tree: format!("{width}-wide"), lanes: 1, subtrees: 1, hits, total, rays: rays.len() };
        report(&row, &pixels, slots);
    }
    Ok(())
}
