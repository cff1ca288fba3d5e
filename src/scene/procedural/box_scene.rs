//! The "box" scene: one unit cube (12 triangles) with a wooden-crate base-colour texture and a
//! roughness map, a camera looking at it from above-front-right, and a directional light.

use super::common::{image, material, tex_roughness, MeshBuilder, Rng, TileNoise};
use crate::scene::{Camera, Instance, Light, Scene};
use glam::{Mat4, Vec3};

/// A crate face: a frame of boards around diagonal-braced planks.
fn crate_texture(rng: &mut Rng) -> crate::scene::TextureImage {
    let noise = TileNoise::new(rng, 4, 3);
    let light = super::common::rgb(196, 150, 96);
    let dark = super::common::rgb(112, 74, 40);
    image("box_crate", 256, |u, v| {
        let frame = !(0.1..=0.9).contains(&u) || !(0.1..=0.9).contains(&v);
        let brace = (u - v).abs() < 0.07 && !frame;
        let grain_dir = if frame && (0.1..=0.9).contains(&u) { u } else { v };
        let g = ((grain_dir * 30.0 + 4.0 * noise.at(u, v)) * std::f32::consts::PI).sin() * 0.5 + 0.5;
        let mut c = light.lerp(dark, 0.45 * g);
        if !frame && !brace {
            // Planks across u with dark gaps.
            let fv = (v * 5.0).fract();
            c *= if fv < 0.03 { 0.45 } else { 0.9 };
        }
        let edge = |t: f32| (t - 0.1).abs() < 0.008 || (t - 0.9).abs() < 0.008;
        if edge(u) || edge(v) || (brace && ((u - v).abs() - 0.07).abs() < 0.008) {
            c *= 0.5;
        }
        c
    })
}

pub(super) fn build() -> Scene {
    let mut rng = Rng::new(0xB0C5);
    let mut b = MeshBuilder::new();
    b.cuboid(Vec3::splat(-0.5), Vec3::splat(0.5), 1.0, 1.0);
    let mesh = b.finish("box");
    let textures = vec![crate_texture(&mut rng), tex_roughness("box_roughness", 128, 0.7, 0.5, &mut rng)];
    let mut m = material("crate", [1.0; 4], Some(0), 0.7);
    m.metallic_roughness_texture = Some(1);
    // The default view, also the first preset.
    let view = Camera::look(Vec3::new(1.6, 1.3, 2.2), Vec3::ZERO, 45.0, 0.05, 50.0);
    Scene {
        name: "box".into(),
        meshes: vec![mesh.into()],
        materials: vec![m].into(),
        instances: vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }].into(),
        textures,
        camera: view,
        presets: vec![
            ("corner".into(), view),
            ("front".into(), Camera::look(Vec3::new(0.0, 0.0, 2.5), Vec3::ZERO, 45.0, 0.05, 50.0)),
            ("close".into(), Camera::look(Vec3::new(0.45, 0.35, 0.9), Vec3::ZERO, 60.0, 0.05, 50.0)),
            // The Stress view (`bench rays`): one face fills the frame, no sky.
            ("stress".into(), Camera::look(Vec3::new(0.08, 0.06, 1.1), Vec3::new(0.0, 0.0, 0.5), 40.0, 0.05, 50.0)),
        ],
        light: Light { direction: Vec3::new(-0.45, 0.8, 0.4).normalize(), color: Vec3::new(1.0, 0.97, 0.92), intensity: 3.0, ambient: 0.3 },
        point_light: None,
        lights: Vec::new(),
        rig: None,
        posed: None,
        environment: None,
    }
}
