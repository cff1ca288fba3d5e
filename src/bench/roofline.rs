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

use crate::accel::bvh::{Blas, BuildConfig};
use crate::accel::cpu_traverse::{offset_ray_origin, CpuTraverser, Ray, TraceStart, TraversalCounts};
use crate::accel::layout::{merge, merge_instances, GpuAccel};
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
}

fn camera_rays(camera: &Camera, size: (u32, u32), stride: u32) -> Vec<Ray> {
    camera.ray_dirs(size, stride).into_iter().map(|d| Ray::new(camera.position, d)).collect()
}

/// The merged layout of `scene`, as `Accel(merge: true)` builds it.
pub(crate) fn merged_layout(scene: &Scene) -> GpuAccel {
    let (mesh, origin) = merge_instances(scene);
    merge(&mesh, &origin, Blas::build(&mesh, &BuildConfig::default()))
}

fn row(test: &str, rays: u64, c: &TraversalCounts, bandwidth: f64) -> RooflineRow {
    let n = rays.max(1) as f64;
    let bytes_per_ray = c.bytes() as f64 / n;
    RooflineRow {
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
    let tracer = CpuTraverser::new(&accel);
    let start_below_root = crate::runtime::exec::features::SceneFeatures::of(scene).start_below_root;
    let mut counts = TraversalCounts::default();
    let mut rays = 0u64;
    let mut rng = crate::util::SplitMix64(1);
    let range = 0.05 * 0.5 * scene.bounds().diagonal();
    for r in camera_rays(scene.camera(), (2560, 1440), stride) {
        rays += 1;
        let Some(hit) = tracer.counted(&r, false, &mut counts) else { continue };
        let inst = &scene.instances()[hit.instance_id as usize];
        let m = &scene.meshes()[inst.mesh];
        let v: [Vec3; 3] = [0, 1, 2].map(|k| inst.transform.transform_point3(Vec3::from(m.vertices[m.indices[3 * hit.prim as usize + k] as usize].position)));
        let mut n = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
        if n.dot(r.dir) > 0.0 {
            n = -n;
        }
        let origin = offset_ray_origin(r.origin + r.dir * hit.t, n);
        rays += 1;
        tracer.counted(&Ray::new(origin, scene.light().direction), true, &mut counts);
        let (t, b) = (n.any_orthonormal_vector(), n.cross(n.any_orthonormal_vector()));
        // A pixel's AO rays go to AO_LANES lanes; a lane's rays start together below the root
        // where the executor turns that on (`common/ao_lane.wgsl`).
        let mut start = TraceStart::Root;
        for i in 0..ao_rays {
            if i % ao_rays.div_ceil(AO_LANES) == 0 && start_below_root {
                start = tracer.start_within(origin, range, &mut counts);
            }
            let (u, w) = (rng.f(), rng.f());
            let (rad, phi) = (u.sqrt(), w * std::f32::consts::TAU);
            let d = (t * (rad * phi.cos()) + b * (rad * phi.sin()) + n * (1.0 - u).max(0.0).sqrt()).normalize();
            rays += 1;
            tracer.any_within(&Ray::with_interval(origin, d, 0.0, range), &start, &mut counts);
        }
    }
    row(scene.name(), rays, &counts, bandwidth)
}

/// Lanes a pixel's AO rays are shared over (the AO layers' `AO_LANES`): `rt_ao`'s count
/// after a frame of which an eighth or more had AO rays, as in the rows modelled here (after
/// frames mostly sky it spreads them over more lanes: `shaders/common/ao_lane_count.wgsl`).
const AO_LANES: u32 = 4;

/// The Miss or Stress test: closest-hit primary rays from `camera`.
pub fn primary_workload(test: &str, scene: &Scene, camera: &Camera, stride: u32, bandwidth: f64) -> RooflineRow {
    let accel = merged_layout(scene);
    let tracer = CpuTraverser::new(&accel);
    let mut counts = TraversalCounts::default();
    let rays = camera_rays(camera, (2560, 1440), stride);
    for r in &rays {
        tracer.counted(r, false, &mut counts);
    }
    row(test, rays.len() as u64, &counts, bandwidth)
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
    s.push_str("| test | rays counted | interior nodes/ray | leaves/ray | triangle tests/ray | instances/ray | bytes/ray | L1 ceiling GR/s | achieved GR/s | achieved/ceiling |\n");
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let achieved = r.achieved.map(|a| format!("{a:.2}")).unwrap_or_else(|| "—".into());
        let frac = r.achieved.map(|a| format!("{:.0}%", 100.0 * a / r.ceiling)).unwrap_or_else(|| "—".into());
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {:.2} | {:.2} | {:.2} | {:.0} | {:.1} | {achieved} | {frac} |",
            r.test, r.rays, r.per_ray[0], r.per_ray[1], r.per_ray[2], r.per_ray[3], r.bytes_per_ray, r.ceiling
        );
    }
    s
}

/// The rows as CSV.
pub fn csv(rows: &[RooflineRow]) -> String {
    let mut s = String::from("test,rays,interior_per_ray,leaves_per_ray,triangles_per_ray,instances_per_ray,bytes_per_ray,ceiling_grays,achieved_grays\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{:.3},{:.3},{:.3},{:.3},{:.1},{:.3},{}",
            r.test,
            r.rays,
            r.per_ray[0],
            r.per_ray[1],
            r.per_ray[2],
            r.per_ray[3],
            r.bytes_per_ray,
            r.ceiling,
            r.achieved.map(|a| format!("{a:.3}")).unwrap_or_default()
        );
    }
    s
}
