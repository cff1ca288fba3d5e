//! Both traversal back-ends against the f64 reference caster, on the same rays: random rays,
//! rays from surfaces, grazing rays and rays aimed exactly at shared vertices and edges, on
//! every built-in scene. Same primitive and t within 1e-4 (relative; for grazing rays plus the
//! f32 position rounding divided by the sine of the angle); a disagreement is allowed
//! only where the reference's normalised edge function is within 1e-5 of zero (the ray passes a
//! triangle edge; for grazing rays 1e-5 divided by the sine of the angle), and the rate of those
//! is printed. Also: watertightness of the closed
//! `organic` mesh from inside, NaN/invalid rays counted and missed, the binding-size limit.

mod common;

use glam::{DVec3, Vec3};
use raygraph::accel::cpu_traverse::Ray;
use raygraph::accel::reference::Reference;
use raygraph::backend::Backend;
use raygraph::runtime::batch::{BatchTracer, GpuRay};
use raygraph::runtime::Gpu;
use raygraph::scene::{open, LoadOptions, Scene};

const T_TOLERANCE: f64 = 1e-4;
const EDGE_EPS: f64 = 1e-5;

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    assert!(gpu.backends.contains(&Backend::RayQuery), "lavapipe >= 24.1 has ray queries; CI must test both back-ends");
    assert!(gpu.backends.contains(&Backend::RtPipeline), "lavapipe >= 24.1 has ray-tracing pipelines; CI must test the rt-pipeline back-end");
    gpu
}

fn scene(name: &str) -> Scene {
    open(name, &LoadOptions { textures: false, ..Default::default() }).unwrap().0
}

fn shaders() -> std::path::PathBuf {
    common::repo().join("shaders")
}

/// splitmix64
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn f(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn dir(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.f() * 2.0 - 1.0, self.f() * 2.0 - 1.0, self.f() * 2.0 - 1.0);
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// World-space triangles of the scene: (instance, prim, vertices).
fn world_triangles(s: &Scene) -> Vec<(u32, u32, [Vec3; 3])> {
    let mut out = Vec::new();
    for (i, inst) in s.instances.iter().enumerate() {
        let m = &s.meshes[inst.mesh];
        for (p, t) in m.indices.chunks_exact(3).enumerate() {
            let v = [0, 1, 2].map(|k| inst.transform.transform_point3(Vec3::from(m.vertices[t[k] as usize].position)));
            if (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0 {
                out.push((i as u32, p as u32, v));
            }
        }
    }
    out
}

/// The test rays of a scene, with a label per group.
fn test_rays(s: &Scene, seed: u64, per_group: usize) -> Vec<(&'static str, Ray)> {
    let mut rng = Rng(seed);
    let b = s.bounds();
    let (c, r) = (b.center(), 0.5 * b.diagonal());
    let tris = world_triangles(s);
    let mut rays = Vec::new();
    // From a sphere around the scene towards random points inside its box.
    for _ in 0..per_group {
        let o = c + rng.dir() * r * 1.5;
        let target = b.min + (b.max - b.min) * Vec3::new(rng.f(), rng.f(), rng.f());
        rays.push(("random", Ray::new(o, (target - o).normalize())));
    }
    // From random surface points, offset along the normal, into the hemisphere.
    for _ in 0..per_group {
        let (_, _, v) = tris[(rng.next() % tris.len() as u64) as usize];
        let (mut a, mut bb) = (rng.f(), rng.f());
        if a + bb > 1.0 {
            (a, bb) = (1.0 - a, 1.0 - bb);
        }
        let p = v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * bb;
        let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let mut d = rng.dir();
        if d.dot(n) < 0.0 {
            d = -d;
        }
        rays.push(("surface", Ray::new(p + n * (1e-4 * r).max(p.abs().max_element() * 1e-5), d)));
    }
    // Grazing: towards a triangle's centroid at 1e-3 .. 1e-7 rad to its plane.
    for k in 0..per_group {
        let (_, _, v) = tris[(rng.next() % tris.len() as u64) as usize];
        let centroid = (v[0] + v[1] + v[2]) / 3.0;
        let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let t = (v[1] - v[0]).normalize();
        let angle = 10f32.powf(-3.0 - 4.0 * (k as f32 / per_group as f32));
        let d = (t * angle.cos() - n * angle.sin()).normalize();
        rays.push(("grazing", Ray::new(centroid - d * r * 0.5, d)));
    }
    // Exactly at shared vertices and edge midpoints, from outside.
    for k in 0..per_group {
        let (_, _, v) = tris[(rng.next() % tris.len() as u64) as usize];
        let target = if k % 2 == 0 { v[(k / 2) % 3] } else { 0.5 * (v[k % 3] + v[(k + 1) % 3]) };
        let o = c + rng.dir() * r * 1.5;
        rays.push(("vertex/edge", Ray::new(o, (target - o).normalize())));
    }
    rays
}

fn gpu_rays(rays: &[(&str, Ray)]) -> Vec<GpuRay> {
    rays.iter().map(|(_, r)| GpuRay { origin: r.origin.into(), t_min: r.t_min, dir: r.dir.into(), t_max: r.t_max }).collect()
}

#[test]
fn both_back_ends_agree_with_the_f64_reference() {
    let gpu = gpu();
    let mut failures: Vec<String> = Vec::new();
    for name in ["box", "organic", "default", "atrium"] {
        let s = scene(name);
        let reference = Reference::new(&s);
        let normals: std::collections::HashMap<(u32, u32), DVec3> =
            world_triangles(&s).into_iter().map(|(i, p, v)| ((i, p), (v[1] - v[0]).cross(v[2] - v[0]).as_dvec3().normalize())).collect();
        let extent = s.bounds().max.abs().max(s.bounds().min.abs()).max_element() as f64;
        let per_group = if name == "atrium" { 150 } else { 400 };
        let rays = test_rays(&s, 7, per_group);
        let reference_hits = reference.closest_many(&rays.iter().map(|(_, r)| *r).collect::<Vec<_>>());
        let reference_any = reference.any_many(&rays.iter().map(|(_, r)| *r).collect::<Vec<_>>());
        for backend in Backend::ALL {
            let tracer = BatchTracer::new(&gpu, backend, &s, &shaders()).unwrap();
            let (hits, stats) = tracer.closest(&gpu, &gpu_rays(&rays)).unwrap();
            let (any, _) = tracer.any(&gpu, &gpu_rays(&rays)).unwrap();
            assert_eq!(stats.closest as usize, rays.len(), "every ray counted on the GPU");
            assert_eq!(stats.invalid, 0);
            let mut near_edge = 0;
            let mut at_edge = vec![false; rays.len()];
            let mut t_err_max = 0.0f64;
            for (k, ((group, ray), (got, want))) in rays.iter().zip(hits.iter().zip(&reference_hits)).enumerate() {
                let edge_of = |inst: u32, prim: u32| reference.edge_distance(ray, inst, prim).unwrap_or(f64::INFINITY);
                // f32 positions carry rounding of a few ulps of the scene's extent; along a
                // grazing ray it becomes a t error divided by the sine of the angle.
                let sine_of = |inst: u32, prim: u32| normals.get(&(inst, prim)).map_or(1.0, |n| n.dot(ray.dir.as_dvec3()).abs().max(1e-12));
                let tolerance_at = |sine: f64, t: f64| T_TOLERANCE + 8.0 * f32::EPSILON as f64 * extent / sine / t.max(1.0);
                // The point where a grazing ray crosses a plane moves by the rounding divided
                // by the sine, and with it the distance to an edge.
                let near_edge_of = |dist: f64, inst: u32, prim: u32| dist <= EDGE_EPS / sine_of(inst, prim).min(1.0);
                at_edge[k] = want.is_some_and(|w| near_edge_of(w.edge_dist, w.instance_id, w.prim))
                    || got.is_some_and(|g| near_edge_of(edge_of(g.instance, g.primitive), g.instance, g.primitive));
                let t_tolerance = |w: &raygraph::accel::reference::RefHit| {
                    let sine = sine_of(w.instance_id, w.prim);
                    (sine, tolerance_at(sine, w.t))
                };
                match (got, want) {
                    (None, None) => {}
                    (Some(g), Some(w)) if g.instance == w.instance_id && g.primitive == w.prim => {
                        let (sine, tolerance) = t_tolerance(w);
                        let err = (g.t as f64 - w.t).abs() / w.t.max(1.0);
                        if sine > 1e-2 {
                            t_err_max = t_err_max.max(err);
                        }
                        if err > tolerance {
                            failures.push(format!(
                                "{name}/{backend} ray {k} ({group}): t {} against {} (relative error {err:e}, tolerance {tolerance:e})",
                                g.t, w.t
                            ));
                        }
                    }
                    (Some(g), Some(w)) => {
                        // Another triangle: only at an edge, at the same distance.
                        // Another triangle: at the same distance (two surfaces meet there: a
                        // shared edge, or coplanar faces), or where one of the two hits is
                        // ambiguous: the reference's (the traversal may pass it and hit farther)
                        // or the traversal's (it may touch something the reference passes).
                        let tol = tolerance_at(sine_of(w.instance_id, w.prim).min(sine_of(g.instance, g.primitive)), w.t) * w.t.max(1.0);
                        let same_t = (g.t as f64 - w.t).abs() <= tol;
                        let ref_ambiguous = near_edge_of(w.edge_dist, w.instance_id, w.prim) && g.t as f64 >= w.t - tol;
                        let gpu_ambiguous = near_edge_of(edge_of(g.instance, g.primitive), g.instance, g.primitive) && g.t as f64 <= w.t + tol;
                        let explained = same_t || ref_ambiguous || gpu_ambiguous;
                        if !explained {
                            failures.push(format!(
                                "{name}/{backend} ray {k} ({group}): hit {}/{} at {} but the reference hits {}/{} at {} (edge distance {:e}, sines {:e} {:e})",
                                g.instance,
                                g.primitive,
                                g.t,
                                w.instance_id,
                                w.prim,
                                w.t,
                                w.edge_dist,
                                sine_of(w.instance_id, w.prim),
                                sine_of(g.instance, g.primitive)
                            ));
                        }
                        near_edge += 1;
                    }
                    (None, Some(w)) => {
                        if !near_edge_of(w.edge_dist, w.instance_id, w.prim) {
                            failures.push(format!(
                                "{name}/{backend} ray {k} ({group}) missed; the reference hits {}/{} at {} (edge distance {:e}, sine {:e})",
                                w.instance_id,
                                w.prim,
                                w.t,
                                w.edge_dist,
                                sine_of(w.instance_id, w.prim)
                            ));
                        }
                        near_edge += 1;
                    }
                    (Some(g), None) => {
                        let e = edge_of(g.instance, g.primitive);
                        if !near_edge_of(e, g.instance, g.primitive) {
                            failures.push(format!(
                                "{name}/{backend} ray {k} ({group}) hit {}/{} at {}; the reference misses (edge distance {e:e}, sine {:e})",
                                g.instance,
                                g.primitive,
                                g.t,
                                sine_of(g.instance, g.primitive)
                            ));
                        }
                        near_edge += 1;
                    }
                }
            }
            let mut any_disagree = 0;
            for (k, (g, w)) in any.iter().zip(&reference_any).enumerate() {
                if g != w {
                    // Only where the closest-hit comparison already found an edge case.
                    if !at_edge[k] {
                        failures.push(format!("{name}/{backend} ray {k} ({}): any-hit {g}, reference {w}", rays[k].0));
                    }
                    any_disagree += 1;
                }
            }
            println!(
                "{name:8} {backend:9}: {} rays, {} hits; disagreements at edges {near_edge} ({:.3}%), any-hit {any_disagree}; max relative t error {t_err_max:.2e} (rays steeper than 0.6°)",
                rays.len(),
                hits.iter().filter(|h| h.is_some()).count(),
                100.0 * near_edge as f64 / rays.len() as f64
            );
        }
    }
    for f in &failures {
        println!("FAIL {f}");
    }
    assert!(failures.is_empty(), "{} rays disagree with the reference beyond the stated tolerances", failures.len());
}

#[test]
fn no_ray_escapes_the_closed_organic_mesh_from_inside() {
    let gpu = gpu();
    let s = scene("organic");
    assert_eq!(s.instances.len(), 1);
    let inst = &s.instances[0];
    let m = &s.meshes[inst.mesh];
    let world = |i: u32| inst.transform.transform_point3(Vec3::from(m.vertices[i as usize].position));
    // An interior point: the mean of the vertices (the head is closed and roughly convex there).
    let inside = m.vertices.iter().map(|v| inst.transform.transform_point3(Vec3::from(v.position)).as_dvec3()).sum::<DVec3>() / m.vertices.len() as f64;
    let inside = inside.as_vec3();
    let mut targets: Vec<Vec3> = (0..m.vertices.len() as u32).map(world).collect();
    for t in m.indices.chunks_exact(3) {
        for k in 0..3 {
            targets.push(0.5 * (world(t[k]) + world(t[(k + 1) % 3])));
        }
    }
    let rays: Vec<GpuRay> = targets.iter().map(|t| GpuRay { origin: inside.into(), t_min: 0.0, dir: (*t - inside).normalize().into(), t_max: 1e30 }).collect();
    for backend in Backend::ALL {
        let tracer = BatchTracer::new(&gpu, backend, &s, &shaders()).unwrap();
        let (hits, _) = tracer.closest(&gpu, &rays).unwrap();
        let escaped: Vec<usize> = hits.iter().enumerate().filter(|(_, h)| h.is_none()).map(|(i, _)| i).collect();
        let (any, _) = tracer.any(&gpu, &rays).unwrap();
        let escaped_any = any.iter().filter(|h| !**h).count();
        println!(
            "{backend}: {} rays at vertices and edge midpoints from inside: {} escaped (closest), {escaped_any} (any); {} of them aimed at vertices",
            rays.len(),
            escaped.len(),
            escaped.iter().filter(|i| **i < m.vertices.len()).count()
        );
        match backend {
            // The project's own traversal: watertight, no exceptions.
            Backend::Compute => {
                assert!(escaped.is_empty() && escaped_any == 0, "{backend}: rays {:?} escaped the closed mesh", &escaped[..escaped.len().min(10)])
            }
            // The driver's intersector: Mesa lavapipe (25.0) lets some rays aimed exactly at a
            // vertex shared by several triangles through (measured: 34 of 1,962 vertex rays,
            // none of the 11,760 edge-midpoint rays). Assert exactly that much: no escape at an
            // edge, and vertex escapes stay a small minority.
            Backend::RayQuery | Backend::RtPipeline => {
                let at_edges = escaped.iter().filter(|i| **i >= m.vertices.len()).count();
                assert_eq!(at_edges, 0, "{backend}: rays aimed at edge midpoints escaped");
                assert!(escaped.len() * 20 <= m.vertices.len(), "{backend}: {} of {} vertex rays escaped", escaped.len(), m.vertices.len());
            }
        }
        assert!(hits.iter().flatten().all(|h| !h.front_face), "{backend}: from inside, every hit is a back face");
    }
}

#[test]
fn invalid_rays_are_counted_and_miss_without_a_crash() {
    let gpu = gpu();
    let s = scene("box");
    let good = GpuRay { origin: [0.0, 0.0, 5.0], t_min: 0.0, dir: [0.0, 0.0, -1.0], t_max: 1e30 };
    let bad = [
        GpuRay { origin: [f32::NAN, 0.0, 5.0], ..good },
        GpuRay { dir: [0.0, f32::INFINITY, -1.0], ..good },
        GpuRay { dir: [0.0, 0.0, 0.0], ..good },
        GpuRay { t_min: -1.0, ..good },
        GpuRay { t_min: 2.0, t_max: 1.0, ..good },
        GpuRay { t_max: f32::NAN, ..good },
    ];
    let mut rays = vec![good];
    rays.extend_from_slice(&bad);
    for backend in Backend::ALL {
        let tracer = BatchTracer::new(&gpu, backend, &s, &shaders()).unwrap();
        let (hits, stats) = tracer.closest(&gpu, &rays).unwrap();
        assert!(hits[0].is_some_and(|h| (h.t - 4.5).abs() < 1e-5), "{backend}: the valid ray hits the box at 4.5: {:?}", hits[0]);
        assert!(hits[1..].iter().all(Option::is_none), "{backend}: invalid rays miss");
        assert_eq!((stats.closest, stats.invalid), (1, bad.len() as u64), "{backend}: {stats:?}");
        let (any, stats) = tracer.any(&gpu, &rays).unwrap();
        assert!(any[0] && !any[1..].iter().any(|h| *h), "{backend}");
        assert_eq!(stats.invalid, bad.len() as u64);
    }
}

#[test]
fn a_scene_too_large_for_a_binding_is_refused_with_the_numbers() {
    let s = scene("organic");
    let flat = raygraph::accel::layout::GpuAccel::build(&s, &Default::default());
    let triangles = std::mem::size_of_val(flat.triangles.as_slice()) as u64;
    raygraph::accel::cache::check_fits("organic", &flat, triangles).unwrap();
    let err = raygraph::accel::cache::check_fits("organic", &flat, triangles - 1).unwrap_err().to_string();
    println!("{err}");
    assert!(err.contains(&triangles.to_string()) && err.contains(&(triangles - 1).to_string()) && err.contains("organic"), "{err}");
}
