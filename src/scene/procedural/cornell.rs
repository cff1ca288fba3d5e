//! The "cornell" scene: the Cornell box of the Cornell Program of Computer Graphics' measured
//! data (the original's millimetre coordinates scaled by 1/100: a box about 5.5 units on a
//! side), for comparisons with outside renderers (Mitsuba 3's `cbox`). A red left wall, a green
//! right wall, white floor, ceiling and back wall, a short and a tall white block rotated as in
//! the original, and the open front the camera looks in through: 32 triangles.
//!
//! Materials are as close to pure Lambert as the material model allows: metallic 0, roughness
//! 1 and specular factor 0 (`KHR_materials_specular`: no dielectric reflection at any angle),
//! with the reflectances of Mitsuba's `cbox`. The only light is the emissive quad just below
//! the ceiling (Mitsuba's radiance); the default sun has intensity 0 and the sky's ambient is 0
//! (a black environment). The raster, hybrid and full-RT graphs do not light surfaces from
//! emissive ones, so there the box is black but for the light itself; that is expected. The GI
//! graphs (`graph/hybrid_soft_gi.ron`, `graph/hybrid_denoised.ron`) gather one bounce of its
//! emission; the path tracer (`graph/reference.ron`) lights it fully (checked against Mitsuba 3
//! in `tests/path_tracer.rs`).

use crate::scene::{Camera, Instance, Light, Lobes, Material, Mesh, Scene};
use glam::{Mat4, Vec3};

/// The original data's millimetres to scene units.
const SCALE: f32 = 0.01;
/// The light quad's gap below the ceiling (original millimetres).
const LIGHT_GAP: f32 = 0.5;

/// Lambert reflectances of Mitsuba's `cbox`: white, red, green.
const WHITE: [f32; 3] = [0.885809, 0.698859, 0.666422];
const RED: [f32; 3] = [0.570068, 0.0430135, 0.0443706];
const GREEN: [f32; 3] = [0.105421, 0.37798, 0.076425];
/// Emitted radiance of the light (Mitsuba's `cbox`).
pub(super) const LIGHT_RADIANCE: [f32; 3] = [18.387, 13.9873, 6.75357];

/// A point of the original data (millimetres) in scene units.
fn p(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z) * SCALE
}

/// Flat quads (each four corners in order around it) facing away from `inside` where `outward`,
/// else towards it: one mesh of two triangles per quad, each quad with its own vertices and
/// normal.
fn quads(name: &str, faces: &[[Vec3; 4]], inside: Vec3, outward: bool) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for corners in faces {
        let centre = corners.iter().sum::<Vec3>() / 4.0;
        let mut normal = (corners[2] - corners[0]).cross(corners[3] - corners[1]).normalize();
        let towards_inside = normal.dot(inside - centre) > 0.0;
        let flip = towards_inside == outward;
        if flip {
            normal = -normal;
        }
        let base = vertices.len() as u32;
        for (c, uv) in corners.iter().zip([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) {
            vertices.push(crate::scene::Vertex { position: (*c).into(), normal: normal.into(), uv });
        }
        let (b, c) = if flip { (3, 2) } else { (1, 2) };
        let d = if flip { 1 } else { 3 };
        indices.extend_from_slice(&[base, base + b, base + c, base, base + c, base + d]);
    }
    Mesh { name: name.into(), vertices, indices, tangents: None, extras: None }
}

/// A Lambert material: reflectance `rgb`, metallic 0, roughness 1, specular factor 0.
fn lambert(name: &str, rgb: [f32; 3]) -> Material {
    Material { roughness: 1.0, lobes: Lobes { specular: 0.0, ..Lobes::default() }, ..Material::diffuse(name, [rgb[0], rgb[1], rgb[2], 1.0], None) }
}

/// The walls: floor, ceiling, back (white), left (red), right (green), as in the original.
fn walls() -> [(&'static str, [Vec3; 4], usize); 5] {
    [
        ("floor", [p(552.8, 0.0, 0.0), p(0.0, 0.0, 0.0), p(0.0, 0.0, 559.2), p(549.6, 0.0, 559.2)], 0),
        ("ceiling", [p(556.0, 548.8, 0.0), p(556.0, 548.8, 559.2), p(0.0, 548.8, 559.2), p(0.0, 548.8, 0.0)], 0),
        ("back wall", [p(549.6, 0.0, 559.2), p(0.0, 0.0, 559.2), p(0.0, 548.8, 559.2), p(556.0, 548.8, 559.2)], 0),
        ("left wall", [p(552.8, 0.0, 0.0), p(549.6, 0.0, 559.2), p(556.0, 548.8, 559.2), p(556.0, 548.8, 0.0)], 1),
        ("right wall", [p(0.0, 0.0, 559.2), p(0.0, 0.0, 0.0), p(0.0, 548.8, 0.0), p(0.0, 548.8, 559.2)], 2),
    ]
}

/// A block of the original: its top's four corners (millimetres) and its height; the top and
/// four sides (no bottom, as in the original).
fn block(name: &str, top: [[f32; 2]; 4], height: f32) -> Mesh {
    let up: Vec<Vec3> = top.iter().map(|[x, z]| p(*x, height, *z)).collect();
    let down: Vec<Vec3> = top.iter().map(|[x, z]| p(*x, 0.0, *z)).collect();
    let mut faces = vec![[up[0], up[1], up[2], up[3]]];
    for i in 0..4 {
        let j = (i + 1) % 4;
        faces.push([down[i], up[i], up[j], down[j]]);
    }
    let centre = up.iter().chain(&down).sum::<Vec3>() / 8.0;
    quads(name, &faces, centre, true)
}

/// The classic view: the original camera at (278, 273, -800) looking along +z, a 39.3° field
/// of view on a square film.
fn classic_camera() -> Camera {
    let mut camera = Camera::look(p(278.0, 273.0, -800.0), p(278.0, 273.0, 0.0), 39.3077, 0.05, 30.0);
    camera.aspect_ratio = Some(1.0);
    camera
}

pub(super) fn build() -> Scene {
    let inside = p(278.0, 274.4, 279.6);
    let mut meshes: Vec<Mesh> = walls().iter().map(|(name, quad, _)| quads(name, &[*quad], inside, false)).collect();
    let mut material_of: Vec<usize> = walls().iter().map(|w| w.2).collect();
    meshes.push(block("short block", [[130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0]], 165.0));
    meshes.push(block("tall block", [[423.0, 247.0], [265.0, 296.0], [314.0, 456.0], [472.0, 406.0]], 330.0));
    material_of.extend([0, 0]);
    let y = 548.8 - LIGHT_GAP;
    let light = [p(343.0, y, 227.0), p(343.0, y, 332.0), p(213.0, y, 332.0), p(213.0, y, 227.0)];
    meshes.push(quads("light", &[light], p(278.0, 0.0, 279.5), false));
    material_of.push(3);
    let materials =
        vec![lambert("white", WHITE), lambert("red", RED), lambert("green", GREEN), Material { emissive: LIGHT_RADIANCE, ..lambert("light", WHITE) }];
    let instances: Vec<Instance> = material_of.iter().enumerate().map(|(mesh, &material)| Instance { mesh, material, transform: Mat4::IDENTITY }).collect();
    let view = classic_camera();
    Scene {
        name: "cornell".into(),
        meshes: meshes.into_iter().map(Into::into).collect(),
        materials: materials.into(),
        instances: instances.into(),
        textures: Vec::new(),
        camera: view,
        presets: vec![
            ("classic".into(), view),
            ("inside".into(), Camera::look(p(278.0, 273.0, 100.0), p(278.0, 200.0, 559.2), 60.0, 0.05, 30.0)),
            ("corner".into(), Camera::look(p(60.0, 480.0, 60.0), p(330.0, 120.0, 400.0), 60.0, 0.05, 30.0)),
        ],
        // No sun and no sky: the light quad is the only source.
        light: Light { intensity: 0.0, ambient: 0.0, ..Light::default() },
        point_light: None,
        lights: Vec::new(),
        rig: None,
        posed: None,
        environment: None,
    }
}
