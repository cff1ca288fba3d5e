//! The "atrium" scene: a Sponza-like courtyard generated from a seed.
//!
//! Layout (metres, y up): the open courtyard runs along x over [-15, 15] and across z over
//! [-3.1, 3.1], with no roof. Along each long side a colonnade of nine columns (x = -12..12,
//! z = ±3.5) carries ten semicircular arches on the ground storey (springing at 4.15 m) and
//! ten on the upper storey (springing at 9.45 m) above a gallery floor at 6.35 m with a
//! balustrade. Behind the arcades are aisles out to the outer walls at z = ±7, spanned by
//! transverse ribs and roofed at 11 m; an attic wall with a cornice and medallions closes the
//! courtyard façade at 12 m. The end walls (x = ±15) carry a door, a rose window and lion
//! masks. Thin single-sided cloth (the thin features) hangs in front of alternate ground
//! arches (curtains), over the gallery balustrade in the other bays (rugs) and in front of the
//! upper columns (banners); a fountain, planted vases, lanterns and benches furnish it. In all:
//! about 262,500 triangles over 468 instances of 103 meshes, 69 textures (64² to 256²).
//!
//! The seed changes shapes (column weathering, cloth folds, plants, vases) and colours, never
//! the structure: every seed gives the same mesh, texture, material and triangle counts.
//! Long-side elements are modelled for the south side (courtyard towards +z) and turned by
//! half a turn about y for the north side; no instance transform mirrors.

use super::common::{
    arc_xy, circle, fbm3, jitter, material, rect_profile, rgb, tex_blocks, tex_diamonds, tex_marble, tex_noise, tex_stripes, tex_tiles, tex_wood, MeshBuilder,
    Rgb, Rng,
};
use crate::scene::{Camera, Instance, Light, Material, Mesh, Scene, TextureImage};
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

/// Inner face of the end walls.
const HALF_X: f32 = 15.0;
/// Column line of the arcades.
const ARCADE_Z: f32 = 3.5;
/// Inner face of the outer (long) walls.
const WALL_Z: f32 = 7.0;
const WALL_T: f32 = 0.4;
const BAY: f32 = 3.0;
const BAYS: usize = 10;
const COLUMNS: usize = BAYS - 1;
const G_SPRING: f32 = 4.15;
const G_RADIUS: f32 = 1.1;
const G_PANEL_T: f32 = 0.8;
const SLAB_Y0: f32 = 6.0;
const SLAB_Y1: f32 = 6.35;
const U_SPRING: f32 = 9.45;
const U_RADIUS: f32 = 1.15;
const U_PANEL_T: f32 = 0.7;
const ROOF_Y0: f32 = 11.0;
const ROOF_Y1: f32 = 11.25;
const TOP_Y: f32 = 12.0;
/// Curtains hang in the ground bays with odd index, this far in front of the column line.
const CLOTH_Z: f32 = 2.9;

fn column_x(k: usize) -> f32 {
    -HALF_X + BAY * (k + 1) as f32
}

fn bay_x(k: usize) -> f32 {
    -HALF_X + BAY * (k as f32 + 0.5)
}

/// The south side as modelled, or the north side (half a turn about y).
fn side(s: usize) -> Mat4 {
    if s == 0 {
        Mat4::IDENTITY
    } else {
        Mat4::from_rotation_y(PI)
    }
}

fn at(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4::from_translation(Vec3::new(x, y, z))
}

/// Subdivides a polyline so no piece is longer than `max_len`; repeated points (creases)
/// stay repeated.
fn refine(points: &[Vec2], max_len: f32) -> Vec<Vec2> {
    let mut out = vec![points[0]];
    for w in points.windows(2) {
        let n = ((w[0].distance(w[1]) / max_len).ceil() as usize).max(1);
        for i in 1..=n {
            out.push(w[0].lerp(w[1], i as f32 / n as f32));
        }
    }
    out
}

/// Splits every segment of non-zero length into `k` pieces (a count independent of the
/// shape, so seeds do not change triangle counts).
fn subdivide(points: &[Vec2], k: usize) -> Vec<Vec2> {
    let mut out = vec![points[0]];
    for w in points.windows(2) {
        if w[0] == w[1] {
            out.push(w[1]);
            continue;
        }
        for i in 1..=k {
            out.push(w[0].lerp(w[1], i as f32 / k as f32));
        }
    }
    out
}

/// Every point doubled: flat shading for a closed sweep profile.
fn creased(points: &[Vec2]) -> Vec<Vec2> {
    points.iter().flat_map(|p| [*p, *p]).collect()
}

/// The scene being assembled.
struct Atrium {
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    instances: Vec<Instance>,
    textures: Vec<TextureImage>,
}

impl Atrium {
    /// A texture with its own material.
    fn textured(&mut self, tex: TextureImage, tint: Rgb, roughness: f32) -> usize {
        self.textures.push(tex);
        let t = self.textures.len() - 1;
        let name = self.textures[t].name.clone();
        self.materials.push(material(&name, [tint.x, tint.y, tint.z, 1.0], Some(t), roughness));
        self.materials.len() - 1
    }

    fn mesh(&mut self, b: MeshBuilder, name: &str) -> usize {
        self.meshes.push(b.finish(name));
        self.meshes.len() - 1
    }

    fn put(&mut self, mesh: usize, material: usize, transform: Mat4) {
        self.instances.push(Instance { mesh, material, transform });
    }
}

// ---------------------------------------------------------------------------------------------
// Architectural elements
// ---------------------------------------------------------------------------------------------

struct ColumnSpec {
    plinth_hw: f32,
    plinth_h: f32,
    base_h: f32,
    base_r: f32,
    shaft_r0: f32,
    shaft_r1: f32,
    shaft_h: f32,
    cap_h: f32,
    cap_r: f32,
    abacus_hw: f32,
    abacus_h: f32,
    flutes: u32,
    segments: u32,
    rings: u32,
    lathe_segments: u32,
}

const GROUND_COLUMN: ColumnSpec = ColumnSpec {
    plinth_hw: 0.35,
    plinth_h: 0.25,
    base_h: 0.2,
    base_r: 0.34,
    shaft_r0: 0.27,
    shaft_r1: 0.235,
    shaft_h: 3.1,
    cap_h: 0.4,
    cap_r: 0.38,
    abacus_hw: 0.4,
    abacus_h: 0.2,
    flutes: 10,
    segments: 40,
    rings: 12,
    lathe_segments: 24,
};

const UPPER_COLUMN: ColumnSpec = ColumnSpec {
    plinth_hw: 0.28,
    plinth_h: 0.2,
    base_h: 0.15,
    base_r: 0.26,
    shaft_r0: 0.2,
    shaft_r1: 0.18,
    shaft_h: 2.3,
    cap_h: 0.3,
    cap_r: 0.31,
    abacus_hw: 0.35,
    abacus_h: 0.15,
    flutes: 8,
    segments: 32,
    rings: 8,
    lathe_segments: 20,
};

/// A column standing on y = 0: plinth, moulded base, fluted weathered shaft with entasis,
/// capital and abacus. `twist` turns the flutes along the shaft.
fn column(s: &ColumnSpec, rng: &mut Rng, twist: f32) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let hw = s.plinth_hw;
    b.cuboid(Vec3::new(-hw, 0.0, -hw), Vec3::new(hw, s.plinth_h, hw), 0.2, 1.5);
    // Base: a torus-like roll over the plinth.
    let y0 = s.plinth_h;
    let mut prof = vec![Vec2::new(0.0, y0), Vec2::new(s.base_r, y0), Vec2::new(s.base_r, y0)];
    let nb = 8;
    for i in 1..=nb {
        let t = i as f32 / nb as f32;
        let r = s.base_r + (s.shaft_r0 * 1.06 - s.base_r) * t + 0.035 * (PI * t).sin();
        prof.push(Vec2::new(r, y0 + s.base_h * t));
    }
    let ys = y0 + s.base_h;
    prof.push(Vec2::new(s.shaft_r0 * 1.06, ys));
    prof.push(Vec2::new(0.0, ys));
    b.lathe(&prof, s.lathe_segments, 2.0, 1.5);
    // Shaft.
    let seed = rng.seed32();
    let weather = rng.range(0.004, 0.012);
    let flute_depth = rng.range(0.025, 0.045);
    let (segments, rings, flutes) = (s.segments, s.rings, s.flutes as f32);
    let (r0, r1, h) = (s.shaft_r0, s.shaft_r1, s.shaft_h + 0.04);
    b.grid(segments, rings, true, |u, v| {
        let a = u * TAU + twist * v;
        let radius = (r0 + (r1 - r0) * v) * (1.0 + 0.025 * (PI * v).sin()) * (1.0 - flute_depth * (0.5 - 0.5 * (flutes * a).cos()));
        let y = ys - 0.02 + h * v;
        let w = 1.0 + weather * 2.0 * fbm3(seed, Vec3::new(a.cos() * 1.5, y * 1.5, a.sin() * 1.5), 2);
        let r = radius * w;
        (Vec3::new(r * a.cos(), y, -r * a.sin()), Vec2::new(u * 2.0, y * 0.7))
    });
    // Capital: necking ring, then a flaring echinus.
    let yc = ys + s.shaft_h;
    let mut prof = vec![Vec2::new(0.0, yc), Vec2::new(r1 * 1.02, yc)];
    let nc = 12;
    for i in 1..=nc {
        let t = i as f32 / nc as f32;
        let ring = if t < 0.25 { 0.02 * (PI * t / 0.25).sin() } else { 0.0 };
        let flare = if t > 0.25 { (s.cap_r - r1 * 1.02) * ((t - 0.25) / 0.75).powf(1.6) } else { 0.0 };
        prof.push(Vec2::new(r1 * 1.02 + ring + flare, yc + s.cap_h * t));
    }
    let ya = yc + s.cap_h;
    prof.push(Vec2::new(s.cap_r, ya));
    prof.push(Vec2::new(0.0, ya));
    b.lathe(&prof, s.lathe_segments, 2.0, 1.5);
    let aw = s.abacus_hw;
    b.cuboid(Vec3::new(-aw, ya, -aw), Vec3::new(aw, ya + s.abacus_h, aw), 0.2, 1.5);
    b
}

/// The wall over one arch: x over [-BAY/2, BAY/2], y over [0, height] from the springing,
/// z over [-t/2, t/2], minus a semicircular opening of `radius`. Front (+z), back (-z) and
/// soffit faces.
fn arch_panel(radius: f32, height: f32, t: f32, arc_segments: u32, rings: u32) -> MeshBuilder {
    let hw = BAY / 2.0;
    let n = arc_segments;
    let n_side = ((n as f32 * height / (2.0 * height + 2.0 * hw)).round() as u32).max(1);
    let n_top = n - 2 * n_side;
    let inner = |k: u32| {
        let a = PI - PI * k as f32 / n as f32;
        Vec2::new(radius * a.cos(), radius * a.sin())
    };
    let outer = |k: u32| {
        if k <= n_side {
            Vec2::new(-hw, height * k as f32 / n_side as f32)
        } else if k <= n_side + n_top {
            Vec2::new(-hw + 2.0 * hw * (k - n_side) as f32 / n_top as f32, height)
        } else {
            Vec2::new(hw, height * (1.0 - (k - n_side - n_top) as f32 / n_side as f32))
        }
    };
    let mut b = MeshBuilder::new();
    for (z, facing) in [(t / 2.0, Vec3::Z), (-t / 2.0, -Vec3::Z)] {
        let first = b.idx().len();
        b.grid(n, rings, false, |u, v| {
            let k = (u * n as f32).round() as u32;
            let p = inner(k).lerp(outer(k), v);
            (Vec3::new(p.x, p.y, z), p * 0.5)
        });
        b.face_towards(first, facing);
    }
    let first = b.idx().len();
    let depth = 3;
    let arc_len = PI * radius;
    b.grid(n, depth, false, |u, v| {
        let k = (u * n as f32).round() as u32;
        let p = inner(k);
        (Vec3::new(p.x, p.y, -t / 2.0 + t * v), Vec2::new(u * arc_len * 0.5, v * t * 0.5))
    });
    b.face_towards(first, -Vec3::Y);
    b
}

/// A half-round moulding following the arch on the front face.
fn archivolt(radius: f32, t: f32, segments: u32) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let path = arc_xy(Vec3::new(0.0, 0.0, t / 2.0), radius + 0.08, PI, 0.0, segments);
    b.sweep(&path, &circle(0.09, 6), false, false, 2.0);
    b
}

/// A straight moulding along x over [-HALF_X, HALF_X] with `profile` in (y, z) offsets.
fn moulding(profile: &[Vec2], segments: usize) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let path: Vec<Vec3> = (0..=segments).map(|i| Vec3::new(-HALF_X + 2.0 * HALF_X * i as f32 / segments as f32, 0.0, 0.0)).collect();
    // Along +x the sweep frame is normal = +y, binormal = +z.
    b.sweep(&path, &creased(profile), false, false, 1.0);
    b
}

/// A transverse rib across the aisle, in the yz plane from the column line towards the wall,
/// springing at y = 0.
fn rib(span: f32, rise: f32, segments: u32) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let r = span / 2.0;
    let path: Vec<Vec3> = (0..=segments)
        .map(|i| {
            let a = PI * i as f32 / segments as f32;
            Vec3::new(0.0, rise * a.sin(), -r + r * a.cos())
        })
        .collect();
    b.sweep(&path, &rect_profile(0.3, 0.25), false, false, 1.5);
    b
}

/// A baluster standing on y = 0.
fn baluster(h: f32, segments: u32) -> MeshBuilder {
    let mut prof = vec![Vec2::new(0.0, 0.0), Vec2::new(0.065, 0.0), Vec2::new(0.065, 0.0), Vec2::new(0.065, 0.06), Vec2::new(0.065, 0.06)];
    let n = 10;
    for i in 0..=n {
        let t = i as f32 / n as f32;
        let bulb = 0.03 + 0.045 * (PI * (t * 1.15).min(1.0)).sin().max(0.0).powf(1.5) * (1.0 - 0.4 * t);
        prof.push(Vec2::new(bulb, 0.06 + (h - 0.12) * t));
    }
    prof.extend_from_slice(&[Vec2::new(0.065, h - 0.06), Vec2::new(0.065, h), Vec2::new(0.065, h), Vec2::new(0.0, h)]);
    let mut b = MeshBuilder::new();
    b.lathe(&prof, segments, 1.0, 2.0);
    b
}

/// A hanging cloth: top edge along x at y = 0, hanging down by `h`, bulging towards +z (its
/// front). Folds, a sagging hem and a breeze come from `rng`.
fn cloth(rng: &mut Rng, w: f32, h: f32, nu: u32, nv: u32, fold_amp: f32) -> MeshBuilder {
    let folds: Vec<(f32, f32, f32)> =
        (0..4).map(|i| (rng.range(0.4, 1.0) * fold_amp / (i + 1) as f32, (2 + i * 2) as f32 + rng.range(-0.5, 0.5), rng.range(0.0, TAU))).collect();
    let belly = rng.range(0.04, 0.14);
    let breeze = rng.range(0.0, 0.12);
    let skew = rng.range(-0.06, 0.06);
    let hem = rng.range(0.02, 0.08);
    let mut b = MeshBuilder::new();
    b.grid(nu, nv, false, |u, v| {
        let mut z = 0.03 + belly * (PI * u).sin() * v.powf(0.8) + breeze * v * v;
        for (a, f, ph) in &folds {
            z += a * (0.5 + 0.5 * (TAU * f * u + ph).sin()) * (0.35 + 0.65 * v);
        }
        let x = (u - 0.5) * w * (1.0 - 0.06 * v) + skew * v * v;
        let y = -h * v * (1.0 - hem * (PI * u).sin());
        (Vec3::new(x, y, z), Vec2::new(u, v))
    });
    b.face_towards(0, Vec3::Z);
    b
}

/// A vase standing on y = 0, open at the top with soil inside.
fn vase(rng: &mut Rng, segments: u32) -> MeshBuilder {
    let h = rng.range(0.7, 1.0);
    let belly = rng.range(0.3, 0.42);
    let neck = belly * rng.range(0.55, 0.75);
    let lip = neck * rng.range(1.15, 1.35);
    let foot = belly * rng.range(0.45, 0.6);
    let mut prof = vec![Vec2::new(0.0, 0.0), Vec2::new(foot, 0.0), Vec2::new(foot, 0.0)];
    let n = 16;
    for i in 0..=n {
        let t = i as f32 / n as f32;
        let r = if t < 0.55 { foot + (belly - foot) * (PI * 0.5 * t / 0.55).sin() } else { belly + (neck - belly) * ((t - 0.55) / 0.45).powf(0.8) };
        prof.push(Vec2::new(r, 0.06 + (h - 0.12) * t));
    }
    let top = h;
    prof.extend_from_slice(&[Vec2::new(lip, top - 0.04), Vec2::new(lip, top), Vec2::new(lip, top), Vec2::new(neck - 0.04, top), Vec2::new(neck - 0.04, top)]);
    let soil = top - 0.1;
    prof.extend_from_slice(&[Vec2::new(neck - 0.04, soil), Vec2::new(neck - 0.04, soil), Vec2::new(0.0, soil)]);
    let mut b = MeshBuilder::new();
    b.lathe(&prof, segments, 2.0, 1.0);
    b
}

/// A lumpy shrub around its centre (radius about `r`).
fn bush(rng: &mut Rng, r: f32, segments: u32, rings: u32) -> MeshBuilder {
    let seed = rng.seed32();
    let lumps = rng.range(2.0, 3.5);
    let prof: Vec<Vec2> = (0..=rings)
        .map(|i| {
            let t = PI * i as f32 / rings as f32;
            Vec2::new(t.sin(), -t.cos())
        })
        .collect();
    let mut b = MeshBuilder::new();
    b.lathe(&prof, segments, 3.0, 2.0);
    let squash = rng.range(0.8, 1.1);
    b.map_positions(0, |p| {
        let d = p.normalize_or(Vec3::Y);
        let k = 1.0 + 0.45 * fbm3(seed, d * lumps, 3);
        Vec3::new(d.x, d.y * squash, d.z) * r * k
    });
    b
}

/// A lantern hanging from y = 0 on a chain of length `chain`.
fn lantern(rng: &mut Rng, chain: f32, segments: u32) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let links = 10;
    let path: Vec<Vec3> = (0..=links).map(|i| Vec3::new(0.0, -chain * i as f32 / links as f32, 0.0)).collect();
    b.sweep(&path, &circle(0.018, 6), false, true, 4.0);
    let body = rng.range(0.16, 0.22);
    let hgt = rng.range(0.45, 0.6);
    let y0 = -chain - hgt;
    let prof = [
        Vec2::new(0.0, y0 - 0.08),
        Vec2::new(0.03, y0 - 0.08),
        Vec2::new(body * 0.6, y0),
        Vec2::new(body * 0.6, y0),
        Vec2::new(body, y0 + 0.05),
        Vec2::new(body * 0.92, y0 + hgt * 0.5),
        Vec2::new(body, y0 + hgt * 0.8),
        Vec2::new(body, y0 + hgt * 0.8),
        Vec2::new(body * 1.15, y0 + hgt * 0.82),
        Vec2::new(body * 0.3, y0 + hgt),
        Vec2::new(0.03, y0 + hgt + 0.02),
        Vec2::new(0.0, y0 + hgt + 0.02),
    ];
    b.lathe(&subdivide(&creased(&prof), 2), segments, 1.0, 2.0);
    b
}

/// A round medallion facing +y (a disc with a rim and a dome).
fn medallion(rng: &mut Rng, r: f32, segments: u32) -> MeshBuilder {
    let dome = rng.range(0.08, 0.16);
    let mut prof = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(r, 0.0),
        Vec2::new(r, 0.0),
        Vec2::new(r, 0.06),
        Vec2::new(r * 0.92, 0.09),
        Vec2::new(r * 0.8, 0.06),
        Vec2::new(r * 0.75, 0.06),
    ];
    let n = 10;
    for i in 0..=n {
        let t = i as f32 / n as f32;
        prof.push(Vec2::new(r * 0.72 * (1.0 - t), 0.06 + dome * (FRAC_PI_2 * t).sin()));
    }
    let mut b = MeshBuilder::new();
    b.lathe(&prof, segments, 1.0, 1.0);
    b
}

/// A lion-like mask facing +z: a displaced half-ellipsoid with a mane of lumps.
fn mask(rng: &mut Rng, segments: u32, rings: u32) -> MeshBuilder {
    let seed = rng.seed32();
    let prof: Vec<Vec2> = (0..=rings)
        .map(|i| {
            let t = FRAC_PI_2 * i as f32 / rings as f32;
            Vec2::new(t.cos(), t.sin())
        })
        .collect();
    // Start at the rim on the wall, go up to the apex: outside to the right.
    let mut full = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0)];
    full.extend_from_slice(&prof[1..]);
    let mut b = MeshBuilder::new();
    b.lathe(&full, segments, 1.0, 1.0);
    let eyes = [Vec3::new(0.35, 0.55, -0.3), Vec3::new(-0.35, 0.55, -0.3)];
    b.map_positions(0, |p| {
        // Here y is the axis (out of the wall); the face plane is xz.
        let d = p.normalize_or(Vec3::Y);
        let mut k = 1.0 + 0.25 * fbm3(seed, d * 3.0, 2) + 0.1 * (d.x.atan2(d.z) * 9.0).sin() * (1.0 - d.y);
        for e in eyes {
            k -= 0.12 * (-(d - e.normalize()).length_squared() / 0.02).exp();
        }
        k += 0.25 * (-(d - Vec3::new(0.0, 0.8, -0.6).normalize()).length_squared() / 0.05).exp();
        Vec3::new(p.x * k, p.y * k * 0.6, p.z * k)
    });
    b
}

// ---------------------------------------------------------------------------------------------
// Assembly
// ---------------------------------------------------------------------------------------------

pub(super) fn build(seed: u64) -> Scene {
    let mut rng = Rng::new(seed ^ 0xA791_0A5E_5EED_0001);
    let mut a = Atrium { meshes: Vec::new(), materials: Vec::new(), instances: Vec::new(), textures: Vec::new() };
    let mut tr = rng.fork(); // texture randomness
    let mut gr = rng.fork(); // geometry randomness

    let stone = jitter(&mut tr, rgb(206, 192, 166), 0.05);
    let warm = jitter(&mut tr, rgb(196, 160, 120), 0.05);
    let white = Vec3::ONE;

    // --- Floors ---------------------------------------------------------------------------
    let m_court = a.textured(
        tex_tiles("atrium_floor_tiles", 256, jitter(&mut tr, rgb(226, 214, 190), 0.05), jitter(&mut tr, rgb(120, 124, 112), 0.05), 8, &mut tr),
        white,
        0.6,
    );
    let mut b = MeshBuilder::new();
    b.patch(Vec3::new(-HALF_X, 0.0, -3.1), Vec3::new(2.0 * HALF_X, 0.0, 0.0), Vec3::new(0.0, 0.0, 6.2), 96, 20, 0.5, Vec3::Y);
    let me = a.mesh(b, "courtyard_floor");
    a.put(me, m_court, Mat4::IDENTITY);

    let m_aisle =
        a.textured(tex_blocks("atrium_aisle_bricks", 128, jitter(&mut tr, rgb(168, 92, 64), 0.06), rgb(150, 140, 128), 16, 4, 0.12, &mut tr), white, 0.8);
    let mut b = MeshBuilder::new();
    b.patch(Vec3::new(-HALF_X, 0.0, -WALL_Z), Vec3::new(2.0 * HALF_X, 0.0, 0.0), Vec3::new(0.0, 0.0, WALL_Z - 3.1), 60, 8, 0.5, Vec3::Y);
    let me = a.mesh(b, "aisle_floor");
    for s in 0..2 {
        a.put(me, m_aisle, side(s));
    }

    // --- Slabs, roofs, walls --------------------------------------------------------------
    let m_slab = a.textured(tex_noise("atrium_slab_stone", 128, stone * 0.8, stone, 6, 1.2, &mut tr), white, 0.8);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-HALF_X, SLAB_Y0, -WALL_Z), Vec3::new(HALF_X, SLAB_Y1, -ARCADE_Z + G_PANEL_T / 2.0), 1.0, 0.5);
    let me = a.mesh(b, "gallery_slab");
    for s in 0..2 {
        a.put(me, m_slab, side(s));
    }

    let m_roof = a.textured(tex_blocks("atrium_roof_slabs", 128, stone * 0.75, stone * 0.55, 4, 2, 0.08, &mut tr), white, 0.9);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-HALF_X, ROOF_Y0, -WALL_Z), Vec3::new(HALF_X, ROOF_Y1, -ARCADE_Z + U_PANEL_T / 2.0), 1.0, 0.5);
    let me = a.mesh(b, "aisle_roof");
    for s in 0..2 {
        a.put(me, m_roof, side(s));
    }

    let m_plaster =
        a.textured(tex_noise("atrium_wall_plaster", 128, jitter(&mut tr, rgb(214, 190, 150), 0.05), rgb(170, 140, 104), 8, 1.6, &mut tr), white, 0.9);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-HALF_X - WALL_T, 0.0, -WALL_Z - WALL_T), Vec3::new(HALF_X + WALL_T, TOP_Y, -WALL_Z), 1.0, 0.25);
    let me = a.mesh(b, "outer_wall");
    for s in 0..2 {
        a.put(me, m_plaster, side(s));
    }

    let m_endwall =
        a.textured(tex_blocks("atrium_end_wall_bricks", 128, jitter(&mut tr, rgb(176, 104, 72), 0.06), rgb(196, 188, 172), 16, 4, 0.1, &mut tr), white, 0.85);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(HALF_X, 0.0, -WALL_Z - WALL_T), Vec3::new(HALF_X + WALL_T, TOP_Y, WALL_Z + WALL_T), 0.6, 0.25);
    let me = a.mesh(b, "end_wall");
    for s in 0..2 {
        a.put(me, m_endwall, side(s));
    }

    let m_attic = a.textured(tex_blocks("atrium_attic_ashlar", 128, stone, stone * 0.7, 4, 2, 0.06, &mut tr), white, 0.8);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-HALF_X, ROOF_Y0, -ARCADE_Z - G_PANEL_T / 2.0), Vec3::new(HALF_X, TOP_Y, -ARCADE_Z + G_PANEL_T / 2.0), 0.5, 0.5);
    let me = a.mesh(b, "attic_wall");
    for s in 0..2 {
        a.put(me, m_attic, side(s));
    }

    // Cornice on top of the attic and a string course under the gallery, on the courtyard face.
    let m_cornice = a.textured(tex_noise("atrium_cornice", 64, stone * 0.9, stone, 4, 1.0, &mut tr), white, 0.7);
    let cornice = [
        Vec2::new(-0.3, -0.1),
        Vec2::new(0.0, -0.1),
        Vec2::new(0.05, 0.05),
        Vec2::new(0.18, 0.12),
        Vec2::new(0.25, 0.3),
        Vec2::new(0.35, 0.32),
        Vec2::new(0.35, -0.1),
    ];
    let me = a.mesh(moulding(&cornice.map(|p| Vec2::new(p.x - 0.35, p.y)), 60), "cornice");
    for s in 0..2 {
        a.put(me, m_cornice, side(s) * at(0.0, TOP_Y, -ARCADE_Z + G_PANEL_T / 2.0));
    }
    let m_string = m_cornice;
    let string = [
        Vec2::new(0.0, -0.1),
        Vec2::new(0.0, 0.08),
        Vec2::new(0.06, 0.16),
        Vec2::new(0.22, 0.16),
        Vec2::new(0.3, 0.08),
        Vec2::new(0.35, 0.08),
        Vec2::new(0.35, -0.1),
    ];
    let me = a.mesh(moulding(&string, 60), "string_course");
    for s in 0..2 {
        a.put(me, m_string, side(s) * at(0.0, SLAB_Y0, -ARCADE_Z + G_PANEL_T / 2.0));
    }
    let skirting = [Vec2::new(0.0, -0.05), Vec2::new(0.0, 0.04), Vec2::new(0.2, 0.04), Vec2::new(0.3, 0.0), Vec2::new(0.3, -0.05)];
    let m_skirting = m_slab;
    let me = a.mesh(moulding(&skirting, 30), "skirting");
    for s in 0..2 {
        a.put(me, m_skirting, side(s) * at(0.0, 0.0, -WALL_Z));
    }

    // --- Columns ----------------------------------------------------------------------------
    let column_textures: Vec<usize> = (0..6)
        .map(|i| {
            let base = jitter(&mut tr, if i < 3 { rgb(222, 214, 200) } else { rgb(208, 196, 176) }, 0.06);
            let vein = jitter(&mut tr, rgb(140, 130, 120), 0.1);
            a.textured(tex_marble(&format!("atrium_column_marble_{i}"), 128, base, vein, 3.0 + i as f32, &mut tr), white, 0.35)
        })
        .collect();
    let ground_variants: Vec<usize> = (0..6)
        .map(|i| {
            let twist = if i == 5 { 1.2 } else { 0.0 };
            let b = column(&GROUND_COLUMN, &mut gr, twist);
            a.mesh(b, &format!("column_ground_{i}"))
        })
        .collect();
    let upper_variants: Vec<usize> = (0..6)
        .map(|i| {
            let twist = if i == 2 { -1.6 } else { 0.0 };
            let b = column(&UPPER_COLUMN, &mut gr, twist);
            a.mesh(b, &format!("column_upper_{i}"))
        })
        .collect();
    for s in 0..2 {
        for k in 0..COLUMNS {
            let v = (k + 3 * s) % 6;
            a.put(ground_variants[v], column_textures[v % 3], side(s) * at(column_x(k), 0.0, -ARCADE_Z));
            a.put(upper_variants[v], column_textures[3 + v % 3], side(s) * at(column_x(k), SLAB_Y1, -ARCADE_Z));
        }
    }
    // Engaged piers where the arcades meet the end walls.
    let m_pier = m_attic;
    let hw = BAY / 2.0 - G_RADIUS;
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-hw / 2.0, 0.0, -G_PANEL_T / 2.0), Vec3::new(hw / 2.0, G_SPRING, G_PANEL_T / 2.0), 0.25, 1.0);
    let pier_g = a.mesh(b, "pier_ground");
    let hw = BAY / 2.0 - U_RADIUS;
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-hw / 2.0, 0.0, -U_PANEL_T / 2.0), Vec3::new(hw / 2.0, U_SPRING - SLAB_Y1, U_PANEL_T / 2.0), 0.25, 1.0);
    let pier_u = a.mesh(b, "pier_upper");
    for sx in [-1.0f32, 1.0] {
        for sz in [-1.0f32, 1.0] {
            a.put(pier_g, m_pier, at(sx * (HALF_X - (BAY / 2.0 - G_RADIUS) / 2.0), 0.0, sz * ARCADE_Z));
            a.put(pier_u, m_pier, at(sx * (HALF_X - (BAY / 2.0 - U_RADIUS) / 2.0), SLAB_Y1, sz * ARCADE_Z));
        }
    }

    // --- Arcades ----------------------------------------------------------------------------
    let m_arch_g = a.textured(tex_blocks("atrium_arch_ground", 128, stone, stone * 0.75, 4, 3, 0.07, &mut tr), white, 0.8);
    let m_arch_u = a.textured(tex_blocks("atrium_arch_upper", 128, warm, warm * 0.75, 4, 3, 0.07, &mut tr), white, 0.8);
    let m_volt = a.textured(tex_noise("atrium_archivolt", 64, stone * 0.95, stone * 0.7, 4, 1.0, &mut tr), white, 0.6);
    let panel_g = a.mesh(arch_panel(G_RADIUS, SLAB_Y0 - G_SPRING, G_PANEL_T, 32, 4), "arch_panel_ground");
    let panel_u = a.mesh(arch_panel(U_RADIUS, ROOF_Y0 - U_SPRING, U_PANEL_T, 32, 4), "arch_panel_upper");
    let volt_g = a.mesh(archivolt(G_RADIUS, G_PANEL_T, 28), "archivolt_ground");
    let volt_u = a.mesh(archivolt(U_RADIUS, U_PANEL_T, 28), "archivolt_upper");
    for s in 0..2 {
        for k in 0..BAYS {
            let g = side(s) * at(bay_x(k), G_SPRING, -ARCADE_Z);
            let u = side(s) * at(bay_x(k), U_SPRING, -ARCADE_Z);
            a.put(panel_g, m_arch_g, g);
            a.put(volt_g, m_volt, g);
            a.put(panel_u, m_arch_u, u);
            a.put(volt_u, m_volt, u);
        }
    }

    // --- Balustrade on the gallery -----------------------------------------------------------
    let m_baluster = a.textured(tex_marble("atrium_baluster", 64, jitter(&mut tr, rgb(230, 224, 212), 0.04), rgb(160, 150, 140), 2.0, &mut tr), white, 0.4);
    let m_rail = a.textured(tex_noise("atrium_rail", 64, stone * 0.8, stone, 4, 1.0, &mut tr), white, 0.6);
    let bal = a.mesh(baluster(0.75, 8), "baluster");
    let rail_len = BAY - 2.0 * UPPER_COLUMN.plinth_hw;
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-rail_len / 2.0, 0.0, -0.13), Vec3::new(rail_len / 2.0, 0.15, 0.13), 0.3, 1.0);
    let rail_low = a.mesh(b, "rail_low");
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-rail_len / 2.0, 0.0, -0.15), Vec3::new(rail_len / 2.0, 0.12, 0.15), 0.3, 1.0);
    let rail_top = a.mesh(b, "rail_top");
    for s in 0..2 {
        for k in 0..BAYS {
            let base = side(s) * at(bay_x(k), SLAB_Y1, -ARCADE_Z);
            a.put(rail_low, m_rail, base);
            a.put(rail_top, m_rail, base * at(0.0, 0.9, 0.0));
            for j in 0..4 {
                a.put(bal, m_baluster, base * at(-0.84 + 0.56 * j as f32, 0.15, 0.0));
            }
        }
    }

    // --- Aisles: wall pilasters, transverse ribs, benches, lanterns -----------------------
    let m_wpil = a.textured(tex_blocks("atrium_wall_pilaster", 64, stone, stone * 0.7, 8, 1, 0.06, &mut tr), white, 0.8);
    let m_rib = a.textured(tex_blocks("atrium_rib", 64, warm, warm * 0.7, 1, 6, 0.08, &mut tr), white, 0.8);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-0.25, 0.0, 0.0), Vec3::new(0.25, 1.0, 0.15), 0.25, 1.0);
    b.cuboid(Vec3::new(-0.32, 1.0, 0.0), Vec3::new(0.32, 1.02, 0.22), 0.25, 1.0);
    let wpil = a.mesh(b, "wall_pilaster");
    let aisle_span = (WALL_Z - 0.15) - (ARCADE_Z + G_PANEL_T / 2.0);
    let rib_g = a.mesh(rib(aisle_span, SLAB_Y0 - G_SPRING - 0.05, 32), "rib_ground");
    let rib_u = a.mesh(rib(WALL_Z - 0.15 - ARCADE_Z - U_PANEL_T / 2.0, ROOF_Y0 - U_SPRING - 0.05, 32), "rib_upper");
    for s in 0..2 {
        for k in 0..COLUMNS {
            let x = column_x(k);
            a.put(wpil, m_wpil, side(s) * at(x, 0.0, -WALL_Z) * Mat4::from_scale(Vec3::new(1.0, G_SPRING - 0.08, 1.0)));
            a.put(wpil, m_wpil, side(s) * at(x, SLAB_Y1, -WALL_Z) * Mat4::from_scale(Vec3::new(1.0, U_SPRING - SLAB_Y1 - 0.08, 1.0)));
            a.put(rib_g, m_rib, side(s) * at(x, G_SPRING, -ARCADE_Z - G_PANEL_T / 2.0));
            a.put(rib_u, m_rib, side(s) * at(x, U_SPRING, -ARCADE_Z - U_PANEL_T / 2.0));
        }
    }
    let m_wood = a.textured(tex_wood("atrium_bench_wood", 64, jitter(&mut tr, rgb(150, 104, 64), 0.05), rgb(80, 50, 30), 4, &mut tr), white, 0.7);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-0.9, 0.42, -0.22), Vec3::new(0.9, 0.5, 0.22), 0.2, 1.0);
    for x in [-0.75f32, 0.75] {
        b.cuboid(Vec3::new(x - 0.05, 0.0, -0.18), Vec3::new(x + 0.05, 0.42, 0.18), 0.2, 1.0);
    }
    let bench = a.mesh(b, "bench");
    for s in 0..2 {
        for k in [1usize, 3, 6, 8] {
            a.put(bench, m_wood, side(s) * at(bay_x(k), 0.0, -WALL_Z + 0.45));
        }
    }
    let m_iron = a.textured(tex_noise("atrium_iron", 64, rgb(40, 38, 36), rgb(92, 86, 80), 8, 1.4, &mut tr), white, 0.5);
    let m_brass = [
        a.textured(tex_noise("atrium_brass_a", 64, jitter(&mut tr, rgb(180, 140, 60), 0.05), rgb(110, 80, 30), 8, 1.4, &mut tr), white, 0.35),
        a.textured(tex_noise("atrium_brass_b", 64, jitter(&mut tr, rgb(160, 110, 70), 0.05), rgb(90, 60, 40), 8, 1.4, &mut tr), white, 0.35),
    ];
    for mm in m_brass {
        a.materials[mm].metallic = 0.8;
    }
    let lanterns = [a.mesh(lantern(&mut gr, 0.9, 12), "lantern_a"), a.mesh(lantern(&mut gr, 1.2, 12), "lantern_b")];
    for s in 0..2 {
        for k in 0..BAYS {
            a.put(lanterns[k % 2], m_brass[k % 2], side(s) * at(bay_x(k), SLAB_Y0, -(ARCADE_Z + WALL_Z) / 2.0));
        }
    }

    // --- Cloth: curtains in the ground bays, banners in front of the upper columns ----------
    let rod = {
        let mut b = MeshBuilder::new();
        b.sweep(&[Vec3::new(-1.3, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.3, 0.0, 0.0)], &circle(0.03, 8), false, true, 2.0);
        a.mesh(b, "curtain_rod")
    };
    let palette = [rgb(150, 30, 34), rgb(30, 70, 140), rgb(40, 110, 60), rgb(190, 150, 40), rgb(110, 40, 110), rgb(200, 190, 170), rgb(180, 80, 30)];
    let mut curtain = 0;
    let mut cloth_materials = Vec::new();
    for s in 0..2 {
        for k in (1..BAYS).step_by(2) {
            let (i0, i1) = (tr.below(palette.len()), tr.below(palette.len()));
            let c0 = jitter(&mut tr, palette[i0], 0.08);
            let c1 = jitter(&mut tr, palette[i1], 0.08);
            let bands = 3 + tr.below(5) as u32;
            let tex = tex_stripes(&format!("atrium_curtain_{curtain}"), 128, &[c0, c1, c0 * 0.8], bands, 32, &mut tr);
            let m = a.textured(tex, white, 0.9);
            a.materials[m].double_sided = true;
            cloth_materials.push(m);
            let me = a.mesh(cloth(&mut gr, 2.3, 3.4, 20, 32, 0.14), &format!("curtain_{curtain}"));
            let top = side(s) * at(bay_x(k), SLAB_Y0 - 0.25, -CLOTH_Z);
            a.put(me, m, top);
            a.put(rod, m_iron, top * at(0.0, 0.0, 0.1));
            curtain += 1;
        }
    }
    // Rugs hung out over the gallery balustrade in the bays without curtains.
    let mut rug = 0;
    for s in 0..2 {
        for k in (0..BAYS).step_by(2) {
            let me = a.mesh(cloth(&mut gr, 1.9, 0.95, 20, 14, 0.05), &format!("rug_{rug}"));
            let m = cloth_materials[(rug * 3 + 1) % cloth_materials.len()];
            a.put(me, m, side(s) * at(bay_x(k), SLAB_Y1 + 1.02, -ARCADE_Z + 0.16));
            rug += 1;
        }
    }
    let mut banner = 0;
    for s in 0..2 {
        for k in 0..COLUMNS {
            let (i0, i1) = (tr.below(palette.len()), tr.below(palette.len()));
            let c0 = jitter(&mut tr, palette[i0], 0.08);
            let c1 = jitter(&mut tr, palette[i1], 0.08);
            let border = jitter(&mut tr, rgb(200, 170, 60), 0.08);
            let n = 3 + tr.below(4) as u32;
            let tex = if k % 2 == 0 {
                tex_diamonds(&format!("atrium_banner_{banner}"), 128, c0, c1, border, n, &mut tr)
            } else {
                tex_stripes(&format!("atrium_banner_{banner}"), 128, &[c0, border, c1, border], n + 1, 24, &mut tr)
            };
            let m = a.textured(tex, white, 0.9);
            a.materials[m].double_sided = true;
            let me = a.mesh(cloth(&mut gr, 0.9, 2.8, 10, 24, 0.05), &format!("banner_{banner}"));
            a.put(me, m, side(s) * at(column_x(k), ROOF_Y0 - 0.15, -ARCADE_Z + G_PANEL_T / 2.0 + 0.2));
            banner += 1;
        }
    }

    // --- End walls: door, rose window, masks -------------------------------------------------
    let m_frame = a.textured(tex_noise("atrium_door_frame", 64, warm * 0.8, warm, 4, 1.0, &mut tr), white, 0.7);
    let m_door = a.textured(tex_wood("atrium_door_wood", 128, jitter(&mut tr, rgb(120, 80, 50), 0.05), rgb(60, 36, 20), 6, &mut tr), white, 0.7);
    let m_rose = a.textured(tex_marble("atrium_rose_stone", 64, stone, stone * 0.6, 2.0, &mut tr), white, 0.6);
    let m_glass = a.textured(
        tex_diamonds("atrium_rose_glass", 128, jitter(&mut tr, rgb(40, 60, 150), 0.1), jitter(&mut tr, rgb(160, 40, 40), 0.1), rgb(200, 170, 60), 6, &mut tr),
        white,
        0.2,
    );
    let m_bronze = a.textured(tex_noise("atrium_mask_bronze", 64, rgb(90, 70, 40), rgb(60, 100, 80), 8, 1.6, &mut tr), white, 0.4);
    a.materials[m_bronze].metallic = 0.7;
    // Models face +z at z = 0; `wall` turns that to face -x at the east wall.
    let wall = |s: usize| side(s) * at(HALF_X, 0.0, 0.0) * Mat4::from_rotation_y(-FRAC_PI_2);
    let mut b = MeshBuilder::new();
    let mut path = vec![Vec3::new(-1.2, 0.0, 0.0)];
    path.extend(arc_xy(Vec3::new(0.0, 3.0, 0.0), 1.2, PI, 0.0, 32));
    path.push(Vec3::new(1.2, 0.0, 0.0));
    b.sweep(&path, &creased(&[Vec2::new(-0.15, -0.1), Vec2::new(0.15, -0.1), Vec2::new(0.15, 0.12), Vec2::new(-0.15, 0.12)]), false, false, 1.0);
    let frame = a.mesh(b, "door_frame");
    let mut b = MeshBuilder::new();
    let door_prof: Vec<Vec2> = std::iter::once(Vec2::new(0.0, 0.0)).chain(arc_xy(Vec3::ZERO, 1.05, PI, 0.0, 24).iter().map(|p| Vec2::new(p.x, p.y))).collect();
    // Door leaf: a rectangle with a round head, tessellated as a fan-grid, 6 cm proud.
    b.patch(Vec3::new(-1.05, 0.0, 0.06), Vec3::new(2.1, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0), 14, 20, 0.5, Vec3::Z);
    let c = b.vert(Vec3::new(0.0, 3.0, 0.06), Vec2::new(0.5, 0.0));
    let first = b.idx().len();
    let ring: Vec<u32> = door_prof[1..].iter().map(|p| b.vert(Vec3::new(p.x, 3.0 + p.y, 0.06), Vec2::new(0.5 + p.x * 0.5, -p.y * 0.5))).collect();
    for w in ring.windows(2) {
        b.tri(c, w[0], w[1]);
    }
    b.face_towards(first, Vec3::Z);
    let door = a.mesh(b, "door_leaf");
    let mut b = MeshBuilder::new();
    let ring_path = |r: f32, n: u32| -> Vec<Vec3> {
        (0..n).map(|i| Vec3::new(r * (TAU * i as f32 / n as f32).cos(), r * (TAU * i as f32 / n as f32).sin(), 0.1)).collect()
    };
    b.sweep(&ring_path(1.7, 48), &circle(0.13, 10), true, false, 1.0);
    b.sweep(&ring_path(0.6, 32), &circle(0.08, 8), true, false, 1.0);
    for i in 0..12 {
        let a0 = TAU * i as f32 / 12.0;
        let d = Vec3::new(a0.cos(), a0.sin(), 0.0);
        let spoke: Vec<Vec3> = (0..=6).map(|j| d * (0.6 + 1.1 * j as f32 / 6.0) + Vec3::new(0.0, 0.0, 0.1)).collect();
        b.sweep(&spoke, &circle(0.05, 6), false, false, 1.0);
    }
    let rose = a.mesh(b, "rose_window_tracery");
    let mut b = MeshBuilder::new();
    b.lathe(&refine(&[Vec2::new(1.75, 0.0), Vec2::new(0.0, 0.0)], 0.25), 48, 1.0, 1.0);
    b.face_towards(0, Vec3::Y);
    let glass = a.mesh(b, "rose_window_glass");
    let masks = [a.mesh(mask(&mut gr, 32, 16), "mask_a"), a.mesh(mask(&mut gr, 32, 16), "mask_b")];
    for s in 0..2 {
        a.put(frame, m_frame, wall(s));
        a.put(door, m_door, wall(s));
        a.put(rose, m_rose, wall(s) * at(0.0, 8.4, 0.0));
        a.put(glass, m_glass, wall(s) * at(0.0, 8.4, 0.03) * Mat4::from_rotation_x(FRAC_PI_2));
        for (i, x) in [-2.6f32, 2.6].into_iter().enumerate() {
            a.put(masks[i], m_bronze, wall(s) * at(x, 4.6, 0.0) * Mat4::from_rotation_x(FRAC_PI_2) * Mat4::from_scale(Vec3::splat(0.32)));
        }
    }

    // --- Medallions on the attic -------------------------------------------------------------
    let m_med = [
        a.textured(tex_marble("atrium_medallion_a", 64, jitter(&mut tr, rgb(220, 210, 196), 0.05), rgb(150, 110, 90), 2.0, &mut tr), white, 0.4),
        a.textured(tex_noise("atrium_medallion_b", 64, jitter(&mut tr, rgb(120, 140, 110), 0.05), rgb(80, 90, 70), 4, 1.2, &mut tr), white, 0.4),
    ];
    let meds = [a.mesh(medallion(&mut gr, 0.3, 16), "medallion_a"), a.mesh(medallion(&mut gr, 0.3, 16), "medallion_b")];
    for s in 0..2 {
        for k in 0..COLUMNS {
            a.put(meds[k % 2], m_med[k % 2], side(s) * at(column_x(k), ROOF_Y0 + 0.35, -ARCADE_Z + G_PANEL_T / 2.0) * Mat4::from_rotation_x(FRAC_PI_2));
        }
    }

    // --- Fountain ------------------------------------------------------------------------------
    let m_basin = a.textured(tex_blocks("atrium_fountain_basin", 128, stone * 0.95, stone * 0.6, 2, 8, 0.06, &mut tr), white, 0.6);
    let m_water = a.textured(tex_noise("atrium_water", 128, jitter(&mut tr, rgb(40, 90, 110), 0.05), rgb(90, 150, 160), 8, 1.6, &mut tr), white, 0.05);
    let m_fmarble =
        a.textured(tex_marble("atrium_fountain_marble", 128, jitter(&mut tr, rgb(236, 230, 220), 0.04), rgb(120, 120, 130), 4.0, &mut tr), white, 0.3);
    let mut b = MeshBuilder::new();
    let basin = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.9, 0.0),
        Vec2::new(1.9, 0.0),
        Vec2::new(1.9, 0.5),
        Vec2::new(1.95, 0.55),
        Vec2::new(1.95, 0.6),
        Vec2::new(1.95, 0.6),
        Vec2::new(1.7, 0.6),
        Vec2::new(1.7, 0.6),
        Vec2::new(1.7, 0.15),
        Vec2::new(1.7, 0.15),
        Vec2::new(0.0, 0.15),
    ];
    b.lathe(&refine(&basin, 0.15), 48, 6.0, 1.0);
    let me = a.mesh(b, "fountain_basin");
    a.put(me, m_basin, Mat4::IDENTITY);
    let mut b = MeshBuilder::new();
    b.lathe(&refine(&[Vec2::new(1.7, 0.42), Vec2::new(0.0, 0.42)], 0.15), 48, 1.0, 1.0);
    b.map_positions(0, |p| Vec3::new(p.x, p.y + 0.01 * (p.x * 9.0).sin() * (p.z * 7.0).cos(), p.z));
    let me = a.mesh(b, "fountain_water");
    a.put(me, m_water, Mat4::IDENTITY);
    let mut prof = vec![Vec2::new(0.0, 0.1), Vec2::new(0.45, 0.1), Vec2::new(0.45, 0.1), Vec2::new(0.45, 0.3), Vec2::new(0.45, 0.3)];
    let n = 20;
    for i in 0..=n {
        let t = i as f32 / n as f32;
        prof.push(Vec2::new(0.22 + 0.06 * (t * 3.0 * TAU).cos() * (1.0 - t) + 0.05 * t, 0.3 + 1.2 * t));
    }
    // Upper bowl (outside up, rim, inside down), then a finial.
    prof.extend_from_slice(&refine(
        &[
            Vec2::new(0.3, 1.5),
            Vec2::new(0.9, 1.72),
            Vec2::new(0.95, 1.8),
            Vec2::new(0.95, 1.8),
            Vec2::new(0.85, 1.8),
            Vec2::new(0.85, 1.8),
            Vec2::new(0.2, 1.65),
        ],
        0.08,
    ));
    let n = 16;
    for i in 0..=n {
        let t = i as f32 / n as f32;
        let r = 0.2 * (1.0 - t) + 0.18 * (PI * t).sin();
        prof.push(Vec2::new(r, 1.65 + 0.7 * t));
    }
    prof.push(Vec2::new(0.0, 2.35));
    let mut b = MeshBuilder::new();
    b.lathe(&prof, 40, 2.0, 1.0);
    let me = a.mesh(b, "fountain_pedestal");
    a.put(me, m_fmarble, Mat4::IDENTITY);

    // --- Planted vases along the colonnades ----------------------------------------------------
    let m_vase: Vec<usize> = (0..3)
        .map(|i| {
            a.textured(tex_noise(&format!("atrium_terracotta_{i}"), 64, jitter(&mut tr, rgb(178, 96, 60), 0.08), rgb(120, 60, 40), 6, 1.2, &mut tr), white, 0.8)
        })
        .collect();
    let m_leaf: Vec<usize> = (0..3)
        .map(|i| {
            a.textured(tex_noise(&format!("atrium_foliage_{i}"), 64, jitter(&mut tr, rgb(40, 90, 36), 0.08), rgb(100, 140, 60), 16, 2.0, &mut tr), white, 0.9)
        })
        .collect();
    let vases: Vec<usize> = (0..4).map(|i| a.mesh(vase(&mut gr, 22), &format!("vase_{i}"))).collect();
    let mut n_bush = 0;
    for s in 0..2 {
        for (j, k) in [0usize, 2, 6, 8].into_iter().enumerate() {
            let h = a.meshes[vases[j]].bounds().max.y;
            let r = gr.range(0.45, 0.6);
            let me = a.mesh(bush(&mut gr, r, 28, 18), &format!("bush_{n_bush}"));
            let pos = side(s) * at(column_x(k), 0.0, -ARCADE_Z + 1.3);
            a.put(vases[j], m_vase[(j + s) % 3], pos);
            a.put(me, m_leaf[n_bush % 3], pos * at(0.0, h + 0.25, 0.0));
            n_bush += 1;
        }
    }
    // And one in each corner of the courtyard.
    for (j, (x, z)) in [(-13.6f32, -2.2f32), (13.6, -2.2), (-13.6, 2.2), (13.6, 2.2)].into_iter().enumerate() {
        let h = a.meshes[vases[3 - j]].bounds().max.y;
        let r = gr.range(0.4, 0.55);
        let me = a.mesh(bush(&mut gr, r, 28, 18), &format!("bush_{n_bush}"));
        a.put(vases[3 - j], m_vase[j % 3], at(x, 0.0, z));
        a.put(me, m_leaf[n_bush % 3], at(x, h + 0.25, z));
        n_bush += 1;
    }

    // The default view, also the first preset.
    let view = Camera::look(Vec3::new(-13.2, 1.8, 0.6), Vec3::new(6.0, 4.2, -0.4), 60.0, 0.05, 120.0);
    Scene {
        name: "atrium".into(),
        meshes: a.meshes.into_iter().map(Into::into).collect(),
        materials: a.materials.into(),
        instances: a.instances.into(),
        textures: a.textures,
        camera: view,
        presets: vec![
            ("courtyard".into(), view),
            ("gallery".into(), Camera::look(Vec3::new(-12.0, 7.6, -5.0), Vec3::new(10.0, 5.0, -4.0), 60.0, 0.05, 120.0)),
            ("aisle".into(), Camera::look(Vec3::new(12.0, 1.7, 5.2), Vec3::new(-10.0, 2.5, 5.0), 60.0, 0.05, 120.0)),
            ("sky".into(), Camera::look(Vec3::new(0.5, 30.0, 0.0), Vec3::new(0.0, 0.0, 0.0), 55.0, 0.05, 120.0)),
            // The Stress view (`bench rays`): down the south aisle under the gallery, no sky.
            ("stress".into(), Camera::look(Vec3::new(12.0, 1.7, 5.2), Vec3::new(-10.0, 2.5, 5.0), 60.0, 0.05, 120.0)),
            // Miss (inside): from the middle of the courtyard, above the fountain (2.35 m),
            // straight up through the open roof (its opening is 6.2 m across at 12 m; 24 degrees over the 6.2 m side leaves the
            // cornice out), so rays cross the scene's box and hit nothing.
            ("miss_inside".into(), Camera { up: Vec3::Z, ..Camera::look(Vec3::new(0.0, 2.6, 0.0), Vec3::new(0.0, 12.0, 0.0), 24.0, 0.05, 120.0) }),
        ],
        light: Light { direction: Vec3::new(-0.32, 0.88, 0.36).normalize(), color: Vec3::new(1.0, 0.95, 0.86), intensity: 3.2, ambient: 0.25 },
        point_light: None,
        lights: Vec::new(),
        rig: None,
        posed: None,
    }
}
