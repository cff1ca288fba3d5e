//! A CPU traversal of [`GpuAccel`] in f32 that does step for step what the `compute`
//! back-end's WGSL does, so that the layout and the numerics are tested before the GPU runs.
//!
//! For every ray:
//!
//! 1. Invalid rays miss (`ray_is_valid`: non-finite origin or direction, zero direction,
//!    negative or non-finite `t_min`, `t_max < t_min`).
//! 2. The reciprocal direction is taken after replacing every component with
//!    `|d| < DIR_EPSILON` by `copysign(DIR_EPSILON, d)` (`safe_reciprocal`), so that no
//!    infinity (and so no `0 * inf = NaN`) ever appears in a slab test.
//! 3. Slab test (`slab_test`, with the per-ray constants of `SlabRay`): per axis
//!    `t = b * inv + c` for the box's min and max planes `b`, where `c = -o * inv` moved
//!    outwards by a bound on its rounding error and on that of the product (the WGSL's `fma`,
//!    which a driver may evaluate split); the near plane is `min` if the reciprocal is >= 0,
//!    else `max`; `t_near = max(t_near_x, t_near_y, t_near_z, t_min)`,
//!    `t_far = min(t_far_x, t_far_y, t_far_z, t_max) * T_FAR_SCALE` (Ize, "Robust BVH ray
//!    traversal", JCGT 2013, for the relative rounding; scaling `t_max` too keeps a box whose
//!    entry rounds a few ulps past the current closest hit); hit if `t_near <= t_far`.
//! 4. TLAS: test the root's box (the WGSL does so only when the root is a leaf; boxes nest and
//!    the test is monotone, so the results are the same); then loop: at a leaf, test its instances in order;
//!    at an interior node test both children's boxes against the current closest `t`, continue
//!    with the nearer (left on a tie) and push the farther; pop when nothing is left. The stack
//!    is a fixed array of `TRAVERSAL_STACK_SIZE` entries per level; a push onto a full stack
//!    is dropped (the builder's depth bound makes that unreachable).
//! 5. Per instance with a non-zero `mask`: origin and direction are moved to object space with
//!    `world_to_object` (direction not renormalised, so `t` stays the world `t`), and the BLAS
//!    from `blas_root` is traversed the same way with the object-space ray.
//! 6. Triangles: the watertight test of Woop, Benthin and Wald (JCGT 2013), see
//!    [`WatertightRay::intersect`]. A hit is accepted if `t_min < t <= t_closest` and then
//!    becomes the new closest (so of hits at exactly the same `t` the last one tested wins).
//!    [`CpuTraverser::any`] returns at the first accepted hit.
//! 7. The hit's instance is the instance's `instance_id`, or, for the one instance of a merged
//!    layout (`MERGED_INSTANCE`), the triangle's `instance`, with `front_face` flipped where
//!    the triangle's flags say its transform mirrors.
//! 8. With `TraceFlags::CULL_BACK_FACES`, a hit the triangle test accepted is dropped when
//!    it is on the triangle's back face (`back_facing`, the WGSL's `trace_back_facing`), and
//!    the traversal goes on as if the triangle were not there.
//! 9. A hit accepted so far on an alpha-tested triangle (the instance's `INSTANCE_ALPHA`, or
//!    in a merged layout the triangle's [`TRI_ALPHA`]) runs the alpha test
//!    ([`crate::accel::alpha::visible`], given the scene with [`CpuTraverser::with_scene`]); a
//!    rejected hit is dropped the same way. Without a scene no alpha test runs.
//!
//! Everything is plain f32 arithmetic in a fixed order, with no fused multiply-add.

use super::layout::{GpuAccel, GpuBvhNode, GpuInstance, GpuTriangle, INSTANCE_ALPHA, MERGED_INSTANCE, TRAVERSAL_STACK_SIZE, TRI_ALPHA, TRI_MIRRORED};
use glam::Vec3;
use rayon::prelude::*;

/// Direction components smaller than this in magnitude are replaced by it (with their sign).
/// A power of two (2^-80), so that its reciprocal and `o * inv` are exact: a ray lying in a
/// slab's plane gets `t = 0` there exactly.
pub(crate) const DIR_EPSILON: f32 = 8.271_806e-25;
/// The slab constant's outward slack, relative to `|o * inv|` (2^-21): covers the rounding of
/// `-o * inv`, of the slack's own addition and of a split `b * inv` (three roundings of about
/// `|o * inv|` each, 2^-24 apiece).
pub(crate) const SLAB_SLACK: f32 = 4.768_371_6e-7;
/// The far-distance scale of the conservative slab test: 1 + 4 ulps, above Ize's
/// `1 + 2 * gamma(3)` (`gamma(n) = n u / (1 - n u)`, `u = 2^-24`, about 3 ulps). The WGSL's
/// `TRACE_WIDEN`.
pub(crate) const T_FAR_SCALE: f32 = 1.000_000_5;

/// A ray: hits are reported for `t_min < t <= t_max`, at `origin + t * dir`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// World-space origin.
    pub origin: Vec3,
    /// World-space direction.
    pub dir: Vec3,
    /// Hits are beyond this distance.
    pub t_min: f32,
    /// Hits are at most this far.
    pub t_max: f32,
}

impl Ray {
    /// A ray over `[0, inf]`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir, t_min: 0.0, t_max: f32::INFINITY }
    }

    /// A ray over `(t_min, t_max]`.
    pub fn with_interval(origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Self {
        Self { origin, dir, t_min, t_max }
    }
}

/// A ray hit. `u`, `v` are the barycentric weights of the triangle's `v1` and `v2` (the weight
/// of `v0` is `1 - u - v`); `front_face` is true when the triangle winds counter-clockwise seen
/// from the ray origin (decided in object space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance along the ray, in units of `dir`.
    pub t: f32,
    /// The scene instance hit.
    pub instance_id: u32,
    /// The triangle's index in its mesh.
    pub prim: u32,
    /// Barycentric weight of `v1`.
    pub u: f32,
    /// Barycentric weight of `v2`.
    pub v: f32,
    /// Whether the front face was hit.
    pub front_face: bool,
}

/// Per-ray flags of the trace interface (`TRACE_*` in `shaders/trace/common.wgsl`; the same
/// bits).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct TraceFlags(pub u32);

impl TraceFlags {
    /// No flags.
    pub(crate) const NONE: TraceFlags = TraceFlags(0);
    /// Back faces (clockwise seen from the ray origin in object space, [`Hit::front_face`]
    /// false) are not hit. The WGSL's `TRACE_CULL_BACK_FACES`, equal to the ray-query flag
    /// `RAY_FLAG_CULL_BACK_FACING`.
    pub(crate) const CULL_BACK_FACES: TraceFlags = TraceFlags(16);

    /// Whether [`TraceFlags::CULL_BACK_FACES`] is set.
    pub(crate) fn culls_back_faces(self) -> bool {
        self.0 & Self::CULL_BACK_FACES.0 != 0
    }
}

/// Whether a ray is traced at all (the WGSL's `trace_ray_is_valid`): finite origin and
/// direction, a non-zero direction, `t_min` finite and not negative (not even -0), `t_max` finite
/// or +inf, and `t_max >= t_min`. Invalid rays miss.
pub(crate) fn ray_is_valid(ray: &Ray) -> bool {
    let t_max_ok = ray.t_max.is_finite() || ray.t_max == f32::INFINITY;
    let t_ok = ray.t_min.is_finite() && !ray.t_min.is_sign_negative() && t_max_ok && ray.t_max >= ray.t_min;
    ray.origin.is_finite() && ray.dir.is_finite() && ray.dir != Vec3::ZERO && t_ok
}

/// `1 / d` per component after replacing tiny components by `copysign(DIR_EPSILON, d)`.
pub(crate) fn safe_reciprocal(d: Vec3) -> Vec3 {
    let f = |x: f32| 1.0 / if x.abs() < DIR_EPSILON { DIR_EPSILON.copysign(x) } else { x };
    Vec3::new(f(d.x), f(d.y), f(d.z))
}

/// A ray's constants of the slab test: `t = b * inv + c_min` for a box's min planes and
/// `b * inv + c_max` for its max planes, one multiply-add per plane instead of a subtraction
/// and a multiplication. `c_min`, `c_max` are `-o * inv` moved by [`SLAB_SLACK`] towards the
/// outside of the slab, so every box stays conservative for any origin (the translated scenes
/// of the hard-case suite). The WGSL's `TraceRay::{inv_dir, c_min, c_max}`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SlabRay {
    /// The reciprocal direction.
    pub(crate) inv: Vec3,
    /// `-o * inv`, moved outwards, for the min planes.
    pub(crate) c_min: Vec3,
    /// `-o * inv`, moved outwards, for the max planes.
    pub(crate) c_max: Vec3,
}

impl SlabRay {
    /// The slab form of the ray from `o` along `d`.
    pub(crate) fn new(o: Vec3, d: Vec3) -> Self {
        let inv = safe_reciprocal(d);
        let oi = -o * inv;
        let slack = oi.abs() * SLAB_SLACK;
        let pos = inv.cmpge(Vec3::ZERO);
        Self { inv, c_min: Vec3::select(pos, oi - slack, oi + slack), c_max: Vec3::select(pos, oi + slack, oi - slack) }
    }
}

/// The conservative slab test: `Some(t_near)` if `[t_min, t_max]` overlaps the node's box.
pub(crate) fn slab_test(n: &GpuBvhNode, r: &SlabRay, t_min: f32, t_max: f32) -> Option<f32> {
    let axis = |a: usize| {
        let t_lo = n.min[a] * r.inv[a] + r.c_min[a];
        let t_hi = n.max[a] * r.inv[a] + r.c_max[a];
        if r.inv[a] >= 0.0 {
            (t_lo, t_hi)
        } else {
            (t_hi, t_lo)
        }
    };
    let (x0, x1) = axis(0);
    let (y0, y1) = axis(1);
    let (z0, z1) = axis(2);
    let t0 = x0.max(y0).max(z0).max(t_min);
    let t1 = x1.min(y1).min(z1).min(t_max) * T_FAR_SCALE;
    (t0 <= t1).then_some(t0)
}

/// `shaders/common/ray_offset.wgsl`'s `offset_ray_origin`: `p` moved along `n` by 256 ulps of
/// its largest coordinate, at least 2^-16 (for rays spawned from surfaces on the CPU).
pub(crate) fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    p + n * (p.abs().max_element() * (256.0 / 8_388_608.0)).max(1.0 / 65536.0)
}

/// Affine 3x4 row-major times a point.
pub(crate) fn transform_point(m: &[[f32; 4]; 3], p: Vec3) -> Vec3 {
    let r = |i: usize| m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
    Vec3::new(r(0), r(1), r(2))
}

/// Affine 3x4 row-major times a vector (no translation).
pub(crate) fn transform_vector(m: &[[f32; 4]; 3], d: Vec3) -> Vec3 {
    let r = |i: usize| m[i][0] * d.x + m[i][1] * d.y + m[i][2] * d.z;
    Vec3::new(r(0), r(1), r(2))
}

/// The 2D edge function `P x Q = Px Qy - Py Qx` of sheared vertices `p`, `q`, as the difference
/// of the two rounded products. Its sign is the comparison of the products, which is what the
/// WGSL's `trace_edge` tests (a comparison cannot be fused into an FMA): swapping `p` and `q`
/// swaps the products bitwise, so both triangles sharing an edge see opposite signs, or both
/// zero. Here nothing is fused, so the difference has exactly that sign.
pub(crate) fn edge_function(p: (f32, f32), q: (f32, f32)) -> f32 {
    p.0 * q.1 - p.1 * q.0
}

/// A ray prepared for the watertight ray-triangle test in one space (object space here).
#[derive(Debug, Clone, Copy)]
pub struct WatertightRay {
    /// Origin.
    org: Vec3,
    /// Direction.
    dir: Vec3,
    /// The axis of the largest `|dir|` component, and the two others (swapped when
    /// `dir[kz] < 0` to keep the winding).
    kx: usize,
    /// The second axis.
    ky: usize,
    /// The third axis.
    kz: usize,
    /// Shear `dir[kx] / dir[kz]`, `dir[ky] / dir[kz]` and scale `1 / dir[kz]`.
    sx: f32,
    /// Shear `dir[ky] / dir[kz]`.
    sy: f32,
    /// Scale `1 / dir[kz]`.
    sz: f32,
}

impl WatertightRay {
    /// `None` for a zero direction.
    pub fn new(org: Vec3, dir: Vec3) -> Option<Self> {
        let a = dir.abs();
        let kz = if a.x > a.y && a.x > a.z {
            0
        } else if a.y > a.z {
            1
        } else {
            2
        };
        if dir[kz] == 0.0 || !dir[kz].is_finite() {
            return None;
        }
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Some(Self { org, dir, kx, ky, kz, sx: dir[kx] / dir[kz], sy: dir[ky] / dir[kz], sz: 1.0 / dir[kz] })
    }

    /// Woop-Benthin-Wald watertight test: translate the vertices to the origin, shear them so
    /// the ray is +z, and evaluate the edge functions `U = E(v1, v2)` (weight of v0),
    /// `V = E(v2, v0)` (weight of v1), `W = E(v0, v1)` (weight of v2) with `edge_function`.
    /// Accepted iff none is < 0 or none is > 0 (an exact 0 counts as either sign, so a ray
    /// through a shared edge or vertex hits every triangle around it, never none; with
    /// sign-exact-or-zero f32 edge functions the triangle that truly contains the ray always
    /// passes), and `det = U + V + W != 0`. Returns `(t, u, v, front_face)` for
    /// `t_min < t <= t_max` (`u`, `v` the weights of v1, v2); `front_face` is
    /// `dot((v1 - v0) x (v2 - v0), dir) < 0`, counter-clockwise seen from the origin.
    pub fn intersect(&self, tri: &GpuTriangle, t_min: f32, t_max: f32) -> Option<(f32, f32, f32, bool)> {
        let (p0, p1, p2) = (Vec3::from(tri.v0), Vec3::from(tri.v1), Vec3::from(tri.v2));
        let a = p0 - self.org;
        let b = p1 - self.org;
        let c = p2 - self.org;
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a2 = (a[kx] - self.sx * a[kz], a[ky] - self.sy * a[kz]);
        let b2 = (b[kx] - self.sx * b[kz], b[ky] - self.sy * b[kz]);
        let c2 = (c[kx] - self.sx * c[kz], c[ky] - self.sy * c[kz]);
        let u = edge_function(b2, c2);
        let v = edge_function(c2, a2);
        let w = edge_function(a2, b2);
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let az = self.sz * a[kz];
        let bz = self.sz * b[kz];
        let cz = self.sz * c[kz];
        let t = (u * az + v * bz + w * cz) / det;
        // Written so that a NaN `t` is rejected.
        if !(t > t_min && t <= t_max) {
            return None;
        }
        if t <= t_error_bound([a2, b2, c2], [az, bz, cz], [u, v, w], det, (self.dir[kx].abs(), self.dir[ky].abs())) {
            return None;
        }
        let front_face = (p1 - p0).cross(p2 - p0).dot(self.dir) < 0.0;
        Some((t, v / det, w / det, front_face))
    }

    /// The shear rows of the WGSL's `TraceRay` (`row_x = e_kx - sx e_kz`,
    /// `row_y = e_ky - sy e_kz`): their cross product is `|sz|` times the direction.
    fn shear_rows(&self) -> (Vec3, Vec3) {
        let mut row_x = Vec3::ZERO;
        let mut row_y = Vec3::ZERO;
        row_x[self.kx] = 1.0;
        row_x[self.kz] = -self.sx;
        row_y[self.ky] = 1.0;
        row_y[self.kz] = -self.sy;
        (row_x, row_y)
    }
}

/// Whether a hit the watertight test accepted is on `tri`'s back face, as the WGSL's
/// `trace_back_facing` decides it for back-face culling: `dot((v1 - v0) x (v2 - v0), dir) > 0`
/// with the direction taken as `row_x x row_y` (a positive multiple of it), flipped where a
/// merged-layout triangle's instance mirrors, so the facing is the object-space one.
pub(crate) fn back_facing(ray: &WatertightRay, tri: &GpuTriangle) -> bool {
    let (p0, p1, p2) = (Vec3::from(tri.v0), Vec3::from(tri.v1), Vec3::from(tri.v2));
    let (row_x, row_y) = ray.shear_rows();
    ((p1 - p0).cross(p2 - p0).dot(row_x.cross(row_y)) > 0.0) != (tri.flags & TRI_MIRRORED != 0)
}

/// A conservative bound on the rounding error of the watertight test's `t` (Pharr, Jakob and
/// Humphreys, PBR 3rd ed. §3.9.2): a hit closer than this may lie behind the origin, so it is
/// rejected. Without it, a ray leaving a large triangle's surface at a shallow angle can hit
/// that triangle again at a tiny positive t (the sheared z values are large and cancel).
/// `shear` is `(|dir[kx]|, |dir[ky]|)`: the shear term `S_x p_z` of a sheared `x` is
/// `|dir[kx]|` times the sheared `z`, where PBR bounds it by the sheared `z` itself, which
/// rejects true hits of grazing rays (and is too small for directions longer than 1).
pub(crate) fn t_error_bound(xy: [(f32, f32); 3], z: [f32; 3], e: [f32; 3], det: f32, shear: (f32, f32)) -> f32 {
    let gamma = |n: f32| n * (f32::EPSILON * 0.5) / (1.0 - n * f32::EPSILON * 0.5);
    let max_z = z.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let max_x = xy.iter().fold(0.0f32, |m, v| m.max(v.0.abs()));
    let max_y = xy.iter().fold(0.0f32, |m, v| m.max(v.1.abs()));
    let max_e = e.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let delta_z = gamma(3.0) * max_z;
    let delta_x = gamma(5.0) * (max_x + shear.0 * max_z);
    let delta_y = gamma(5.0) * (max_y + shear.1 * max_z);
    let delta_e = 2.0 * (gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    3.0 * (gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) * (1.0 / det).abs()
}

/// What one traversal touched: the loads the `compute` back-end makes for it are these
/// counts times the sizes of the GPU layout's records.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TraversalCounts {
    /// Interior nodes visited, TLAS and BLAS (each reads its two children: 64 bytes).
    pub interior: u64,
    /// Leaves visited.
    pub leaves: u64,
    /// Triangles tested (48 bytes each).
    pub triangles: u64,
    /// Instances entered (64 of their 112 bytes are read).
    pub instances: u64,
}

impl TraversalCounts {
    /// Adds `o`'s counts.
    pub fn add(&mut self, o: &TraversalCounts) {
        self.interior += o.interior;
        self.leaves += o.leaves;
        self.triangles += o.triangles;
        self.instances += o.instances;
    }

    /// Bytes of nodes, triangles and instances the `compute` back-end loads for them.
    pub fn bytes(&self) -> u64 {
        64 * self.interior + 48 * self.triangles + 64 * self.instances
    }
}

/// Traverses a [`GpuAccel`] on the CPU.
#[derive(Debug, Clone, Copy)]
pub struct CpuTraverser<'a> {
    /// The structure traversed.
    accel: &'a GpuAccel,
    /// The scene `accel` was built from, for the alpha test (none: no alpha test).
    scene: Option<&'a crate::scene::Scene>,
}

impl<'a> CpuTraverser<'a> {
    /// A traverser of `accel` without an alpha test.
    pub fn new(accel: &'a GpuAccel) -> Self {
        Self { accel, scene: None }
    }

    /// A traverser that runs the alpha test of `scene`'s alpha-tested instances.
    pub fn with_scene(accel: &'a GpuAccel, scene: &'a crate::scene::Scene) -> Self {
        Self { accel, scene: Some(scene) }
    }

    /// The closest hit in `(t_min, t_max]`.
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        self.closest_flags(ray, TraceFlags::NONE)
    }

    /// Whether anything is hit in `(t_min, t_max]` (stops at the first hit found).
    pub fn any(&self, ray: &Ray) -> bool {
        self.any_flags(ray, TraceFlags::NONE)
    }

    /// [`CpuTraverser::closest`] with per-ray flags (the WGSL's `trace_closest_flags`).
    pub(crate) fn closest_flags(&self, ray: &Ray, flags: TraceFlags) -> Option<Hit> {
        self.trace(ray, false, flags, &mut TraversalCounts::default())
    }

    /// [`CpuTraverser::any`] with per-ray flags (the WGSL's `trace_any_flags`).
    pub(crate) fn any_flags(&self, ray: &Ray, flags: TraceFlags) -> bool {
        self.trace(ray, true, flags, &mut TraversalCounts::default()).is_some()
    }

    /// [`CpuTraverser::closest`] (`any_hit` false) or [`CpuTraverser::any`], adding what the
    /// traversal touched to `counts`.
    pub fn counted(&self, ray: &Ray, any_hit: bool, counts: &mut TraversalCounts) -> Option<Hit> {
        self.trace(ray, any_hit, TraceFlags::NONE, counts)
    }

    /// [`CpuTraverser::closest`] for many rays, in parallel.
    pub fn closest_many(&self, rays: &[Ray]) -> Vec<Option<Hit>> {
        rays.par_iter().map(|r| self.closest(r)).collect()
    }

    /// [`CpuTraverser::any`] for many rays, in parallel.
    pub fn any_many(&self, rays: &[Ray]) -> Vec<bool> {
        rays.par_iter().map(|r| self.any(r)).collect()
    }

    fn trace(&self, ray: &Ray, any_hit: bool, flags: TraceFlags, counts: &mut TraversalCounts) -> Option<Hit> {
        let a = self.accel;
        if !ray_is_valid(ray) {
            return None;
        }
        let slab = SlabRay::new(ray.origin, ray.dir);
        traverse(&a.tlas_nodes, 0, &slab, (ray.t_min, ray.t_max), any_hit, counts, |k, t_far, counts| {
            let inst = a.instances.get(k as usize)?;
            if inst.mask == 0 {
                return Some(None);
            }
            counts.instances += 1;
            Some(self.trace_instance(inst, ray, t_far, any_hit, flags, counts))
        })
    }

    /// The closest hit in `[ray.t_min, t_far]` within one instance.
    fn trace_instance(&self, inst: &GpuInstance, ray: &Ray, t_far: f32, any_hit: bool, flags: TraceFlags, counts: &mut TraversalCounts) -> Option<Hit> {
        self.trace_instance_from(inst, inst.blas_root, ray, t_far, (any_hit, flags), counts)
    }

    /// [`CpuTraverser::trace_instance`] from node `root` of its BLAS.
    fn trace_instance_from(
        &self,
        inst: &GpuInstance,
        root: u32,
        ray: &Ray,
        t_far: f32,
        (any_hit, flags): (bool, TraceFlags),
        counts: &mut TraversalCounts,
    ) -> Option<Hit> {
        let a = self.accel;
        let o = transform_point(&inst.world_to_object, ray.origin);
        let d = transform_vector(&inst.world_to_object, ray.dir);
        let wt = WatertightRay::new(o, d)?;
        let slab = SlabRay::new(o, d);
        traverse(&a.blas_nodes, root, &slab, (ray.t_min, t_far), any_hit, counts, |k, t_far, counts| {
            let tri = a.triangles.get(k as usize)?;
            counts.triangles += 1;
            Some(self.triangle_hit(inst, tri, &wt, (ray.t_min, t_far), flags))
        })
    }

    /// The hit of one triangle of `inst` in `(t_min, t_far]`, if the watertight test accepts it
    /// and neither back-face culling nor the alpha test drops it.
    fn triangle_hit(&self, inst: &GpuInstance, tri: &GpuTriangle, wt: &WatertightRay, (t_min, t_far): (f32, f32), flags: TraceFlags) -> Option<Hit> {
        let (t, u, v, front_face) = wt.intersect(tri, t_min, t_far)?;
        if flags.culls_back_faces() && back_facing(wt, tri) {
            return None;
        }
        let hit = if inst.instance_id == MERGED_INSTANCE {
            Hit { t, instance_id: tri.instance, prim: tri.prim, u, v, front_face: front_face != (tri.flags & TRI_MIRRORED != 0) }
        } else {
            Hit { t, instance_id: inst.instance_id, prim: tri.prim, u, v, front_face }
        };
        let tested = inst.flags & INSTANCE_ALPHA != 0 || tri.flags & TRI_ALPHA != 0;
        if let Some(scene) = self.scene.filter(|_| tested) {
            if !super::alpha::visible(scene, hit.instance_id as usize, hit.prim as usize, [u as f64, v as f64]) {
                return None;
            }
        }
        Some(hit)
    }
}

/// Where the rays within a sphere start ([`CpuTraverser::start_within`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TraceStart {
    /// At the root: the scene is not one merged instance (or the start is off).
    Root,
    /// Below it: rays whose segment stays in the box `lo`..`hi` start at `node` of the merged
    /// instance `instance`'s BLAS (`None`: nothing within reach); other rays at the root.
    Within {
        /// The merged instance.
        instance: u32,
        /// The start node, if anything lies within reach.
        node: Option<u32>,
        /// The box of the sphere.
        lo: Vec3,
        /// The box of the sphere.
        hi: Vec3,
    },
}

impl CpuTraverser<'_> {
    /// The node where rays that stay within `radius` of `origin` start (the WGSL's
    /// `trace_start_within`, one start node): from the root of the merged instance's BLAS
    /// down, while only one child's box overlaps the box of the sphere (widened as the WGSL
    /// widens it). Adds the nodes and the instance it reads to `counts`.
    pub fn start_within(&self, origin: Vec3, radius: f32, counts: &mut TraversalCounts) -> TraceStart {
        let a = self.accel;
        let e = radius * 1.0001 + origin.abs().max_element() * 1e-6;
        let (lo, hi) = (origin - Vec3::splat(e), origin + Vec3::splat(e));
        let overlaps = |n: &GpuBvhNode| (0..3).all(|k| n.min[k] <= hi[k] && lo[k] <= n.max[k]);
        let Some(root) = a.tlas_nodes.first().filter(|r| r.count == 1 && radius >= 0.0) else { return TraceStart::Root };
        let Some(inst) = a.instances.get(root.left_or_first as usize) else { return TraceStart::Root };
        if inst.instance_id != MERGED_INSTANCE || inst.mask == 0 || inst.flags & INSTANCE_ALPHA != 0 {
            return TraceStart::Root;
        }
        counts.instances += 1;
        let mut node = overlaps(root).then_some(inst.blas_root);
        while let Some(n) = node.and_then(|k| a.blas_nodes.get(k as usize)).filter(|n| n.count == 0) {
            counts.interior += 1;
            let (l, r) = (n.left_or_first, n.left_or_first.wrapping_add(1));
            let inside = |k: u32| a.blas_nodes.get(k as usize).is_some_and(overlaps);
            node = match (inside(l), inside(r)) {
                (true, true) => break,
                (true, false) => Some(l),
                (false, true) => Some(r),
                (false, false) => None,
            };
        }
        TraceStart::Within { instance: root.left_or_first, node, lo, hi }
    }

    /// Whether an any-hit `ray` hits anything, started where `start` says (the WGSL's
    /// `trace_transmittance_within` for opaque geometry, for the rays it is given: from the
    /// sphere's centre, reaching no farther than its radius); a ray whose segment leaves the
    /// start's box, which the WGSL's merged path does not test for, takes the whole traversal
    /// here. Adds what it touched to `counts`.
    pub fn any_within(&self, ray: &Ray, start: &TraceStart, counts: &mut TraversalCounts) -> bool {
        let TraceStart::Within { instance, node, lo, hi } = *start else { return self.counted(ray, true, counts).is_some() };
        if !ray_is_valid(ray) {
            return false;
        }
        let end = ray.origin + ray.dir * ray.t_max;
        if ray.origin.min(end).cmplt(lo).any() || ray.origin.max(end).cmpgt(hi).any() {
            return self.counted(ray, true, counts).is_some();
        }
        let (Some(node), Some(inst)) = (node, self.accel.instances.get(instance as usize)) else { return false };
        self.trace_instance_from(inst, node, ray, ray.t_max, (true, TraceFlags::NONE), counts).is_some()
    }
}

/// The stack traversal both levels share (steps 3-4 of the module docs): from `root`, whose
/// box must pass the slab test, to every leaf in nearer-first order. `leaf(k, t_far, counts)`
/// tests primitive `k` of a leaf against the current closest `t_far`: `None` when there is no
/// such primitive (the rest of the leaf is skipped), `Some(None)` for no hit, `Some(Some(hit))`
/// for a hit, which becomes the closest (and the answer at once with `any_hit`).
fn traverse(
    nodes: &[GpuBvhNode],
    root: u32,
    slab: &SlabRay,
    (t_min, mut t_far): (f32, f32),
    any_hit: bool,
    counts: &mut TraversalCounts,
    mut leaf: impl FnMut(u32, f32, &mut TraversalCounts) -> Option<Option<Hit>>,
) -> Option<Hit> {
    slab_test(nodes.get(root as usize)?, slab, t_min, t_far)?;
    let mut best: Option<Hit> = None;
    let mut stack = [0u32; TRAVERSAL_STACK_SIZE];
    let mut sp = 0usize;
    let mut node = root;
    while let Some(n) = nodes.get(node as usize) {
        if n.count > 0 {
            counts.leaves += 1;
            for k in n.left_or_first..n.left_or_first.saturating_add(n.count) {
                let Some(found) = leaf(k, t_far, counts) else { break };
                if let Some(h) = found {
                    t_far = h.t;
                    best = Some(h);
                    if any_hit {
                        return best;
                    }
                }
            }
        } else if let Some(next) = {
            counts.interior += 1;
            visit_children(nodes, n, slab, t_min, t_far, &mut stack, &mut sp)
        } {
            node = next;
            continue;
        }
        if sp == 0 {
            break;
        }
        sp -= 1;
        node = stack[sp];
    }
    best
}

/// Tests both children of interior node `n`; returns the child to visit next (the nearer, left
/// on a tie) after pushing the other one if it is hit too.
#[allow(clippy::too_many_arguments)]
fn visit_children(
    nodes: &[GpuBvhNode],
    n: &GpuBvhNode,
    slab: &SlabRay,
    t_min: f32,
    t_far: f32,
    stack: &mut [u32; TRAVERSAL_STACK_SIZE],
    sp: &mut usize,
) -> Option<u32> {
    let l = n.left_or_first;
    let r = l.wrapping_add(1);
    let tl = nodes.get(l as usize).and_then(|c| slab_test(c, slab, t_min, t_far));
    let tr = nodes.get(r as usize).and_then(|c| slab_test(c, slab, t_min, t_far));
    match (tl, tr) {
        (Some(a), Some(b)) => {
            let (near, far) = if a <= b { (l, r) } else { (r, l) };
            // The builder bounds the depth so the stack cannot overflow; if a foreign tree
            // does, the farther subtree is skipped rather than written out of bounds.
            if *sp < TRAVERSAL_STACK_SIZE {
                stack[*sp] = far;
                *sp += 1;
            }
            Some(near)
        }
        (Some(_), None) => Some(l),
        (None, Some(_)) => Some(r),
        (None, None) => None,
    }
}
