//! The atrium's shapes: each a [`MeshBuilder`] in its own model space (columns, arch panels,
//! mouldings, cloth, vases, the end walls' door and rose window, the fountain, ...), from the
//! dimensions and seeded randomness it is given. Where they go is `layout`'s business.

use super::super::common::{arc_xy, circle, fbm3, rect_profile, MeshBuilder, Rng};
use super::layout::{ColumnSpec, Drape, BAY, HALF_X, UPPER_COLUMN};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

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

/// A column standing on y = 0: plinth, moulded base, fluted weathered shaft with entasis,
/// capital and abacus. `twist` turns the flutes along the shaft.
pub(super) fn column(s: &ColumnSpec, rng: &mut Rng, twist: f32) -> MeshBuilder {
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
pub(super) fn arch_panel(radius: f32, height: f32, t: f32, arc_segments: u32, rings: u32) -> MeshBuilder {
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
pub(super) fn archivolt(radius: f32, t: f32, segments: u32) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let path = arc_xy(Vec3::new(0.0, 0.0, t / 2.0), radius + 0.08, PI, 0.0, segments);
    b.sweep(&path, &circle(0.09, 6), false, false, 2.0);
    b
}

/// A straight moulding along x over [-HALF_X, HALF_X] with `profile` in (y, z) offsets.
pub(super) fn moulding(profile: &[Vec2], segments: usize) -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let path: Vec<Vec3> = (0..=segments).map(|i| Vec3::new(-HALF_X + 2.0 * HALF_X * i as f32 / segments as f32, 0.0, 0.0)).collect();
    // Along +x the sweep frame is normal = +y, binormal = +z.
    b.sweep(&path, &creased(profile), false, false, 1.0);
    b
}

/// A transverse rib across the aisle, in the yz plane from the column line towards the wall,
/// springing at y = 0.
pub(super) fn rib(span: f32, rise: f32, segments: u32) -> MeshBuilder {
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
pub(super) fn baluster(h: f32, segments: u32) -> MeshBuilder {
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

/// A hanging cloth of `drape`'s size: top edge along x at y = 0, hanging down, bulging towards
/// +z (its front). Folds, a sagging hem and a breeze come from `rng`.
pub(super) fn cloth(rng: &mut Rng, drape: &Drape) -> MeshBuilder {
    let Drape { width: w, drop: h, cells: [nu, nv], fold_amp } = *drape;
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
pub(super) fn vase(rng: &mut Rng, segments: u32) -> MeshBuilder {
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
pub(super) fn bush(rng: &mut Rng, r: f32, segments: u32, rings: u32) -> MeshBuilder {
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
pub(super) fn lantern(rng: &mut Rng, chain: f32, segments: u32) -> MeshBuilder {
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
pub(super) fn medallion(rng: &mut Rng, r: f32, segments: u32) -> MeshBuilder {
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
pub(super) fn mask(rng: &mut Rng, segments: u32, rings: u32) -> MeshBuilder {
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

/// An engaged pier where an arcade meets an end wall: filling the `BAY / 2 - radius` the last
/// arch leaves, `panel_t` deep, `height` tall from y = 0.
pub(super) fn pier(radius: f32, panel_t: f32, height: f32) -> MeshBuilder {
    let hw = BAY / 2.0 - radius;
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-hw / 2.0, 0.0, -panel_t / 2.0), Vec3::new(hw / 2.0, height, panel_t / 2.0), 0.25, 1.0);
    b
}

/// A balustrade rail between two upper columns' plinths, `half_depth` either side of z = 0
/// and `height` tall from y = 0.
pub(super) fn rail(half_depth: f32, height: f32) -> MeshBuilder {
    let rail_len = BAY - 2.0 * UPPER_COLUMN.plinth_hw;
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-rail_len / 2.0, 0.0, -half_depth), Vec3::new(rail_len / 2.0, height, half_depth), 0.3, 1.0);
    b
}

/// A pilaster on an aisle wall, one unit tall (scaled to its storey) with a capital slab.
pub(super) fn wall_pilaster() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-0.25, 0.0, 0.0), Vec3::new(0.25, 1.0, 0.15), 0.25, 1.0);
    b.cuboid(Vec3::new(-0.32, 1.0, 0.0), Vec3::new(0.32, 1.02, 0.22), 0.25, 1.0);
    b
}

/// A wooden bench: a seat on two legs.
pub(super) fn bench() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::new(-0.9, 0.42, -0.22), Vec3::new(0.9, 0.5, 0.22), 0.2, 1.0);
    for x in [-0.75f32, 0.75] {
        b.cuboid(Vec3::new(x - 0.05, 0.0, -0.18), Vec3::new(x + 0.05, 0.42, 0.18), 0.2, 1.0);
    }
    b
}

/// The iron rod a curtain hangs from, along x.
pub(super) fn curtain_rod() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    b.sweep(&[Vec3::new(-1.3, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.3, 0.0, 0.0)], &circle(0.03, 8), false, true, 2.0);
    b
}

/// The round-headed frame of an end wall's door, facing +z at z = 0.
pub(super) fn door_frame() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let mut path = vec![Vec3::new(-1.2, 0.0, 0.0)];
    path.extend(arc_xy(Vec3::new(0.0, 3.0, 0.0), 1.2, PI, 0.0, 32));
    path.push(Vec3::new(1.2, 0.0, 0.0));
    b.sweep(&path, &creased(&[Vec2::new(-0.15, -0.1), Vec2::new(0.15, -0.1), Vec2::new(0.15, 0.12), Vec2::new(-0.15, 0.12)]), false, false, 1.0);
    b
}

/// The door leaf: a rectangle with a round head, tessellated as a fan-grid, 6 cm proud.
pub(super) fn door_leaf() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    let door_prof: Vec<Vec2> = std::iter::once(Vec2::new(0.0, 0.0)).chain(arc_xy(Vec3::ZERO, 1.05, PI, 0.0, 24).iter().map(|p| Vec2::new(p.x, p.y))).collect();
    b.patch(Vec3::new(-1.05, 0.0, 0.06), Vec3::new(2.1, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0), 14, 20, 0.5, Vec3::Z);
    let c = b.vert(Vec3::new(0.0, 3.0, 0.06), Vec2::new(0.5, 0.0));
    let first = b.idx().len();
    let ring: Vec<u32> = door_prof[1..].iter().map(|p| b.vert(Vec3::new(p.x, 3.0 + p.y, 0.06), Vec2::new(0.5 + p.x * 0.5, -p.y * 0.5))).collect();
    for w in ring.windows(2) {
        b.tri(c, w[0], w[1]);
    }
    b.face_towards(first, Vec3::Z);
    b
}

/// The rose window's tracery around its centre: an outer and an inner ring joined by twelve
/// spokes, 10 cm proud of z = 0.
pub(super) fn rose_tracery() -> MeshBuilder {
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
    b
}

/// The rose window's glass: a disc facing +y (turned to face the courtyard where it is placed).
pub(super) fn rose_glass() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    b.lathe(&refine(&[Vec2::new(1.75, 0.0), Vec2::new(0.0, 0.0)], 0.25), 48, 1.0, 1.0);
    b.face_towards(0, Vec3::Y);
    b
}

/// The fountain's basin: a low round wall with a rim around a floor.
pub(super) fn fountain_basin() -> MeshBuilder {
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
    b
}

/// The water in the basin: a rippled disc.
pub(super) fn fountain_water() -> MeshBuilder {
    let mut b = MeshBuilder::new();
    b.lathe(&refine(&[Vec2::new(1.7, 0.42), Vec2::new(0.0, 0.42)], 0.15), 48, 1.0, 1.0);
    b.map_positions(0, |p| Vec3::new(p.x, p.y + 0.01 * (p.x * 9.0).sin() * (p.z * 7.0).cos(), p.z));
    b
}

/// The fountain's pedestal: a fluted stem, an upper bowl and a finial.
pub(super) fn fountain_pedestal() -> MeshBuilder {
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
    b
}
