//! The "organic" scene: one closed, watertight head-like mesh (a frequency-14 geodesic
//! icosphere, 3,920 triangles, displaced radially with eye sockets, eyeballs, brows, a nose, a
//! mouth, ears with cavities and fine noise), smooth normals, seam-free mirrored spherical uvs
//! and two textures (a mottled base colour and a roughness map).
//!
//! Every vertex is shared by all triangles around it, every edge belongs to exactly two
//! triangles, and all triangles wind counter-clockwise seen from outside; the displacement is
//! along the radius and stays positive, so the surface never folds over itself.

use super::common::{fbm3, image, material, rgb, tex_roughness, Rng, TileNoise};
use crate::scene::{Camera, Instance, Light, Mesh, Scene, Vertex};
use glam::{Mat4, Vec2, Vec3};
use std::collections::HashMap;

/// Edge subdivisions of each icosahedron face: 20 * FREQ² triangles.
const FREQ: u32 = 14;

/// A bump (positive) or dent (negative) of `amp` around direction `c`; `w` is its chord radius,
/// `stretch` widens it along x.
struct Feature {
    c: Vec3,
    amp: f32,
    w: f32,
    stretch: f32,
}

fn features() -> Vec<Feature> {
    let f = |x: f32, y: f32, z: f32, amp: f32, w: f32, stretch: f32| Feature { c: Vec3::new(x, y, z).normalize(), amp, w, stretch };
    let mut v = Vec::new();
    for s in [-1.0f32, 1.0] {
        v.push(f(0.36 * s, 0.22, 0.9, -0.22, 0.22, 1.0)); // eye socket
        v.push(f(0.36 * s, 0.2, 0.91, 0.11, 0.11, 1.0)); // eyeball in the socket
        v.push(f(0.33 * s, 0.42, 0.85, 0.05, 0.17, 1.6)); // brow
        v.push(f(0.98 * s, 0.12, -0.05, 0.3, 0.24, 1.0)); // ear
        v.push(f(1.0 * s, 0.12, 0.02, -0.14, 0.13, 1.0)); // ear cavity
        v.push(f(0.5 * s, -0.25, 0.8, 0.05, 0.2, 1.0)); // cheek
    }
    v.push(f(0.0, 0.02, 1.0, 0.2, 0.13, 0.8)); // nose
    v.push(f(0.0, -0.06, 1.0, -0.05, 0.07, 1.4)); // under the nose
    v.push(f(0.0, -0.38, 0.92, -0.1, 0.12, 2.4)); // mouth
    v.push(f(0.0, -0.3, 0.95, 0.05, 0.2, 2.0)); // upper lip ridge
    v.push(f(0.0, -0.7, 0.7, 0.08, 0.25, 1.2)); // chin
    v.push(f(0.0, 0.8, -0.3, 0.06, 0.45, 1.0)); // crown
    v
}

/// Radius of the surface in direction `d` (unit).
fn radius(d: Vec3, feats: &[Feature], seed: u32) -> f32 {
    let mut r = 1.0 + 0.025 * fbm3(seed, d * 4.0, 3) * 2.0;
    for f in feats {
        let mut e = d - f.c;
        e.x /= f.stretch;
        r += f.amp * (-e.length_squared() / (f.w * f.w)).exp();
    }
    r.max(0.5)
}

/// The icosahedron's 12 corners and 20 faces, wound counter-clockwise from outside.
fn icosahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let corners: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for f in &mut faces {
        let (a, b, c) = (corners[f[0] as usize], corners[f[1] as usize], corners[f[2] as usize]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            f.swap(1, 2);
        }
    }
    (corners, faces)
}

/// The closed head mesh.
pub(super) fn head_mesh(seed: u32) -> Mesh {
    let (corners, faces) = icosahedron();
    let feats = features();
    let n = FREQ;
    let mut dirs: Vec<Vec3> = Vec::new();
    let mut index: HashMap<[(u32, u32); 3], u32> = HashMap::new();
    let mut indices = Vec::with_capacity((20 * n * n * 3) as usize);
    for f in &faces {
        // Lattice point (i, j): weights (n - i - j, i, j) on the corners (a, b, c).
        let mut id = |i: u32, j: u32| -> u32 {
            let mut key = [(f[0], n - i - j), (f[1], i), (f[2], j)];
            for k in &mut key {
                if k.1 == 0 {
                    *k = (u32::MAX, 0);
                }
            }
            key.sort_unstable();
            *index.entry(key).or_insert_with(|| {
                let p = key.iter().filter(|k| k.1 > 0).map(|k| corners[k.0 as usize] * k.1 as f32).sum::<Vec3>();
                dirs.push(p.normalize());
                (dirs.len() - 1) as u32
            })
        };
        for i in 0..n {
            for j in 0..n - i {
                let (a, b, c) = (id(i, j), id(i + 1, j), id(i, j + 1));
                indices.extend_from_slice(&[a, b, c]);
                if i + j + 1 < n {
                    let d = id(i + 1, j + 1);
                    indices.extend_from_slice(&[b, d, c]);
                }
            }
        }
    }
    // Displace, then squash into a head-like ellipsoid (a positive scale keeps the winding).
    let scale = Vec3::new(0.86, 1.0, 0.92);
    let pos: Vec<Vec3> = dirs.iter().map(|&d| d * radius(d, &feats, seed) * scale).collect();
    let mut acc = vec![Vec3::ZERO; pos.len()];
    for t in indices.chunks_exact(3) {
        let nrm = (pos[t[1] as usize] - pos[t[0] as usize]).cross(pos[t[2] as usize] - pos[t[0] as usize]);
        for &i in t {
            acc[i as usize] += nrm;
        }
    }
    let vertices = dirs
        .iter()
        .zip(&pos)
        .zip(&acc)
        .map(|((d, p), a)| {
            // Mirrored spherical projection: continuous everywhere, so no seam is needed.
            let h = (d.x * d.x + d.z * d.z).sqrt();
            let u = if h > 1e-6 { (d.z / h).clamp(-1.0, 1.0).acos() / std::f32::consts::PI } else { 0.5 };
            let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
            Vertex { position: (*p).into(), normal: a.normalize_or(*d).into(), uv: (Vec2::new(u, v) * 2.0).into() }
        })
        .collect();
    Mesh { name: "organic_head".into(), vertices, indices, tangents: None, extras: None }
}

pub(super) fn build() -> Scene {
    let mut rng = Rng::new(0x0E6A);
    let mesh = head_mesh(rng.seed32());
    let noise = TileNoise::new(&mut rng, 4, 4);
    let spots = TileNoise::new(&mut rng, 16, 2);
    let (skin, shade, spot) = (rgb(196, 150, 118), rgb(150, 96, 84), rgb(120, 82, 60));
    let base = image("organic_skin", 256, |u, v| {
        let c = skin.lerp(shade, (0.5 + 1.6 * noise.at(u, v)).clamp(0.0, 1.0));
        let s = spots.at(u, v);
        if s > 0.28 {
            c.lerp(spot, ((s - 0.28) * 6.0).min(0.6))
        } else {
            c
        }
    });
    let textures = vec![base, tex_roughness("organic_roughness", 128, 0.55, 0.6, &mut rng)];
    let mut m = material("organic_skin", [1.0; 4], Some(0), 0.55);
    m.metallic_roughness_texture = Some(1);
    // The default view, also the first preset.
    let view = Camera::look(Vec3::new(1.5, 0.7, 3.0), Vec3::new(0.0, 0.05, 0.0), 45.0, 0.05, 50.0);
    Scene {
        name: "organic".into(),
        meshes: vec![mesh.into()],
        materials: vec![m].into(),
        instances: vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }].into(),
        textures,
        camera: view,
        presets: vec![
            ("three-quarter".into(), view),
            ("front".into(), Camera::look(Vec3::new(0.0, 0.1, 3.2), Vec3::new(0.0, 0.05, 0.0), 45.0, 0.05, 50.0)),
            ("profile".into(), Camera::look(Vec3::new(3.2, 0.2, 0.0), Vec3::new(0.0, 0.05, 0.0), 45.0, 0.05, 50.0)),
            // The Stress view (`bench rays`): the face fills the frame, no sky.
            ("stress".into(), Camera::look(Vec3::new(0.0, 0.1, 2.2), Vec3::new(0.0, 0.05, 0.0), 20.0, 0.05, 50.0)),
        ],
        light: Light { direction: Vec3::new(0.5, 0.7, 0.5).normalize(), color: Vec3::new(1.0, 0.97, 0.92), intensity: 3.0, ambient: 0.3 },
        point_light: None,
        lights: Vec::new(),
        rig: None,
        posed: None,
        environment: None,
    }
}
