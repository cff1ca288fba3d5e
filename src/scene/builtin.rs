//! The built-in default scene: a few lit primitives on a textured floor. Generated
//! deterministically; needs no files.

use super::*;
use std::f32::consts::PI;

/// A square in the xz plane, facing +y, `size` wide, with uv repeated `tiles` times.
pub fn plane(name: &str, size: f32, tiles: f32) -> Mesh {
    let h = size / 2.0;
    let n = [0.0, 1.0, 0.0];
    let v = |x: f32, z: f32, u: f32, w: f32| Vertex { position: [x, 0.0, z], normal: n, uv: [u, w] };
    Mesh {
        name: name.into(),
        vertices: vec![v(-h, -h, 0.0, 0.0), v(-h, h, 0.0, tiles), v(h, h, tiles, tiles), v(h, -h, tiles, 0.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    }
}

/// A unit cube centred at the origin (24 vertices, 12 triangles).
pub fn cube(name: &str) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ];
    for (n, u, w) in faces {
        let (n, u, w) = (Vec3::from(n), Vec3::from(u), Vec3::from(w));
        let base = vertices.len() as u32;
        for (su, sw) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = 0.5 * (n + su * u + sw * w);
            vertices.push(Vertex { position: p.into(), normal: n.into(), uv: [(su + 1.0) / 2.0, (1.0 - sw) / 2.0] });
        }
        indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    Mesh { name: name.into(), vertices, indices, tangents: None, extras: None }
}

/// A UV sphere of radius 1.
pub fn sphere(name: &str, rings: u32, segments: u32) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for r in 0..=rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..=segments {
            // The seam's two columns and each pole's row at exactly one position, so that the
            // mesh is closed (`scene::topology`).
            let phi = 2.0 * PI * (s % segments) as f32 / segments as f32;
            let ring = if r == 0 || r == rings { 0.0 } else { theta.sin() };
            let n = Vec3::new(ring * phi.cos(), theta.cos(), -ring * phi.sin());
            vertices.push(Vertex { position: n.into(), normal: n.into(), uv: [s as f32 / segments as f32, r as f32 / rings as f32] });
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            if r != 0 {
                indices.extend_from_slice(&[a, b, a + 1]);
            }
            if r != rings - 1 {
                indices.extend_from_slice(&[a + 1, b, b + 1]);
            }
        }
    }
    Mesh { name: name.into(), vertices, indices, tangents: None, extras: None }
}

/// A checkerboard texture.
pub fn checker(name: &str, size: u32, cells: u32, a: [u8; 3], b: [u8; 3]) -> TextureImage {
    let mut rgba = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            let c = if ((x * cells / size) + (y * cells / size)).is_multiple_of(2) { a } else { b };
            rgba.extend_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
    TextureImage { name: name.into(), width: size, height: size, rgba: rgba.into() }
}

/// A brick pattern texture.
pub(crate) fn bricks(name: &str, size: u32) -> TextureImage {
    let mut rgba = Vec::with_capacity((size * size * 4) as usize);
    let rows = 8;
    let bh = size / rows;
    let bw = bh * 2;
    for y in 0..size {
        for x in 0..size {
            let row = y / bh;
            let xo = (x + if row % 2 == 1 { bw / 2 } else { 0 }) % bw;
            let mortar = y % bh < 2 || xo < 2;
            // A little deterministic variation per brick.
            let id = row.wrapping_mul(73856093) ^ ((x + if row % 2 == 1 { bw / 2 } else { 0 }) / bw).wrapping_mul(19349663);
            let shade = (id % 40) as u8;
            let c = if mortar { [200, 196, 186] } else { [150 + shade, 62 + shade / 2, 48] };
            rgba.extend_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
    TextureImage { name: name.into(), width: size, height: size, rgba: rgba.into() }
}

/// The default scene: a checker floor, a brick cube, two spheres.
pub fn default_scene() -> Scene {
    let meshes = vec![plane("floor", 12.0, 6.0), cube("cube"), sphere("sphere", 24, 48)];
    let textures = vec![checker("checker", 256, 8, [225, 225, 225], [60, 60, 66]), bricks("bricks", 256)];
    let materials = vec![
        Material::diffuse("floor", [1.0, 1.0, 1.0, 1.0], Some(0)),
        Material::diffuse("bricks", [1.0, 1.0, 1.0, 1.0], Some(1)),
        Material::diffuse("red", [0.8, 0.15, 0.1, 1.0], None),
        Material { metallic: 1.0, roughness: 0.08, ..Material::diffuse("blue", [0.15, 0.3, 0.85, 1.0], None) },
    ];
    let instances = vec![
        Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY },
        Instance {
            mesh: 1,
            material: 1,
            transform: Mat4::from_scale_rotation_translation(Vec3::splat(1.6), glam::Quat::from_rotation_y(0.5), Vec3::new(-1.6, 0.8, 0.0)),
        },
        Instance { mesh: 2, material: 2, transform: Mat4::from_scale_rotation_translation(Vec3::splat(0.9), glam::Quat::IDENTITY, Vec3::new(1.2, 0.9, 0.6)) },
        Instance { mesh: 2, material: 3, transform: Mat4::from_scale_rotation_translation(Vec3::splat(0.5), glam::Quat::IDENTITY, Vec3::new(0.2, 0.5, 2.2)) },
    ];
    // The default view, also the first preset.
    let view = Camera::look(Vec3::new(3.5, 3.2, 6.5), Vec3::new(0.0, 0.6, 0.4), 50.0, 0.05, 100.0);
    Scene {
        name: "default".into(),
        meshes: meshes.into_iter().map(Into::into).collect(),
        materials: materials.into(),
        instances: instances.into(),
        textures,
        camera: view,
        presets: vec![
            ("main".into(), view),
            ("low".into(), Camera::look(Vec3::new(-4.0, 0.6, 4.5), Vec3::new(0.0, 0.8, 0.0), 50.0, 0.05, 100.0)),
            ("top".into(), Camera::look(Vec3::new(0.0, 9.0, 0.01), Vec3::ZERO, 50.0, 0.05, 100.0)),
        ],
        light: Light { direction: Vec3::new(-0.4, 0.8, 0.45).normalize(), color: Vec3::new(1.0, 0.96, 0.9), intensity: 3.0, ambient: 0.35 },
        point_light: None,
        lights: Vec::new(),
        rig: None,
        posed: None,
        environment: None,
    }
}
