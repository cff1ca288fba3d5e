//! `raygraph bench roofline`: an approximate roofline of Table 3's tests for the `compute`
//! back-end. The CPU mirror of its traversal ([`crate::accel::cpu_traverse`]) runs the tests'
//! rays on the layout the bench graphs use (the merged one) and counts, per ray, the interior
//! nodes, leaves, triangle tests and instances it touches; times the record sizes, that is the
//! bytes the WGSL loads per ray. Against a GPU's aggregate L1 bandwidth this gives the
//! load-bound ceiling in GigaRays/s, and with a `bench rays` CSV the achieved fraction of it.
//!
//! The rays follow `graph/bench_rays.ron` and `graph/bench_primary.ron` at 2560x1440, on every
//! `stride`-th pixel in each direction: a primary ray through the pixel centre; for a hit, one
//! shadow ray towards the directional light and `ao_rays` cosine-weighted AO rays of length 5%
//! of the scene's bounding radius (independent random directions), from the hit moved off the
//! surface as the shaders do, each lane's quarter of them started together below the root
//! where the executor does that (scenes of at least 1024 triangles; the start's own loads
//! counted once per lane); the Miss and Stress tests' primary rays from their cameras.
//!
//! Loads are not the whole of a row's time: the lanes of a subgroup trace their rays together,
//! and a round of rays lasts as long as its longest ray. [`subgroup_share_ao`] and
//! [`subgroup_share_primary`] model that on the same CPU counts: lanes laid out as the passes
//! lay them out (a subgroup of 32), each lane's rays in rounds, the share of a subgroup's
//! traversal steps (interior nodes and leaves visited) that do work; the AO rays there take
//! the directions the shader takes (the AO layers' default sampling, the net).
//! [`voted_fetch_time`] prices the same subgroups' rays in one loop whose lanes fetch together
//! by a vote ([`ao_subgroup_steps`] gives them); [`scene_workload_rays`] hands the workload's
//! rays to other tracers (the examples `ao_fetch_model` and `wide_count`, PERF.md steps 44-47).

use crate::accel::bvh::{Blas, BuildConfig};
use crate::accel::cpu_traverse::{offset_ray_origin, CpuTraverser, Hit, Ray, TraceStart, TraversalCounts};
use crate::accel::layout::{merge, merge_instances, GpuAccel};
use crate::accel::reference_render::{ao_numbers, cosine_hemisphere, r2_sample, AoSettings};
use crate::scene::{Camera, Scene};
use glam::Vec3;
use std::fmt::Write;

/// The H100's aggregate L1 bandwidth: 132 SMs x 128 bytes per clock x 1.98 GHz.
pub const H100_L1_BYTES_PER_S: f64 = 132.0 * 128.0 * 1.98e9;

/// One test's bytes per ray.
#[derive(Debug, Clone)]
pub struct RooflineRow {
    /// The test's name.
    pub test: String,
    /// Rays counted.
    pub rays: u64,
    /// Interior nodes, leaves, triangles and instances visited per ray.
    pub per_ray: [f64; 4],
    /// Bytes loaded per ray.
    pub bytes_per_ray: f64,
    /// Load-bound ceiling at the given bandwidth, GigaRays/s.
    pub ceiling: f64,
    /// From a `bench rays` CSV, if given: achieved GigaRays/s.
    pub achieved: Option<f64>,
    /// The share of a subgroup's traversal steps that do work ([`round_share`]), where modelled.
    pub subgroup_share: Option<f64>,
    /// The primary tests: interior nodes per ray when each ray starts with `t_max` at its own
    /// closest hit, the fewest this traversal order visits had it known the hit first (a bound
    /// on what testing a likely hit first, the hit of the ray before, could save).
    pub known_hit_interior: Option<f64>,
}

/// Lanes of a subgroup on the GPUs this models (NVIDIA's warps).
pub const SUBGROUP_LANES: usize = 32;

/// The share of a subgroup's traversal steps that do work when its lanes trace their rays in
/// rounds: `steps[lane][round]` is the steps (interior nodes and leaves visited) of the lane's
/// ray of that round (0 where it has none), and every round lasts its longest ray for every
/// lane. 1 for a subgroup without steps.
pub fn round_share(steps: &[Vec<u64>]) -> f64 {
    let (useful, issued) = round_steps(steps);
    share(useful, issued)
}

/// The steps of [`round_share`] that do work, and those the subgroup issues.
fn round_steps(steps: &[Vec<u64>]) -> (u64, u64) {
    let rounds = steps.iter().map(Vec::len).max().unwrap_or(0);
    let useful: u64 = steps.iter().flatten().sum();
    let longest: u64 = (0..rounds).map(|k| steps.iter().map(|lane| lane.get(k).copied().unwrap_or(0)).max().unwrap_or(0)).sum();
    (useful, longest * steps.len() as u64)
}

/// The time a subgroup takes, in steps, to trace `steps[lane]` (each ray's steps, in order) in
/// one loop where lanes whose ray is done fetch their next one together: an iteration is a
/// fetch, costing `fetch` steps, when some lanes wait to fetch and either no lane has a ray in
/// flight or at least `threshold` of the lanes with work left wait; else one step of every ray
/// in flight, costing `1 + vote` (the vote's own work). A `threshold` above 1 is rays in
/// rounds (every round one fetch, no vote). Returns the steps that do work and the time.
pub fn voted_fetch_time(steps: &[Vec<u64>], fetch: f64, vote: f64, threshold: f64) -> (u64, f64) {
    let useful: u64 = steps.iter().flatten().sum();
    let mut next = vec![0usize; steps.len()];
    let mut left: Vec<Option<u64>> = vec![None; steps.len()];
    let mut time = 0.0;
    loop {
        let waiting = (0..steps.len()).filter(|&l| left[l].is_none() && next[l] < steps[l].len()).count();
        let flying = left.iter().filter(|r| r.is_some()).count();
        if waiting + flying == 0 {
            return (useful, time);
        }
        if waiting > 0 && (flying == 0 || waiting as f64 >= threshold * (waiting + flying) as f64) {
            time += fetch;
            for l in 0..steps.len() {
                if left[l].is_none() && next[l] < steps[l].len() {
                    left[l] = Some(steps[l][next[l]]).filter(|&s| s > 0);
                    next[l] += 1;
                }
            }
            continue;
        }
        time += 1.0 + if threshold > 1.0 { 0.0 } else { vote };
        for r in left.iter_mut() {
            *r = r.and_then(|s| Some(s - 1).filter(|&s| s > 0));
        }
    }
}

fn share(useful: u64, issued: u64) -> f64 {
    if issued == 0 {
        1.0
    } else {
        useful as f64 / issued as f64
    }
}

fn camera_rays(camera: &Camera, size: (u32, u32), stride: u32) -> Vec<Ray> {
    camera.ray_dirs(size, stride).into_iter().map(|d| Ray::new(camera.position, d)).collect()
}

/// The merged layout of `scene`, as `Accel(merge: true)` builds it (also for the examples that
/// count its rays: `wide_count`, `lane_split_count`).
pub fn merged_layout(scene: &Scene) -> GpuAccel {
    let (mesh, origin) = merge_instances(scene);
    merge(&mesh, &origin, Blas::build(&mesh, &BuildConfig::default()))
}

fn row(test: &str, rays: u64, c: &TraversalCounts, bandwidth: f64) -> RooflineRow {
    let n = rays.max(1) as f64;
    let bytes_per_ray = c.bytes() as f64 / n;
    RooflineRow {
        subgroup_share: None,
        known_hit_interior: None,
        test: test.into(),
        rays,
        per_ray: [c.interior as f64 / n, c.leaves as f64 / n, c.triangles as f64 / n, c.instances as f64 / n],
        bytes_per_ray,
        ceiling: bandwidth / bytes_per_ray.max(1.0) / 1e9,
        achieved: None,
    }
}

/// The scene workload of one scene: primary, shadow and AO rays, counted together.
pub fn scene_workload(scene: &Scene, stride: u32, ao_rays: u32, bandwidth: f64) -> RooflineRow {
    let accel = merged_layout(scene);
    scene_workload_on(scene, &CpuTraverser::new(&accel), stride, ao_rays, bandwidth)
}

/// [`scene_workload`] traced by `tracer` (another layout of `scene`, or with its alpha test).
pub fn scene_workload_on(scene: &Scene, tracer: &CpuTraverser, stride: u32, ao_rays: u32, bandwidth: f64) -> RooflineRow {
    let mut counts = TraversalCounts::default();
    let mut rays = 0u64;
    let mut start = TraceStart::Root;
    scene_workload_rays(scene, stride, ao_rays, |w| match w {
        WorkloadRay::Primary(r) => {
            rays += 1;
            tracer.counted(&r, false, &mut counts)
        }
        WorkloadRay::Shadow(r) => {
            rays += 1;
            tracer.counted(&r, true, &mut counts);
            None
        }
        WorkloadRay::LaneStart { origin, radius } => {
            start = tracer.start_within(origin, radius, &mut counts);
            None
        }
        WorkloadRay::Ao(r) => {
            rays += 1;
            tracer.any_within(&r, &start, &mut counts);
            None
        }
    });
    row(scene.name(), rays, &counts, bandwidth)
}

/// One ray of the scene workload, or the start of a lane's AO rays.
#[derive(Debug, Clone, Copy)]
pub enum WorkloadRay {
    /// A primary ray (closest hit).
    Primary(Ray),
    /// The shadow ray of a primary ray's hit (any hit).
    Shadow(Ray),
    /// The AO rays that follow, up to the next start, stay within `radius` of `origin` and
    /// start together below the root (`common/ao_lane.wgsl`; the executor turns it on).
    LaneStart {
        /// The rays' origin.
        origin: Vec3,
        /// Their reach.
        radius: f32,
    },
    /// An AO ray (any hit).
    Ao(Ray),
}

/// The rays of [`scene_workload`], in the order it traces them: every `stride`-th pixel's
/// primary ray; where `visit` returns its closest hit (its answer for a primary ray; the
/// others' answers are not read), one shadow ray towards the light and `ao_rays` AO rays, a
/// lane's share of them (a quarter) after its [`WorkloadRay::LaneStart`].
pub fn scene_workload_rays(scene: &Scene, stride: u32, ao_rays: u32, mut visit: impl FnMut(WorkloadRay) -> Option<Hit>) {
    let start_below_root = crate::runtime::exec::features::SceneFeatures::of(scene).start_below_root;
    let mut rng = crate::util::SplitMix64(1);
    let range = 0.05 * 0.5 * scene.bounds().diagonal();
    for r in camera_rays(scene.camera(), (2560, 1440), stride) {
        let Some(hit) = visit(WorkloadRay::Primary(r)) else { continue };
        let (origin, n) = ao_origin(scene, &r, &hit);
        visit(WorkloadRay::Shadow(Ray::new(origin, scene.light().direction)));
        for i in 0..ao_rays {
            if i % ao_rays.div_ceil(AO_LANES) == 0 && start_below_root {
                visit(WorkloadRay::LaneStart { origin, radius: range });
            }
            visit(WorkloadRay::Ao(Ray::with_interval(origin, cosine_direction(n, &mut rng), 0.0, range)));
        }
    }
}

/// Where the AO rays of the primary ray `r`'s `hit` start (the hit moved off the surface as the
/// shaders move it), and the surface's normal facing the ray.
fn ao_origin(scene: &Scene, r: &Ray, hit: &Hit) -> (Vec3, Vec3) {
    let inst = &scene.instances()[hit.instance_id as usize];
    let m = &scene.meshes()[inst.mesh];
    let v: [Vec3; 3] = [0, 1, 2].map(|k| inst.transform.transform_point3(Vec3::from(m.vertices[m.indices[3 * hit.prim as usize + k] as usize].position)));
    let mut n = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
    if n.dot(r.dir) > 0.0 {
        n = -n;
    }
    (offset_ray_origin(r.origin + r.dir * hit.t, n), n)
}

/// A cosine-weighted direction about `n`, from two numbers of `rng`.
fn cosine_direction(n: Vec3, rng: &mut crate::util::SplitMix64) -> Vec3 {
    let (t, b) = (n.any_orthonormal_vector(), n.cross(n.any_orthonormal_vector()));
    let (u, w) = (rng.f(), rng.f());
    let (rad, phi) = (u.sqrt(), w * std::f32::consts::TAU);
    (t * (rad * phi.cos()) + b * (rad * phi.sin()) + n * (1.0 - u).max(0.0).sqrt()).normalize()
}

/// The top left pixels of `blocks` x `blocks` subgroups of `w`x`h` pixels spread over
/// 2560x1440 (each block's corner a multiple of its size).
fn subgroup_corners(blocks: u32, (w, h): (u32, u32)) -> impl Iterator<Item = (u32, u32)> {
    (0..blocks * blocks).map(move |k| {
        let (bx, by) = (k % blocks, k / blocks);
        ((bx * 2560 / blocks + 2560 / blocks / 2) / w * w, (by * 1440 / blocks + 1440 / blocks / 2) / h * h)
    })
}

/// Traversal steps (interior nodes and leaves) a count holds.
fn steps(c: &TraversalCounts) -> u64 {
    c.interior + c.leaves
}

/// [`round_share`] of the scene workload's AO rays (its bulk): subgroups of 4x2 pixels of
/// AO_LANES lanes each, as `rt/ao.wgsl` lays its 8x8 workgroups over `partial` (twice the frame
/// in each axis), `ao_rays` a pixel in rounds of one ray a lane (lane k rays k, k + AO_LANES,
/// ...), each lane's rays started where `scene_workload` starts them; `blocks` x `blocks`
/// subgroups over the frame. The directions are the shader's for `sampling` (the AO layers'
/// parameter: 2, the net, is their default), through the f32 mirror
/// [`crate::accel::reference_render::ao_numbers`], seed 0 as in `graph/bench_rays.ron`.
pub fn subgroup_share_ao(scene: &Scene, blocks: u32, ao_rays: u32, sampling: u32) -> f64 {
    let (mut useful, mut issued) = (0u64, 0u64);
    for lanes in ao_subgroup_steps(scene, blocks, ao_rays, sampling) {
        let (u, i) = round_steps(&lanes);
        (useful, issued) = (useful + u, issued + i);
    }
    share(useful, issued)
}

/// The subgroups of [`subgroup_share_ao`]: for each, `steps[lane][round]`.
pub fn ao_subgroup_steps(scene: &Scene, blocks: u32, ao_rays: u32, sampling: u32) -> Vec<Vec<Vec<u64>>> {
    let accel = merged_layout(scene);
    let tracer = CpuTraverser::new(&accel);
    let start_below_root = crate::runtime::exec::features::SceneFeatures::of(scene).start_below_root;
    let range = 0.05 * 0.5 * scene.bounds().diagonal();
    let settings = AoSettings { rays: ao_rays, range, sampling, seed: 0 };
    let mut subgroups = Vec::new();
    for (x0, y0) in subgroup_corners(blocks, (4, 2)) {
        let mut lanes = Vec::with_capacity(SUBGROUP_LANES);
        for k in 0..8 {
            let (o, d) = scene.camera().ray_through((2560, 1440), glam::Vec2::new((x0 + k % 4) as f32 + 0.5, (y0 + k / 4) as f32 + 0.5));
            let r = Ray::new(o, d);
            let Some(hit) = tracer.closest(&r) else {
                lanes.extend((0..AO_LANES).map(|_| Vec::new()));
                continue;
            };
            // The pixel's lanes share its origin and their start (each finds the same one).
            let (origin, n) = ao_origin(scene, &r, &hit);
            let start = if start_below_root { tracer.start_within(origin, range, &mut TraversalCounts::default()) } else { TraceStart::Root };
            let numbers = ao_numbers((x0 + k % 4, y0 + k / 4), &settings);
            for lane in 0..AO_LANES {
                let rays = (0..ao_rays.div_ceil(AO_LANES)).map(|round| (round * AO_LANES + lane) as usize).filter(|&i| i < numbers.len());
                let lane = rays
                    .map(|i| {
                        let mut c = TraversalCounts::default();
                        tracer.any_within(&Ray::with_interval(origin, cosine_hemisphere(n, numbers[i]), 0.0, range), &start, &mut c);
                        steps(&c)
                    })
                    .collect();
                lanes.push(lane);
            }
        }
        subgroups.push(lanes);
    }
    subgroups
}

/// [`round_share`] of a primary test (Miss, Stress: `rt/primary_n.wgsl`): subgroups of 8x4
/// pixels, one lane each, `rays` closest-hit rays a pixel through its R2 points (the shader's
/// own f32 sequence, [`r2_sample`]) in rounds;
/// `blocks` x `blocks` subgroups over the frame.
pub fn subgroup_share_primary(scene: &Scene, camera: &Camera, blocks: u32, rays: u32) -> f64 {
    let accel = merged_layout(scene);
    let tracer = CpuTraverser::new(&accel);
    let (mut useful, mut issued) = (0u64, 0u64);
    for (x0, y0) in subgroup_corners(blocks, (8, 4)) {
        let lanes: Vec<Vec<u64>> = (0..SUBGROUP_LANES as u32)
            .map(|k| {
                (0..rays)
                    .map(|i| {
                        let (o, d) =
                            camera.ray_through((2560, 1440), glam::Vec2::new((x0 + k % 8) as f32, (y0 + k / 8) as f32) + glam::Vec2::from(r2_sample(i)));
                        let mut c = TraversalCounts::default();
                        tracer.counted(&Ray::new(o, d), false, &mut c);
                        steps(&c)
                    })
                    .collect()
            })
            .collect();
        let (u, i) = round_steps(&lanes);
        (useful, issued) = (useful + u, issued + i);
    }
    share(useful, issued)
}

/// Lanes a pixel's AO rays are shared over (the AO layers' `AO_LANES`): `rt_ao`'s count
/// after a frame of which an eighth or more had AO rays, as in the rows modelled here (after
/// frames mostly sky it spreads them over more lanes: `shaders/common/ao_lane_count.wgsl`).
const AO_LANES: u32 = 4;

/// The Miss or Stress test: closest-hit primary rays from `camera`.
pub fn primary_workload(test: &str, scene: &Scene, camera: &Camera, stride: u32, bandwidth: f64) -> RooflineRow {
    let accel = merged_layout(scene);
    primary_workload_on(test, &CpuTraverser::new(&accel), camera, stride, bandwidth)
}

/// [`primary_workload`] traced by `tracer` (another layout of the scene, or with its alpha test).
pub fn primary_workload_on(test: &str, tracer: &CpuTraverser, camera: &Camera, stride: u32, bandwidth: f64) -> RooflineRow {
    let (mut counts, mut known) = (TraversalCounts::default(), TraversalCounts::default());
    let rays = camera_rays(camera, (2560, 1440), stride);
    for r in &rays {
        let mut c = TraversalCounts::default();
        match tracer.counted(r, false, &mut c) {
            Some(hit) => _ = tracer.counted(&Ray::with_interval(r.origin, r.dir, r.t_min, hit.t), false, &mut known),
            None => known.add(&c),
        }
        counts.add(&c);
    }
    let mut row = row(test, rays.len() as u64, &counts, bandwidth);
    row.known_hit_interior = Some(known.interior as f64 / rays.len().max(1) as f64);
    row
}

/// Fills `achieved` from a `bench rays` CSV (its `compute` rows).
pub fn with_achieved(rows: &mut [RooflineRow], rays_csv: &str) {
    let mut lines = rays_csv.lines().filter(|l| !l.starts_with('#'));
    let Some(header) = lines.next() else { return };
    let cols: Vec<&str> = header.split(',').collect();
    let (Some(t), Some(b), Some(g)) =
        (cols.iter().position(|c| *c == "test"), cols.iter().position(|c| *c == "backend"), cols.iter().position(|c| *c == "grays_per_s"))
    else {
        return;
    };
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        if f.get(b) != Some(&"compute") {
            continue;
        }
        if let (Some(name), Some(v)) = (f.get(t), f.get(g).and_then(|v| v.parse::<f64>().ok())) {
            if let Some(r) = rows.iter_mut().find(|r| r.test == *name) {
                r.achieved = Some(v);
            }
        }
    }
}

/// The rows as a markdown table, at `bandwidth` bytes/s, for rays sampled every `stride` pixels.
pub fn markdown(rows: &[RooflineRow], bandwidth: f64, stride: u32) -> String {
    let mut s = String::from("# bench roofline: bytes per ray of the compute back-end\n\n");
    let _ = writeln!(
        s,
        "CPU count of the merged layout's traversal, every {stride}th pixel of 2560x1440 in each direction; bytes = 64 per interior node, 48 per triangle test, 64 per instance entered; ceiling at {:.1} TB/s of L1 bandwidth.\n",
        bandwidth / 1e12
    );
    s.push_str("Subgroup share: the share of a subgroup's traversal steps that do work, its lanes tracing their rays in rounds (32 lanes laid out as the passes lay them; the scene workload's AO rays, the primary tests' rays); the last column divides the achieved fraction by it.\n\n");
    s.push_str("Hit known: the primary tests' interior nodes per ray when each ray starts with its t_max at its own closest hit, the fewest this traversal order visits had it known the hit first.\n\n");
    s.push_str("| test | rays counted | interior nodes/ray | leaves/ray | triangle tests/ray | instances/ray | bytes/ray | L1 ceiling GR/s | achieved GR/s | achieved/ceiling | subgroup share | achieved/(ceiling x share) | interior nodes/ray, hit known |\n");
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    let or_dash = |v: Option<String>| v.unwrap_or_else(|| "—".into());
    for r in rows {
        let achieved = or_dash(r.achieved.map(|a| format!("{a:.2}")));
        let frac = or_dash(r.achieved.map(|a| format!("{:.0}%", 100.0 * a / r.ceiling)));
        let share = or_dash(r.subgroup_share.map(|f| format!("{f:.2}")));
        let within = or_dash(r.achieved.zip(r.subgroup_share).map(|(a, f)| format!("{:.0}%", 100.0 * a / (r.ceiling * f))));
        let known = or_dash(r.known_hit_interior.map(|k| format!("{k:.1}")));
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {:.2} | {:.2} | {:.2} | {:.0} | {:.1} | {achieved} | {frac} | {share} | {within} | {known} |",
            r.test, r.rays, r.per_ray[0], r.per_ray[1], r.per_ray[2], r.per_ray[3], r.bytes_per_ray, r.ceiling
        );
    }
    s
}

/// The rows as CSV.
pub fn csv(rows: &[RooflineRow]) -> String {
    let mut s = String::from(
        "test,rays,interior_per_ray,leaves_per_ray,triangles_per_ray,instances_per_ray,bytes_per_ray,ceiling_grays,achieved_grays,subgroup_share,interior_per_ray_hit_known\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{:.3},{:.3},{:.3},{:.3},{:.1},{:.3},{},{},{}",
            r.test,
            r.rays,
            r.per_ray[0],
            r.per_ray[1],
            r.per_ray[2],
            r.per_ray[3],
            r.bytes_per_ray,
            r.ceiling,
            r.achieved.map(|a| format!("{a:.3}")).unwrap_or_default(),
            r.subgroup_share.map(|f| format!("{f:.4}")).unwrap_or_default(),
            r.known_hit_interior.map(|k| format!("{k:.3}")).unwrap_or_default()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{round_share, voted_fetch_time};

    #[test]
    fn rounds_cost_a_fetch_and_their_longest_ray_each() {
        let lanes = vec![vec![3, 0, 5], vec![1, 0, 2]];
        // (2 + 3) + 2 (a round of rays that need no step) + (2 + 5)
        assert_eq!(voted_fetch_time(&lanes, 2.0, 0.5, f64::INFINITY), (11, 14.0));
    }

    #[test]
    fn a_vote_lets_lanes_out_of_step_fetch_together() {
        // Rounds: 10 + 10. Lane 0 fetches its second ray when it is half the lanes with work
        // left and waits, at step 1: both lanes are done at step 11.
        let lanes = vec![vec![1, 10], vec![10, 1]];
        assert_eq!(voted_fetch_time(&lanes, 0.0, 0.0, f64::INFINITY).1, 20.0);
        assert_eq!(voted_fetch_time(&lanes, 0.0, 0.0, 0.5).1, 11.0);
        // A vote that needs both lanes is rounds again.
        assert_eq!(voted_fetch_time(&lanes, 0.0, 0.0, 1.0).1, 20.0);
    }

    #[test]
    fn a_round_lasts_its_longest_ray() {
        // Two lanes, two rounds: 1 and 3 steps, then 3 and 1: each round issues 3 steps to
        // both lanes (12), of which 8 do work.
        assert!((round_share(&[vec![1, 3], vec![3, 1]]) - 8.0 / 12.0).abs() < 1e-12);
        // Lanes alike: every step does work; a lane without rays idles through every round.
        assert_eq!(round_share(&[vec![2, 5], vec![2, 5]]), 1.0);
        assert!((round_share(&[vec![4], vec![]]) - 0.5).abs() < 1e-12);
        assert_eq!(round_share(&[]), 1.0);
    }
}
