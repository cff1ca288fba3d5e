//! The f64 reference ray caster: the ground truth that tests compare both GPU back-ends (and
//! [`crate::accel::cpu_traverse`]) against.
//!
//! Deliberately simple: every triangle of every instance is moved to world space in f64 once,
//! and every ray is tested against every triangle with Möller–Trumbore in f64 (inclusive on the
//! edges). No acceleration structure, no culling; only the triangles and instances that the BVH
//! builder leaves out are skipped, by the same rules (`triangle_status`,
//! [`instance_transform`]): they do not exist for either side. Batches of rays run in parallel
//! with rayon.
//!
//! Each hit also carries `edge_dist`: the distance from the hit point to the nearest edge of
//! the hit triangle, divided by the coordinate magnitude of the problem (the largest absolute
//! coordinate of the ray origin, the hit point and the triangle's world vertices). An f32 ulp is
//! about `1.2e-7` in these units, so a disagreement with an f32 traversal at `edge_dist` of a
//! few 1e-7 is rounding, not a bug.
//!
//! [`Reference::closest_with_margin`] and [`Reference::any_with_margin`] go further: with the
//! answer they return its *margin*, the smallest relative perturbation of the ray (in the same
//! normalised units) that could change it: a triangle's edge, the ray's ends `t_min` and
//! `t_max`, or a second surface at nearly the same depth within that distance. An f32
//! traversal may disagree with the reference only where the margin is a few ulps.
//!
//! Alpha-tested instances ([`crate::accel::alpha`]) run the same alpha test on every
//! candidate hit (f64 barycentrics and bilinear arithmetic): a rejected hit does not exist. In
//! the margins, a hit whose `base_color.a` x texture alpha lies within `ALPHA_BAND` of the
//! cutoff counts as on an edge (margin 0: the f32 traversals' interpolated uv may land on
//! either side); any other alpha decision does not limit the margin.

use super::bvh::{instance_transform, mesh_triangle, triangle_status, TriangleStatus};
use super::cpu_traverse::{ray_is_valid, Ray};
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// A reference hit; the fields mean the same as [`crate::accel::cpu_traverse::Hit`]'s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefHit {
    /// Distance along the ray.
    pub t: f64,
    /// The scene instance hit.
    pub instance_id: u32,
    /// The triangle's index in its mesh.
    pub prim: u32,
    /// Barycentric weight of `v1`.
    pub u: f64,
    /// Barycentric weight of `v2`.
    pub v: f64,
    /// Counter-clockwise seen from the origin in object space (world winding flipped back for
    /// a mirroring transform).
    pub front_face: bool,
    /// Normalised distance of the hit point to the triangle's nearest edge (module docs).
    pub edge_dist: f64,
}

#[derive(Debug, Clone, Copy)]
struct RefTriangle {
    v: [DVec3; 3],
    instance_id: u32,
    prim: u32,
    mirrored: bool,
    /// Whether the triangle's instance is alpha-tested.
    alpha: bool,
}

/// Alpha values within this of the cutoff are on an alpha edge for the margins (module docs):
/// a quarter of an 8-bit texel step.
pub(crate) const ALPHA_BAND: f64 = 1.0 / 1024.0;

/// All usable triangles of a scene in world space, f64.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    tris: Vec<RefTriangle>,
    by_id: HashMap<(u32, u32), usize>,
    /// The scene, kept only if it has alpha-tested instances (their test reads it).
    alpha_scene: Option<std::sync::Arc<Scene>>,
}

impl Reference {
    /// The reference of `scene`: its triangles in world space, in f64.
    pub fn new(scene: &Scene) -> Self {
        let mut tris = Vec::new();
        for (i, inst) in scene.instances().iter().enumerate() {
            let (Some(xf), Some(mesh)) = (instance_transform(&inst.transform), scene.meshes().get(inst.mesh)) else { continue };
            let mirrored = xf.matrix3.determinant() < 0.0;
            let alpha = super::alpha::instance_tested(scene, i);
            for t in 0..mesh.triangle_count() {
                let Some(v) = mesh_triangle(mesh, t) else { continue };
                if triangle_status(&v) != TriangleStatus::Valid {
                    continue;
                }
                tris.push(RefTriangle { v: v.map(|p| xf.transform_point3(p.as_dvec3())), instance_id: i as u32, prim: t as u32, mirrored, alpha });
            }
        }
        let by_id = tris.iter().enumerate().map(|(k, t)| ((t.instance_id, t.prim), k)).collect();
        let alpha_scene = tris.iter().any(|t| t.alpha).then(|| std::sync::Arc::new(scene.clone()));
        Self { tris, by_id, alpha_scene }
    }

    /// `base_color.a` x texture alpha minus the cutoff at barycentrics (u, v) of `tri` (>= 0:
    /// kept); `None` for a triangle that is not alpha-tested.
    fn alpha_excess(&self, tri: &RefTriangle, u: f64, v: f64) -> Option<f64> {
        let scene = self.alpha_scene.as_deref().filter(|_| tri.alpha)?;
        super::alpha::excess(scene, tri.instance_id as usize, tri.prim as usize, [u, v])
    }

    /// Whether a geometric hit at (u, v) on `tri` survives the alpha test.
    fn keeps(&self, tri: &RefTriangle, u: f64, v: f64) -> bool {
        self.alpha_excess(tri, u, v).is_none_or(|e| e >= 0.0)
    }

    /// Number of triangles (over all instances).
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The closest hit with `t_min < t <= t_max` (the first triangle in scene order on a tie).
    /// Rays that the traversals reject (`ray_is_valid`) miss here too.
    pub fn closest(&self, ray: &Ray) -> Option<RefHit> {
        if !ray_is_valid(ray) {
            return None;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let (t_min, t_max) = (ray.t_min as f64, ray.t_max as f64);
        let mut best: Option<(f64, f64, f64, bool, usize)> = None;
        for (k, tri) in self.tris.iter().enumerate() {
            if let Some((t, u, v, front)) = moller_trumbore(&tri.v, o, d) {
                if t > t_min && t <= t_max && best.is_none_or(|b| t < b.0) && self.keeps(tri, u, v) {
                    best = Some((t, u, v, front, k));
                }
            }
        }
        let (t, u, v, front, k) = best?;
        let tri = &self.tris[k];
        Some(RefHit {
            t,
            instance_id: tri.instance_id,
            prim: tri.prim,
            u,
            v,
            front_face: front != tri.mirrored,
            edge_dist: edge_distance(&tri.v, o, o + t * d),
        })
    }

    /// Whether any triangle is hit with `t_min < t <= t_max`.
    pub fn any(&self, ray: &Ray) -> bool {
        if !ray_is_valid(ray) {
            return false;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let (t_min, t_max) = (ray.t_min as f64, ray.t_max as f64);
        self.tris.iter().any(|tri| moller_trumbore(&tri.v, o, d).is_some_and(|(t, u, v, _)| t > t_min && t <= t_max && self.keeps(tri, u, v)))
    }

    /// [`Reference::closest`] of each ray, in parallel.
    pub fn closest_many(&self, rays: &[Ray]) -> Vec<Option<RefHit>> {
        rays.par_iter().map(|r| self.closest(r)).collect()
    }

    /// [`Reference::any`] of each ray, in parallel.
    pub fn any_many(&self, rays: &[Ray]) -> Vec<bool> {
        rays.par_iter().map(|r| self.any(r)).collect()
    }

    /// The world-space vertices of triangle `prim` of instance `instance_id`, if it is usable.
    pub fn triangle(&self, instance_id: u32, prim: u32) -> Option<[DVec3; 3]> {
        self.by_id.get(&(instance_id, prim)).map(|&k| self.tris[k].v)
    }

    /// The hit of `ray` on triangle `prim` of instance `instance_id` alone
    /// (`t_min < t <= t_max`), if any.
    pub fn hit_triangle(&self, ray: &Ray, instance_id: u32, prim: u32) -> Option<RefHit> {
        let tri = &self.tris[*self.by_id.get(&(instance_id, prim))?];
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let (t, u, v, front) = moller_trumbore(&tri.v, o, d)?;
        (t > ray.t_min as f64 && t <= ray.t_max as f64 && self.keeps(tri, u, v)).then(|| RefHit {
            t,
            instance_id,
            prim,
            u,
            v,
            front_face: front != tri.mirrored,
            edge_dist: edge_distance(&tri.v, o, o + t * d),
        })
    }

    /// For triangle `prim` of instance `instance_id`: the normalised distance (module docs) from
    /// the point where the ray's line crosses the triangle's plane to the triangle's boundary,
    /// whether that point is inside or outside. `None` if there is no such triangle or the ray
    /// is parallel to its plane. Lets a test tell "the traversal hit a triangle the reference
    /// missed by a hair" from a real error.
    pub fn edge_distance(&self, ray: &Ray, instance_id: u32, prim: u32) -> Option<f64> {
        let tri = &self.tris[*self.by_id.get(&(instance_id, prim))?];
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let n = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
        let denom = n.dot(d);
        if denom == 0.0 {
            return None;
        }
        let t = n.dot(tri.v[0] - o) / denom;
        Some(edge_distance(&tri.v, o, o + t * d))
    }
}

impl Reference {
    /// [`Reference::closest`] and its margin (module docs): the least of the hit triangle's
    /// `Reference::signed_margin` and, for every other triangle, the perturbation that would
    /// make it hit and in front of the closest hit (the larger of the two needed).
    pub fn closest_with_margin(&self, ray: &Ray) -> (Option<RefHit>, f64) {
        let best = self.closest(ray);
        if !ray_is_valid(ray) {
            return (None, f64::INFINITY);
        }
        let t_best = best.map_or(f64::INFINITY, |h| h.t);
        let mut margin = f64::INFINITY;
        for tri in &self.tris {
            let Some((s, t, scale)) = self.signed_margin(tri, ray) else { continue };
            if best.is_some_and(|h| (h.instance_id, h.prim) == (tri.instance_id, tri.prim)) {
                margin = margin.min(s.abs());
            } else {
                let to_front = ((t - t_best) * ray.dir.as_dvec3().length() / scale).max(0.0);
                margin = margin.min((-s).max(0.0).max(to_front));
            }
        }
        (best, margin)
    }

    /// [`signed_margin`] with the alpha test (module docs): a geometric hit that the test
    /// rejects is a miss that only a change of alpha decision could turn into a hit.
    fn signed_margin(&self, tri: &RefTriangle, ray: &Ray) -> Option<(f64, f64, f64)> {
        let (s, t, scale) = signed_margin(tri, ray)?;
        let excess = moller_trumbore(&tri.v, ray.origin.as_dvec3(), ray.dir.as_dvec3()).and_then(|(_, u, v, _)| self.alpha_excess(tri, u, v));
        Some(match excess {
            Some(e) if e.abs() < ALPHA_BAND => (0.0, t, scale),
            Some(e) if e < 0.0 && s > 0.0 => (f64::NEG_INFINITY, t, scale),
            _ => (s, t, scale),
        })
    }

    /// [`Reference::any`] and its margin (module docs): how far the most robustly hit triangle
    /// is from being missed, or, on a miss, how far the nearest triangle is from being hit.
    pub fn any_with_margin(&self, ray: &Ray) -> (bool, f64) {
        if !ray_is_valid(ray) {
            return (false, f64::INFINITY);
        }
        let best = self.tris.iter().filter_map(|tri| self.signed_margin(tri, ray)).map(|(s, ..)| s).fold(f64::NEG_INFINITY, f64::max);
        (self.any(ray), best.abs())
    }
}

/// How robustly `ray` hits or misses `tri`, as `(s, t, scale)`: `t` where the ray's line meets
/// the triangle's plane, `scale` the coordinate magnitude (module docs), and `s` positive for a
/// hit (the distance to the nearest edge or to the nearer end of `[t_min, t_max]`, the
/// smaller) or negative for a miss (the distance outside the triangle or outside the interval,
/// the larger), normalised by `scale`. `None` when the ray runs parallel to the plane.
fn signed_margin(tri: &RefTriangle, ray: &Ray) -> Option<(f64, f64, f64)> {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let n = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
    let denom = n.dot(d);
    if denom == 0.0 || !denom.is_finite() {
        return None;
    }
    let t = n.dot(tri.v[0] - o) / denom;
    let p = o + t * d;
    let scale = [o, p, tri.v[0], tri.v[1], tri.v[2]].iter().map(|x| x.abs().max_element()).fold(f64::MIN_POSITIVE, f64::max);
    let edge = edge_distance(&tri.v, o, p);
    let inside = moller_trumbore(&tri.v, o, d).is_some();
    let len = d.length();
    let (t_min, t_max) = (ray.t_min as f64, ray.t_max as f64);
    let in_range = t > t_min && t <= t_max;
    let outside_or_inside = if in_range {
        (t - t_min).min(t_max - t)
    } else if t <= t_min {
        t_min - t
    } else {
        t - t_max
    };
    let range = outside_or_inside * len / scale;
    let s = match (inside, in_range) {
        (true, true) => edge.min(range),
        (true, false) => -range,
        (false, true) => -edge,
        (false, false) => -edge.max(range),
    };
    Some((s, t, scale))
}

/// Möller–Trumbore in f64, inclusive on the edges: `(t, u, v, det > 0)` for any `t` (the caller
/// checks the interval); `det > 0` means counter-clockwise seen from the origin.
fn moller_trumbore(v: &[DVec3; 3], o: DVec3, d: DVec3) -> Option<(f64, f64, f64, bool)> {
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - v[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let w = d.dot(q) * inv;
    if w < 0.0 || u + w > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    Some((t, u, w, det > 0.0))
}

fn point_segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let s = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + s * ab)).length()
}

/// Distance from `p` to the nearest edge of triangle `v`, over the coordinate magnitude.
fn edge_distance(v: &[DVec3; 3], o: DVec3, p: DVec3) -> f64 {
    let dist = point_segment_distance(p, v[0], v[1]).min(point_segment_distance(p, v[1], v[2])).min(point_segment_distance(p, v[2], v[0]));
    let scale = [o, p, v[0], v[1], v[2]].iter().map(|x| x.abs().max_element()).fold(f64::MIN_POSITIVE, f64::max);
    dist / scale
}
