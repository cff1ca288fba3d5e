//! What every procedural scene is built from: the seeded PRNG ([`Rng`]), value noise, the
//! [`MeshBuilder`] with its primitives (patches, boxes, lathes, sweeps), smooth-normal
//! generation, the procedural texture generators and materials.

use crate::scene::{Material, Mesh, TextureImage, Vertex};
use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

// ---------------------------------------------------------------------------------------------
// Random numbers and noise
// ---------------------------------------------------------------------------------------------

/// A splitmix64 generator ([`crate::util::SplitMix64`]) seeded for scene generation: tiny,
/// fast and fully deterministic.
#[derive(Debug, Clone)]
pub(crate) struct Rng(crate::util::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        let mut r = Rng(crate::util::SplitMix64(seed ^ 0x6A09_E667_F3BC_C908));
        r.next_u64();
        r
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        self.0.f()
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// An independent generator derived from this one.
    pub(crate) fn fork(&mut self) -> Rng {
        Rng::new(self.next_u64())
    }

    /// A 32-bit seed for the hash noise.
    pub(crate) fn seed32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }
}

/// A hash of a lattice point to [0, 1).
pub(crate) fn hash3(seed: u32, x: i32, y: i32, z: i32) -> f32 {
    let mut h = seed ^ 0x9E37_79B9;
    h = (h ^ (x as u32)).wrapping_mul(0x85EB_CA6B);
    h = (h ^ (h >> 13) ^ (y as u32)).wrapping_mul(0xC2B2_AE35);
    h = (h ^ (h >> 16) ^ (z as u32)).wrapping_mul(0x27D4_EB2D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    (h >> 8) as f32 / 16_777_216.0
}

fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// 3D value noise in [0, 1).
pub(crate) fn noise3(seed: u32, p: Vec3) -> f32 {
    let f = p.floor();
    let (x, y, z) = (f.x as i32, f.y as i32, f.z as i32);
    let t = p - f;
    let (u, v, w) = (smooth(t.x), smooth(t.y), smooth(t.z));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let c = |dx: i32, dy: i32, dz: i32| hash3(seed, x + dx, y + dy, z + dz);
    let x00 = lerp(c(0, 0, 0), c(1, 0, 0), u);
    let x10 = lerp(c(0, 1, 0), c(1, 1, 0), u);
    let x01 = lerp(c(0, 0, 1), c(1, 0, 1), u);
    let x11 = lerp(c(0, 1, 1), c(1, 1, 1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

/// Fractal 3D value noise, roughly in [-0.5, 0.5].
pub(crate) fn fbm3(seed: u32, p: Vec3, octaves: u32) -> f32 {
    let (mut sum, mut amp, mut freq, mut norm) = (0.0, 1.0, 1.0, 0.0);
    for o in 0..octaves {
        sum += amp * (noise3(seed.wrapping_add(o * 101), p * freq) - 0.5);
        norm += amp;
        amp *= 0.5;
        freq *= 2.03;
    }
    sum / norm
}

/// Tileable 2D fractal value noise over the unit square, precomputed as lattices.
pub(crate) struct TileNoise {
    octaves: Vec<(u32, Vec<f32>, f32)>,
}

impl TileNoise {
    /// `period` lattice cells across the square at the coarsest octave.
    pub fn new(rng: &mut Rng, period: u32, octaves: u32) -> Self {
        let mut v = Vec::new();
        let mut amp = 1.0;
        for o in 0..octaves {
            let p = period << o;
            let vals = (0..p * p).map(|_| rng.f32()).collect();
            v.push((p, vals, amp));
            amp *= 0.5;
        }
        Self { octaves: v }
    }

    /// Roughly in [-0.5, 0.5]; `u`, `v` wrap at 1.
    pub fn at(&self, u: f32, v: f32) -> f32 {
        let mut sum = 0.0;
        let mut norm = 0.0;
        for (p, vals, amp) in &self.octaves {
            let p = *p;
            let x = u.rem_euclid(1.0) * p as f32;
            let y = v.rem_euclid(1.0) * p as f32;
            let (xi, yi) = (x as u32 % p, y as u32 % p);
            let (tx, ty) = (smooth(x.fract()), smooth(y.fract()));
            let (x1, y1) = ((xi + 1) % p, (yi + 1) % p);
            let a = vals[(yi * p + xi) as usize];
            let b = vals[(yi * p + x1) as usize];
            let c = vals[(y1 * p + xi) as usize];
            let d = vals[(y1 * p + x1) as usize];
            let top = a + (b - a) * tx;
            let bot = c + (d - c) * tx;
            sum += amp * (top + (bot - top) * ty - 0.5);
            norm += amp;
        }
        sum / norm
    }
}

// ---------------------------------------------------------------------------------------------
// Mesh building
// ---------------------------------------------------------------------------------------------

/// Twice the area below which a triangle is dropped as degenerate.
const MIN_DOUBLE_AREA: f32 = 1e-8;

/// Positions, uvs and triangles; normals are derived from the winding when finished.
#[derive(Debug, Clone, Default)]
pub(crate) struct MeshBuilder {
    pos: Vec<Vec3>,
    uv: Vec<Vec2>,
    idx: Vec<u32>,
    /// Pairs of vertices at the same position whose normals are averaged (texture seams).
    seams: Vec<(u32, u32)>,
}

impl MeshBuilder {
    /// The triangles' vertex indices, three per triangle.
    pub(crate) fn idx(&self) -> &[u32] {
        &self.idx
    }

    pub fn new() -> Self {
        Self::default()
    }

    pub(crate) fn vert(&mut self, p: Vec3, uv: Vec2) -> u32 {
        debug_assert!(p.is_finite() && uv.is_finite(), "non-finite vertex {p} {uv}");
        self.pos.push(p);
        self.uv.push(uv);
        (self.pos.len() - 1) as u32
    }

    /// A triangle, counter-clockwise seen from its front; dropped if degenerate.
    pub fn tri(&mut self, a: u32, b: u32, c: u32) {
        let (pa, pb, pc) = (self.pos[a as usize], self.pos[b as usize], self.pos[c as usize]);
        if (pb - pa).cross(pc - pa).length() > MIN_DOUBLE_AREA && a != b && b != c && a != c {
            self.idx.extend_from_slice(&[a, b, c]);
        }
    }

    /// A quad a-b-c-d, counter-clockwise seen from its front, split along its shorter diagonal.
    pub fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        let (pa, pb, pc, pd) = (self.pos[a as usize], self.pos[b as usize], self.pos[c as usize], self.pos[d as usize]);
        if pa.distance_squared(pc) <= pb.distance_squared(pd) {
            self.tri(a, b, c);
            self.tri(a, c, d);
        } else {
            self.tri(a, b, d);
            self.tri(b, c, d);
        }
    }

    /// A (nu x nv)-cell grid over `f(u, v) -> (position, uv)` with u, v in [0, 1]. The front is
    /// the side of dP/du x dP/dv. With `wrap_u` the column u = 1 is a seam copy of u = 0 (same
    /// position, own uv) whose normals are averaged with it.
    pub fn grid(&mut self, nu: u32, nv: u32, wrap_u: bool, mut f: impl FnMut(f32, f32) -> (Vec3, Vec2)) {
        let base = self.pos.len() as u32;
        let row = nu + 1;
        for j in 0..=nv {
            let v = j as f32 / nv as f32;
            for i in 0..=nu {
                let u = i as f32 / nu as f32;
                let (p, t) = f(u, v);
                if wrap_u && i == nu {
                    let first = self.pos[(base + j * row) as usize];
                    self.vert(first, t);
                    self.seams.push((base + j * row, base + j * row + nu));
                } else {
                    self.vert(p, t);
                }
            }
        }
        for j in 0..nv {
            for i in 0..nu {
                let a = base + j * row + i;
                self.quad(a, a + 1, a + 1 + row, a + row);
            }
        }
    }

    /// Flips the triangles from `first_index` on if their summed normal points away from `dir`.
    pub(crate) fn face_towards(&mut self, first_index: usize, dir: Vec3) {
        let mut sum = Vec3::ZERO;
        for t in self.idx[first_index..].chunks_exact(3) {
            let (a, b, c) = (self.pos[t[0] as usize], self.pos[t[1] as usize], self.pos[t[2] as usize]);
            sum += (b - a).cross(c - a);
        }
        if sum.dot(dir) < 0.0 {
            for t in self.idx[first_index..].chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
    }

    /// A flat patch origin + u*eu + v*ev facing `facing`, with `nu` x `nv` cells and uvs of
    /// `uv_per_m` repeats per metre.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn patch(&mut self, origin: Vec3, eu: Vec3, ev: Vec3, nu: u32, nv: u32, uv_per_m: f32, facing: Vec3) {
        let first = self.idx.len();
        let (lu, lv) = (eu.length() * uv_per_m, ev.length() * uv_per_m);
        self.grid(nu.max(1), nv.max(1), false, |u, v| (origin + u * eu + v * ev, Vec2::new(u * lu, (1.0 - v) * lv)));
        self.face_towards(first, facing);
    }

    /// An axis-aligned box with outward faces, cells at most `cell` metres across.
    pub(crate) fn cuboid(&mut self, min: Vec3, max: Vec3, cell: f32, uv_per_m: f32) {
        let d = max - min;
        let n = |l: f32| ((l / cell).ceil() as u32).max(1);
        let (x, y, z) = (Vec3::new(d.x, 0.0, 0.0), Vec3::new(0.0, d.y, 0.0), Vec3::new(0.0, 0.0, d.z));
        self.patch(Vec3::new(max.x, min.y, min.z), z, y, n(d.z), n(d.y), uv_per_m, Vec3::X);
        self.patch(min, z, y, n(d.z), n(d.y), uv_per_m, -Vec3::X);
        self.patch(Vec3::new(min.x, max.y, min.z), x, z, n(d.x), n(d.z), uv_per_m, Vec3::Y);
        self.patch(min, x, z, n(d.x), n(d.z), uv_per_m, -Vec3::Y);
        self.patch(Vec3::new(min.x, min.y, max.z), x, y, n(d.x), n(d.y), uv_per_m, Vec3::Z);
        self.patch(min, x, y, n(d.x), n(d.y), uv_per_m, -Vec3::Z);
    }

    /// A surface of revolution about +y. `profile` is (radius, height), ordered so that the
    /// outside lies to its right (bottom centre, out, up the side, in to the top centre). A
    /// repeated point makes a crease. `radius_at(angle, profile_index)` scales the radius.
    pub(crate) fn lathe_with(&mut self, profile: &[Vec2], segments: u32, uv_u: f32, uv_v: f32, mut radius_at: impl FnMut(f32, usize) -> f32) {
        let mut cum = vec![0.0f32; profile.len()];
        for k in 1..profile.len() {
            cum[k] = cum[k - 1] + profile[k].distance(profile[k - 1]);
        }
        let last = (profile.len() - 1) as f32;
        self.grid(segments, profile.len() as u32 - 1, true, |u, v| {
            let k = (v * last).round() as usize;
            let a = u * TAU;
            let r = profile[k].x * radius_at(a, k);
            (Vec3::new(r * a.cos(), profile[k].y, -r * a.sin()), Vec2::new(u * uv_u, cum[k] * uv_v))
        });
    }

    pub(crate) fn lathe(&mut self, profile: &[Vec2], segments: u32, uv_u: f32, uv_v: f32) {
        self.lathe_with(profile, segments, uv_u, uv_v, |_, _| 1.0);
    }

    /// Sweeps a closed 2D `profile` (in the path's normal/binormal plane) along `path`; normals
    /// face away from the profile's inside. Open paths get flat end caps if `caps`.
    pub fn sweep(&mut self, path: &[Vec3], profile: &[Vec2], closed_path: bool, caps: bool, uv_per_m: f32) {
        let frames = frames(path, closed_path);
        let mut prof: Vec<Vec2> = profile.to_vec();
        let signed_area: f32 = (0..prof.len()).map(|i| prof[i].perp_dot(prof[(i + 1) % prof.len()])).sum();
        if signed_area < 0.0 {
            prof.reverse();
        }
        let mut plen = vec![0.0f32; path.len()];
        for k in 1..path.len() {
            plen[k] = plen[k - 1] + path[k].distance(path[k - 1]);
        }
        let np = prof.len() as u32;
        let nk = path.len() as u32;
        let perim: f32 = (0..prof.len()).map(|i| prof[i].distance(prof[(i + 1) % prof.len()])).sum();
        let base = self.pos.len() as u32;
        // Rows along the path, columns around the profile (with a seam copy).
        for k in 0..nk {
            let (c, n, b) = (path[k as usize], frames[k as usize].0, frames[k as usize].1);
            let mut acc = 0.0;
            for i in 0..=np {
                let p = prof[(i % np) as usize];
                if i > 0 {
                    acc += prof[(i - 1) as usize].distance(p);
                }
                self.vert(c + p.x * n + p.y * b, Vec2::new(acc / perim.max(1e-6) * (perim * uv_per_m).max(1.0).round(), plen[k as usize] * uv_per_m));
            }
            self.seams.push((base + k * (np + 1), base + k * (np + 1) + np));
        }
        let row = np + 1;
        let rows = if closed_path { nk } else { nk - 1 };
        for k in 0..rows {
            let k1 = (k + 1) % nk;
            for i in 0..np {
                let a = base + k * row + i;
                let b = base + k1 * row + i;
                // dP/dprofile x tangent is outward for a counter-clockwise profile.
                self.quad(a, a + 1, b + 1, b);
            }
        }
        if caps && !closed_path {
            for (k, dir) in [(0usize, -(path[1] - path[0])), (path.len() - 1, path[path.len() - 1] - path[path.len() - 2])] {
                let first = self.idx.len();
                let (n, b) = (frames[k].0, frames[k].1);
                let centroid = prof.iter().copied().sum::<Vec2>() / prof.len() as f32;
                let cb = self.pos.len() as u32;
                let c = self.vert(path[k] + centroid.x * n + centroid.y * b, Vec2::splat(0.5));
                for p in &prof {
                    self.vert(path[k] + p.x * n + p.y * b, Vec2::new(0.5, 0.5) + (*p - centroid) * uv_per_m);
                }
                for i in 0..np {
                    self.tri(c, cb + 1 + i, cb + 1 + (i + 1) % np);
                }
                self.face_towards(first, dir);
            }
        }
    }

    /// Applies `f` to every position from vertex `first` on.
    pub(crate) fn map_positions(&mut self, first: usize, mut f: impl FnMut(Vec3) -> Vec3) {
        for p in &mut self.pos[first..] {
            *p = f(*p);
        }
    }

    /// The finished mesh: area-weighted smooth normals over shared vertices (seam copies
    /// averaged), unused vertices dropped.
    pub fn finish(self, name: &str) -> Mesh {
        let mut acc = vec![Vec3::ZERO; self.pos.len()];
        for t in self.idx.chunks_exact(3) {
            let (a, b, c) = (self.pos[t[0] as usize], self.pos[t[1] as usize], self.pos[t[2] as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                acc[i as usize] += n;
            }
        }
        for &(a, b) in &self.seams {
            let s = acc[a as usize] + acc[b as usize];
            acc[a as usize] = s;
            acc[b as usize] = s;
        }
        // Compact: keep only referenced vertices, in first-use order.
        let mut remap = vec![u32::MAX; self.pos.len()];
        let mut vertices = Vec::with_capacity(self.pos.len());
        let mut indices = Vec::with_capacity(self.idx.len());
        for t in self.idx.chunks_exact(3) {
            let face = {
                let (a, b, c) = (self.pos[t[0] as usize], self.pos[t[1] as usize], self.pos[t[2] as usize]);
                (b - a).cross(c - a).normalize_or(Vec3::Y)
            };
            for &i in t {
                let i = i as usize;
                if remap[i] == u32::MAX {
                    remap[i] = vertices.len() as u32;
                    let n = acc[i].normalize_or(face);
                    vertices.push(Vertex { position: self.pos[i].into(), normal: n.into(), uv: self.uv[i].into() });
                }
                indices.push(remap[i]);
            }
        }
        Mesh { name: name.into(), vertices, indices, tangents: None, extras: None }
    }
}

/// Nearly rotation-minimising frames (normal, binormal) along a path: the previous normal is
/// projected onto each new normal plane.
fn frames(path: &[Vec3], closed: bool) -> Vec<(Vec3, Vec3)> {
    let n = path.len();
    let tangent = |k: usize| -> Vec3 {
        let (a, b) = if closed { (path[(k + n - 1) % n], path[(k + 1) % n]) } else { (path[k.saturating_sub(1)], path[(k + 1).min(n - 1)]) };
        (b - a).normalize_or(Vec3::X)
    };
    let t0 = tangent(0);
    let helper = if t0.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let mut nrm = (helper - t0 * helper.dot(t0)).normalize();
    let mut out = Vec::with_capacity(n);
    let mut prev_t = t0;
    for k in 0..n {
        let t = tangent(k);
        // Project the previous normal onto the new normal plane.
        nrm = (nrm - t * nrm.dot(t)).normalize_or((prev_t.cross(t)).normalize_or(Vec3::Y));
        prev_t = t;
        out.push((nrm, t.cross(nrm)));
    }
    out
}

/// Points on a circular arc in the xy plane around `c` from angle `a0` to `a1`.
pub(crate) fn arc_xy(c: Vec3, r: f32, a0: f32, a1: f32, segments: u32) -> Vec<Vec3> {
    (0..=segments)
        .map(|i| {
            let a = a0 + (a1 - a0) * i as f32 / segments as f32;
            c + Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

/// A circle profile (counter-clockwise) of `n` points.
pub(crate) fn circle(r: f32, n: u32) -> Vec<Vec2> {
    (0..n).map(|i| Vec2::from_angle(TAU * i as f32 / n as f32) * r).collect()
}

/// A rectangle profile (counter-clockwise) with creases at the corners.
pub(crate) fn rect_profile(w: f32, h: f32) -> Vec<Vec2> {
    let (x, y) = (w / 2.0, h / 2.0);
    vec![Vec2::new(-x, -y), Vec2::new(x, -y), Vec2::new(x, -y), Vec2::new(x, y), Vec2::new(x, y), Vec2::new(-x, y), Vec2::new(-x, y), Vec2::new(-x, -y)]
}

// ---------------------------------------------------------------------------------------------
// Textures
// ---------------------------------------------------------------------------------------------

pub(crate) type Rgb = Vec3;

/// An sRGB colour from bytes.
pub(crate) fn rgb(r: u8, g: u8, b: u8) -> Rgb {
    Vec3::new(r as f32, g as f32, b as f32) / 255.0
}

/// `c` with each channel moved by up to `amount` (shared brightness plus a little hue).
pub(crate) fn jitter(rng: &mut Rng, c: Rgb, amount: f32) -> Rgb {
    let l = rng.range(-amount, amount);
    let h = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3)) * amount;
    (c + Vec3::splat(l) + h).clamp(Vec3::ZERO, Vec3::ONE)
}

/// A `size`² image from `f(u, v)` (pixel centres, v down) in sRGB [0, 1].
pub(crate) fn image(name: &str, size: u32, mut f: impl FnMut(f32, f32) -> Rgb) -> TextureImage {
    let mut rgba = Vec::with_capacity((size * size * 4) as usize);
    let inv = 1.0 / size as f32;
    for y in 0..size {
        let v = (y as f32 + 0.5) * inv;
        for x in 0..size {
            let c = f((x as f32 + 0.5) * inv, v).clamp(Vec3::ZERO, Vec3::ONE) * 255.0 + 0.5;
            rgba.extend_from_slice(&[c.x as u8, c.y as u8, c.z as u8, 255]);
        }
    }
    TextureImage { name: name.into(), width: size, height: size, rgba: rgba.into() }
}

/// Bricks or ashlar blocks: `rows` courses of `cols` blocks, running bond, mortar lines.
#[allow(clippy::too_many_arguments)]
pub(crate) fn tex_blocks(name: &str, size: u32, block: Rgb, mortar: Rgb, rows: u32, cols: u32, vary: f32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 8, 3);
    let shades: Vec<Rgb> = (0..rows * cols).map(|_| jitter(rng, block, vary)).collect();
    let (rf, cf) = (rows as f32, cols as f32);
    let joint = 1.5 / size as f32;
    image(name, size, |u, v| {
        let row = (v * rf) as u32 % rows;
        let uu = (u + if row % 2 == 1 { 0.5 / cf } else { 0.0 }).rem_euclid(1.0);
        let col = (uu * cf) as u32 % cols;
        let (fu, fv) = ((uu * cf).fract() / cf, (v * rf).fract() / rf);
        let n = noise.at(u, v);
        if fu < joint || fv < joint {
            mortar * (0.95 + 0.2 * n)
        } else {
            shades[(row * cols + col) as usize] * (1.0 + 0.35 * n)
        }
    })
}

/// Floor tiles: a checkerboard of two stones with thin joints and veining.
pub(crate) fn tex_tiles(name: &str, size: u32, a: Rgb, b: Rgb, cells: u32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 4, 4);
    let cf = cells as f32;
    image(name, size, |u, v| {
        let (cx, cy) = ((u * cf) as u32, (v * cf) as u32);
        let (fx, fy) = ((u * cf).fract(), (v * cf).fract());
        let n = noise.at(u, v);
        let base = if (cx + cy) % 2 == 0 { a } else { b };
        let joint = fx < 0.03 || fy < 0.03;
        let vein = (((u + v) * 9.0 + 6.0 * n) * PI).sin().abs();
        let c = base * (1.0 + 0.25 * n) * (0.93 + 0.07 * vein);
        if joint {
            c * 0.6
        } else {
            c
        }
    })
}

/// Two-colour fractal noise (plaster, stone, marble, bark, foliage).
pub(crate) fn tex_noise(name: &str, size: u32, a: Rgb, b: Rgb, period: u32, contrast: f32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, period, 4);
    image(name, size, |u, v| {
        let t = (0.5 + contrast * noise.at(u, v)).clamp(0.0, 1.0);
        a.lerp(b, t)
    })
}

/// Marble: sine veins distorted by noise.
pub(crate) fn tex_marble(name: &str, size: u32, a: Rgb, vein: Rgb, waves: f32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 4, 4);
    let wave = waves.round().max(1.0);
    image(name, size, |u, v| {
        let s = ((u * wave + v * wave + 4.0 * noise.at(u, v)) * PI).sin();
        let t = (1.0 - s.abs()).powi(6);
        a.lerp(vein, t) * (1.0 + 0.1 * noise.at(v, u))
    })
}

/// Woven fabric stripes: colour bands across u with a weave texture.
pub(crate) fn tex_stripes(name: &str, size: u32, colors: &[Rgb], bands: u32, weave: u32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 8, 2);
    let bf = bands as f32;
    let wf = weave as f32;
    image(name, size, |u, v| {
        let band = ((u * bf) as usize) % colors.len();
        let (wx, wy) = ((u * wf) as u32, (v * wf) as u32);
        let over = (wx + wy) % 2 == 0;
        let thread = if over { 1.0 - 0.25 * ((u * wf).fract() - 0.5).abs() } else { 0.85 - 0.25 * ((v * wf).fract() - 0.5).abs() };
        colors[band] * thread * (1.0 + 0.15 * noise.at(u, v))
    })
}

/// Harlequin diamonds with a border band (banners).
pub(crate) fn tex_diamonds(name: &str, size: u32, a: Rgb, b: Rgb, border: Rgb, n: u32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 8, 2);
    let nf = n as f32;
    image(name, size, |u, v| {
        let (x, y) = ((u * nf).fract() - 0.5, (v * nf).fract() - 0.5);
        let inside = x.abs() + y.abs() < 0.5;
        let edge = (u - 0.5).abs() > 0.42 || (v - 0.5).abs() > 0.45;
        let c = if edge {
            border
        } else if inside {
            a
        } else {
            b
        };
        c * (1.0 + 0.15 * noise.at(u, v))
    })
}

/// Wood planks along u with grain.
pub(crate) fn tex_wood(name: &str, size: u32, light: Rgb, dark: Rgb, planks: u32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 4, 3);
    let offsets: Vec<f32> = (0..planks).map(|_| rng.f32()).collect();
    let pf = planks as f32;
    image(name, size, |u, v| {
        let p = ((v * pf) as usize).min(planks as usize - 1);
        let fv = (v * pf).fract();
        let g = (((u + offsets[p]) * 24.0 + 3.0 * noise.at(u, v + offsets[p])) * PI).sin() * 0.5 + 0.5;
        let c = light.lerp(dark, 0.6 * g);
        if !(0.04..=0.96).contains(&fv) {
            dark * 0.6
        } else {
            c
        }
    })
}

/// A grey roughness map (glTF: roughness in G, metallic in B = 0).
pub(crate) fn tex_roughness(name: &str, size: u32, mean: f32, spread: f32, rng: &mut Rng) -> TextureImage {
    let noise = TileNoise::new(rng, 8, 4);
    image(name, size, |u, v| {
        let r = (mean + spread * noise.at(u, v)).clamp(0.05, 1.0);
        Vec3::new(1.0, r, 0.0)
    })
}

/// A diffuse material with roughness `roughness`.
pub(crate) fn material(name: &str, color: [f32; 4], texture: Option<usize>, roughness: f32) -> Material {
    let mut m = Material::diffuse(name, color, texture);
    m.roughness = roughness;
    m
}
