//! The f64 reference of the ray-traced channels at small sizes: primary visibility, the shadow
//! mask, ambient occlusion and the first mirror-reflection ray, computed per pixel with the
//! brute-force caster of [`crate::accel::reference`], so that tests compare both GPU back-ends
//! with it pixel by pixel rather than statistically.
//!
//! Every ray is built in f32 exactly as the layer's shader builds it (camera rays as
//! `shaders/common/camera.wgsl`, shadow rays as `shaders/rt/shadow.wgsl`, AO directions with the
//! same PCG / R2 / net numbers and cosine mapping as `shaders/common/ao_lane.wgsl` and
//! `shaders/common/sampling.wgsl`, reflection rays as the first bounce of
//! `shaders/rt/reflection.wgsl` for a mirror), from the surface points a G-buffer holds
//! ([`SurfacePoint`]): either the GPU's own G-buffer, which isolates the trace pass being
//! checked, or the reference's ([`ReferenceRenderer::surfaces`]). Only the f32 functions the
//! GPU evaluates with its own rounding (division, sqrt, sin, cos, normalisation) can differ,
//! by a few ulps. Each ray is then traced in f64, and every answer carries its margin
//! ([`Classified`]): a GPU answer may differ from the reference's only where the margin is of
//! that order.
//!
//! Alpha-tested geometry: the reference runs the same alpha test, and a hit whose alpha
//! (`base_color.a` x the texture's level-0 bilinear alpha) is within
//! `crate::accel::reference::ALPHA_BAND` of the cutoff has margin 0, so a pixel on an alpha
//! edge may go either way; every other alpha decision leaves the margin geometric. The GPU
//! reads the texture-array fallback's resampled texels, which move alpha edges by a fraction
//! of a source texel: compare those renders on scenes whose pixels keep clear of alpha edges.

use super::cpu_traverse::{offset_ray_origin, Ray};
use super::reference::{RefHit, Reference};
use crate::scene::{Camera, Light, PointLight, Scene};
use glam::Vec3;
use rayon::prelude::*;

/// A reference answer and its margin: the smallest relative perturbation of the ray (distance
/// over coordinate magnitude, [`crate::accel::reference`]'s units) that could change it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Classified<T> {
    /// The answer.
    pub value: T,
    /// The smallest relative perturbation of the ray that could change it.
    pub margin: f64,
}

/// What a G-buffer holds of a surface point, in f32: the position, the geometric normal (facing
/// the camera) and the shading normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// World-space position.
    pub position: Vec3,
    /// Geometric normal, facing the camera.
    pub geo_normal: Vec3,
    /// Shading normal.
    pub normal: Vec3,
    /// How far shadow rays leave above the surface along `geo_normal` (the G-buffer's
    /// `geo_normal.w`: the shadow-terminator offset; 0 on flat triangles).
    pub shadow_offset: f32,
}

/// One pixel of the shadow mask: lit by the directional light (r channel), and by the point
/// light (g channel; `None` without one). A surface facing away from a light is unlit without a
/// ray (margin infinite), as the shader does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowPixel {
    /// Lit by the directional light.
    pub sun: Classified<bool>,
    /// Lit by the point light (`None` without one).
    pub point: Option<Classified<bool>>,
}

/// The AO layer's parameters that decide its rays (`layers/rt_ao.ron`); the range is the
/// final one (`range + range_scale * scene radius`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AoSettings {
    /// Rays per pixel.
    pub rays: u32,
    /// Ray length, world units.
    pub range: f32,
    /// 0: white noise (PCG per ray), 1: R2 rotated per pixel, 2: a scrambled (0,k,2)-net per
    /// pixel in cell order ([`net_point`]).
    pub sampling: u32,
    /// Seed of the sample sequence.
    pub seed: u32,
}

/// The f64 reference renderer of one scene.
pub struct ReferenceRenderer {
    /// The f64 caster.
    pub reference: Reference,
}

impl ReferenceRenderer {
    /// The renderer of `scene`.
    pub fn new(scene: &Scene) -> Self {
        Self { reference: Reference::new(scene) }
    }

    /// The camera rays through the pixel centres of a `size` image, row by row, as
    /// `camera_dir` builds them (`t` over `[0, 3e38]`).
    pub fn camera_rays(camera: &Camera, size: (u32, u32)) -> Vec<Ray> {
        camera.rays(size, 1).into_iter().map(|(o, d)| Ray::with_interval(o, d, 0.0, 3.0e38)).collect()
    }

    /// Primary visibility: the closest hit of each ray, with its margin.
    pub fn visibility(&self, rays: &[Ray]) -> Vec<Classified<Option<RefHit>>> {
        rays.par_iter()
            .map(|r| {
                let (value, margin) = self.reference.closest_with_margin(r);
                Classified { value, margin }
            })
            .collect()
    }

    /// The reference's own G-buffer from primary hits: the f64 hit point and the triangle's
    /// normal facing the ray (as `surface_at_cone` computes them), rounded to f32. The shading
    /// normal is the geometric one (vertex normals are not interpolated here).
    pub fn surfaces(&self, rays: &[Ray], hits: &[Classified<Option<RefHit>>]) -> Vec<Option<SurfacePoint>> {
        rays.iter()
            .zip(hits)
            .map(|(r, h)| {
                let h = h.value?;
                let v = self.reference.triangle(h.instance_id, h.prim)?;
                let d = r.dir.as_dvec3();
                let mut n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                if n.dot(d) > 0.0 {
                    n = -n;
                }
                let p = r.origin.as_dvec3() + h.t * d;
                Some(SurfacePoint { position: p.as_vec3(), geo_normal: n.as_vec3(), normal: n.as_vec3(), shadow_offset: 0.0 })
            })
            .collect()
    }

    /// The shadow mask of `rt_shadow` (`shaders/rt/shadow.wgsl`): from the offset surface point
    /// (lifted by the part of its shadow-terminator offset `terminator_lift` gives)
    /// one ray towards the directional light (unbounded) and one towards the point light
    /// (stopping at 0.9999 of its distance), each only where the surface faces the light.
    pub fn shadow(&self, surfaces: &[Option<SurfacePoint>], light: &Light, point_light: Option<&PointLight>) -> Vec<Option<ShadowPixel>> {
        let l = light.direction.normalize();
        let facing_away = Classified { value: false, margin: f64::INFINITY };
        surfaces
            .par_iter()
            .map(|s| {
                let s = s.as_ref()?;
                let n = s.geo_normal.normalize();
                // With a shadow-terminator offset the shading normal decides which lights the
                // surface faces, and each light's ray leaves from the part of the offset its
                // angle asks for (as shaders/rt/shadow.wgsl).
                let facing = if s.shadow_offset > 0.0 { s.normal } else { n };
                let origin_towards = |dir: Vec3| offset_ray_origin(s.position + n * terminator_lift(s.shadow_offset, s.normal, n, dir), n);
                let sun = if facing.dot(l) > 0.0 { self.lit(&Ray::with_interval(origin_towards(l), l, 0.0, 3.0e38)) } else { facing_away };
                let point = point_light.filter(|p| p.intensity > 0.0).map(|p| {
                    let origin = origin_towards((p.position - s.position).normalize());
                    let to_light = p.position - origin;
                    let dist = to_light.length();
                    let dir = to_light / dist;
                    if facing.dot(dir) > 0.0 {
                        self.lit(&Ray::with_interval(origin, dir, 0.0, dist * 0.9999))
                    } else {
                        facing_away
                    }
                });
                Some(ShadowPixel { sun, point })
            })
            .collect()
    }

    fn lit(&self, ray: &Ray) -> Classified<bool> {
        let (hit, margin) = self.reference.any_with_margin(ray);
        Classified { value: !hit, margin }
    }

    /// The AO rays of `rt_ao` (`shaders/rt/ao.wgsl`) for every pixel of a `size.0`-wide image:
    /// per ray, whether it is unoccluded. Sky pixels have no rays (the layer writes 1).
    pub fn ao(&self, surfaces: &[Option<SurfacePoint>], width: u32, settings: &AoSettings) -> Vec<Option<Vec<Classified<bool>>>> {
        surfaces
            .par_iter()
            .enumerate()
            .map(|(i, s)| {
                let s = s.as_ref()?;
                let pixel = (i as u32 % width, i as u32 / width);
                let n = s.geo_normal.normalize();
                let origin = offset_ray_origin(s.position, n);
                Some(
                    ao_numbers(pixel, settings)
                        .into_iter()
                        .map(|u| self.lit(&Ray::with_interval(origin, cosine_hemisphere(n, u), 0.0, settings.range)))
                        .collect(),
                )
            })
            .collect()
    }

    /// The first ray of `rt_reflection` for a mirror (`shaders/rt/reflection.wgsl`, roughness
    /// below 0.03): the view direction reflected about the shading normal, folded back above
    /// the surface about the geometric normal where it points into it; its closest hit.
    pub fn mirror(&self, camera_position: Vec3, surfaces: &[Option<SurfacePoint>]) -> Vec<Option<Classified<Option<RefHit>>>> {
        surfaces
            .par_iter()
            .map(|s| {
                let ray = mirror_ray(camera_position, s.as_ref()?);
                let (value, margin) = self.reference.closest_with_margin(&ray);
                Some(Classified { value, margin })
            })
            .collect()
    }
}

/// How much of a shadow-terminator offset `offset` a shadow ray towards `l` leaves from:
/// `terminator_lift` in `shaders/common/shadow_ray.wgsl` (Cycles' cutoff 0.1 and blend).
pub(crate) fn terminator_lift(offset: f32, n: Vec3, geo: Vec3, l: Vec3) -> f32 {
    if offset <= 0.0 {
        return 0.0;
    }
    let (nl, ngl) = (n.dot(l), geo.dot(l));
    let amount = if nl < 0.1 { (2.0 - (ngl + nl) / 0.1).clamp(0.0, 1.0) } else { (1.0 - ngl / 0.1).clamp(0.0, 1.0) };
    offset * amount
}

/// The mirror ray from a surface point seen from `camera_position` (module docs of
/// [`ReferenceRenderer::mirror`]), in f32 as the shader builds it.
pub(crate) fn mirror_ray(camera_position: Vec3, s: &SurfacePoint) -> Ray {
    let n = s.normal.normalize();
    let geo = s.geo_normal.normalize();
    let v = (camera_position - s.position).normalize();
    let mut dir = reflect(-v, n);
    if dir.dot(geo) <= 0.0 {
        dir = reflect(dir, geo);
    }
    Ray::with_interval(offset_ray_origin(s.position, geo), dir, 0.0, 3.0e38)
}

/// WGSL's `reflect`: `i - 2 dot(n, i) n`.
fn reflect(i: Vec3, n: Vec3) -> Vec3 {
    i - 2.0 * n.dot(i) * n
}

/// `pcg_hash` of `shaders/common/sampling.wgsl`.
pub(crate) fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Top 24 bits of a hash as a number in [0, 1).
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// `pixel_random2`.
fn pixel_random2(pixel: (u32, u32), seed: u32) -> [f32; 2] {
    let h1 = pcg_hash(pixel.0 ^ pcg_hash(pixel.1 ^ pcg_hash(seed)));
    [unit(h1), unit(pcg_hash(h1))]
}

/// `fract` as WGSL defines it: `x - floor(x)`.
fn fract(x: f32) -> f32 {
    x - x.floor()
}

/// `r2_sample`: the i-th point of the R2 sequence (the plastic number's powers in f32).
pub(crate) fn r2_sample(i: u32) -> [f32; 2] {
    let g: f32 = 1.324_717_9;
    let step = [1.0 / g, 1.0 / (g * g)];
    let k = (i + 1) as f32;
    [fract(0.5 + k * step[0]), fract(0.5 + k * step[1])]
}

/// The uniform number pairs of a pixel's AO rays, in the order `ao.wgsl` draws them.
pub(crate) fn ao_numbers(pixel: (u32, u32), settings: &AoSettings) -> Vec<[f32; 2]> {
    let rotation = pixel_random2(pixel, settings.seed);
    let mut state = pcg_hash(pixel.0 ^ pcg_hash(pixel.1 ^ pcg_hash(settings.seed.wrapping_add(0x9e37_79b9))));
    let net_scramble = [pcg_hash(state), pcg_hash(pcg_hash(state))];
    (0..settings.rays)
        .map(|i| {
            if settings.sampling == 0 {
                state = pcg_hash(state);
                let a = state;
                state = pcg_hash(state);
                [unit(a), unit(state)]
            } else if settings.sampling == 2 {
                net_point(i, settings.rays, net_scramble)
            } else {
                let r = r2_sample(i);
                [fract(r[0] + rotation[0]), fract(r[1] + rotation[1])]
            }
        })
        .collect()
}

/// `ao_net_point` (`shaders/common/ao_lane.wgsl`): ray `i` of `n`'s point of the pixel's
/// scrambled Hammersley net, the one in cell `i` (Morton order) of its 2^a x 2^b grid where `n`
/// is a power of two, else point `i` with its y stratified.
pub(crate) fn net_point(i: u32, n: u32, scramble: [u32; 2]) -> [f32; 2] {
    let to_unit = |v: u32| (v >> 8) as f32 * (1.0 / 16_777_216.0);
    if n <= 1 {
        return scramble.map(to_unit);
    }
    if !n.is_power_of_two() {
        let y = (i as f32 + to_unit(scramble[1])) / n as f32;
        return [to_unit(i.reverse_bits() ^ scramble[0]), y.min(0.999_999_94)];
    }
    let k = n.trailing_zeros();
    let (a, b) = (k.div_ceil(2), k / 2);
    let mut cx = if a > b { ((i >> (k - 1)) & 1) << b } else { 0 };
    let mut cy = 0;
    for t in 0..b {
        cx |= ((i >> (2 * t)) & 1) << t;
        cy |= ((i >> (2 * t + 1)) & 1) << t;
    }
    let low = (cx ^ (scramble[0] >> (32 - a))).reverse_bits() >> (32 - a);
    let high = if b > 0 { cy ^ (scramble[1] >> (32 - b)) } else { 0 };
    let j = (high << a) | low;
    [to_unit(j.reverse_bits() ^ scramble[0]), to_unit((j << (32 - k)) ^ scramble[1])]
}

/// `cosine_hemisphere`: a cosine-weighted direction around unit `n` (basis of Duff et al.).
pub(crate) fn cosine_hemisphere(n: Vec3, u: [f32; 2]) -> Vec3 {
    let r = u[0].sqrt();
    let phi = 6.283_185_5 * u[1];
    let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u[0]).max(0.0).sqrt());
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = Vec3::new(b, s + n.y * n.y * a, -n.y);
    (local.x * t + local.y * bt + local.z * n).normalize()
}

#[cfg(test)]
mod tests {
    use super::{net_point, pcg_hash};

    #[test]
    fn the_net_has_one_point_a_cell_visited_in_morton_order() {
        for n in [2u32, 4, 8, 16, 32, 64, 128, 256, 1024] {
            let k = n.trailing_zeros();
            let (a, b) = (k.div_ceil(2), k / 2);
            for seed in 0..20u32 {
                let scramble = [pcg_hash(seed), pcg_hash(seed ^ 0x5bd1_e995)];
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let p = net_point(i, n, scramble);
                    assert!(p.iter().all(|v| (0.0..1.0).contains(v)), "n {n}: {p:?}");
                    let (cx, cy) = ((p[0] * (1u32 << a) as f32) as u32, (p[1] * (1u32 << b) as f32) as u32);
                    let cell = (cy << a | cx) as usize;
                    assert!(!seen[cell], "n {n}, seed {seed}: two points in cell ({cx}, {cy})");
                    seen[cell] = true;
                    // Ray i's cell is cell i in Morton order: its low bits alternate x and y.
                    for t in 0..b {
                        assert_eq!((cx >> t) & 1, (i >> (2 * t)) & 1, "n {n}, ray {i}: x bit {t}");
                        assert_eq!((cy >> t) & 1, (i >> (2 * t + 1)) & 1, "n {n}, ray {i}: y bit {t}");
                    }
                }
            }
        }
        // Not a power of two: y stratified, one point in each row of n.
        for i in 0..10 {
            let p = net_point(i, 10, [pcg_hash(1), pcg_hash(2)]);
            assert_eq!((p[1] * 10.0) as u32, i);
        }
    }
}
