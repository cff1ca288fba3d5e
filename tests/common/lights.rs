//! Scenes of many lights shared by tests/many_lights.rs and tests/restir.rs.

use glam::{Mat4, Vec3};
use raygraph::scene::builtin::{cube, default_scene, plane};
use raygraph::scene::{Camera, Instance, LightKind, Material, PunctualLight, Scene};

/// A floor and a block under sixteen coloured point lights (some with a range) and a dim sun,
/// no sky: every light's shadow and colour shows.
pub fn sixteen_lights() -> Scene {
    let mut s = default_scene();
    s.set_name("sixteen lights");
    s.set_meshes(vec![plane("floor", 20.0, 1.0), cube("block")]);
    *s.textures_mut() = Vec::new();
    // Smooth enough for reflection rays (rt_reflection's max_roughness is 0.5), whose hits
    // are lit by the lights too.
    let mut m = Material::diffuse("grey", [0.6, 0.6, 0.6, 1.0], None);
    m.roughness = 0.3;
    *s.materials_mut() = vec![m];
    *s.instances_mut() = vec![
        Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY },
        Instance { mesh: 1, material: 0, transform: Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)) },
    ];
    let mut lights: Vec<PunctualLight> = (0..16)
        .map(|i| {
            let a = i as f32 * 0.3927;
            let colour = Vec3::new(0.3 + 0.7 * (i % 3) as f32 / 2.0, 0.3 + 0.7 * (i % 5) as f32 / 4.0, 1.0 - 0.6 * (i % 4) as f32 / 3.0);
            PunctualLight {
                name: format!("light {i}"),
                kind: LightKind::Point { range: if i % 4 == 0 { Some(3.0) } else { None } },
                position: Vec3::new(2.5 * a.cos(), 0.6 + 0.25 * (i % 5) as f32, 2.5 * a.sin()),
                direction: Vec3::NEG_Y,
                color: colour,
                intensity: 0.2 + 0.1 * (i % 7) as f32,
            }
        })
        .collect();
    lights.push(PunctualLight {
        name: "dim sun".into(),
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        color: Vec3::ONE,
        intensity: 0.1,
    });
    *s.lights_mut() = lights;
    s.light_mut().ambient = 0.0;
    *s.camera_mut() = Camera::look(Vec3::new(0.0, 5.0, 4.0), Vec3::ZERO, 60.0, 0.01, 100.0);
    s
}
