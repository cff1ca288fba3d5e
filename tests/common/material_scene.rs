//! The procedural metallic-roughness scene shared by tests/real_assets.rs and
//! tests/mode_agreement.rs: data textures, normal maps, occlusion, emission, a large ground
//! plane, mirrored and double-sided instances, and tiles of constant textures whose G-buffer
//! channels have closed forms.

use glam::{Mat4, Quat, Vec3};
use raygraph::scene::builtin::{cube, plane, sphere};
use raygraph::scene::{Camera, Light, Material, Mesh, Scene, TextureImage};

/// An RGBA8 texture of `size`² texels from a function of the texel centre's uv.
fn texture(name: &str, size: u32, f: impl Fn(f32, f32) -> [u8; 4]) -> TextureImage {
    let mut rgba = Vec::new();
    for y in 0..size {
        for x in 0..size {
            rgba.extend_from_slice(&f((x as f32 + 0.5) / size as f32, (y as f32 + 0.5) / size as f32));
        }
    }
    TextureImage { name: name.into(), width: size, height: size, rgba: rgba.into() }
}

fn constant(name: &str, texel: [u8; 4]) -> TextureImage {
    texture(name, 4, |_, _| texel)
}

/// Texels of the procedural scene's constant tiles.
pub const MR_TEXEL: [u8; 4] = [255, 64, 192, 255]; // roughness 64/255, metallic 192/255
pub const OCCLUSION_RED: u8 = 51; // 0.2
pub const EMISSIVE_TEXEL: [u8; 4] = [188, 100, 255, 255]; // sRGB
/// A normal-map texel tilted 30 degrees towards +x (tangent, +u) and one towards +y (-v).
pub fn tilted(axis: usize) -> [u8; 4] {
    let (s, c) = (30f32.to_radians().sin(), 30f32.to_radians().cos());
    let mut m = [0.0, 0.0, c];
    m[axis] = s;
    let b = |v: f32| ((v * 0.5 + 0.5) * 255.0).round() as u8;
    [b(m[0]), b(m[1]), b(m[2]), 255]
}

/// The procedural metallic-roughness scene: a 40 x 40 ground (smooth metallic-roughness,
/// normal and occlusion textures, repeated 8 times), four tiles with constant textures (the
/// closed-form checks), a textured sphere, a mirrored box and a double-sided card seen from
/// behind beside a single-sided one (culled in both modes).
pub fn metallic_roughness_scene() -> (Scene, Vec<(&'static str, Vec3)>) {
    let wave = |u: f32, v: f32| (0.5 + 0.5 * (u * std::f32::consts::TAU).sin() * (v * std::f32::consts::TAU).cos()).clamp(0.0, 1.0);
    let textures = vec![
        // 0: ground base colour (sRGB), 1: ground metallic-roughness, 2: ground normal map, 3: ground occlusion
        texture("ground base", 64, |u, v| [(80.0 + 120.0 * wave(u, v)) as u8, 120, (200.0 - 100.0 * wave(v, u)) as u8, 255]),
        texture("ground mr", 64, |u, v| [255, (30.0 + 200.0 * wave(u, v)) as u8, (255.0 * wave(v, u)) as u8, 255]),
        texture("ground normal", 64, |u, v| {
            let (dx, dy) = (0.3 * (u * std::f32::consts::TAU).cos(), 0.3 * (v * std::f32::consts::TAU).sin());
            let n = Vec3::new(dx, dy, 1.0).normalize();
            [((n.x * 0.5 + 0.5) * 255.0) as u8, ((n.y * 0.5 + 0.5) * 255.0) as u8, ((n.z * 0.5 + 0.5) * 255.0) as u8, 255]
        }),
        texture("ground occlusion", 64, |u, v| [(100.0 + 155.0 * wave(u, v)) as u8, 0, 0, 255]),
        // 4..: constant tiles
        constant("mr", MR_TEXEL),
        constant("occlusion", [OCCLUSION_RED, 0, 0, 255]),
        constant("emissive", EMISSIVE_TEXEL),
        constant("normal +u", tilted(0)),
        constant("normal +y", tilted(1)),
    ];
    let mut ground = Material::diffuse("ground", [1.0, 1.0, 1.0, 1.0], Some(0));
    ground.metallic = 1.0;
    ground.roughness = 1.0;
    ground.metallic_roughness_texture = Some(1);
    ground.normal_texture = Some(2);
    ground.occlusion_texture = Some(3);
    let mut mr = Material::diffuse("mr tile", [0.5, 0.5, 0.5, 1.0], None);
    (mr.metallic, mr.roughness, mr.metallic_roughness_texture, mr.occlusion_texture, mr.occlusion_strength) = (0.8, 0.9, Some(4), Some(5), 0.5);
    let mut glow = Material::diffuse("emissive tile", [0.2, 0.2, 0.2, 1.0], None);
    (glow.emissive, glow.emissive_texture) = ([2.0, 1.0, 0.5], Some(6));
    let mut bump_u = Material::diffuse("normal +u tile", [0.6, 0.6, 0.6, 1.0], None);
    bump_u.normal_texture = Some(7);
    let mut bump_v = bump_u.clone();
    bump_v.normal_texture = Some(8);
    bump_v.normal_scale = 0.5;
    let mut card = Material::diffuse("double-sided card", [0.9, 0.8, 0.1, 1.0], Some(0));
    card.double_sided = true;
    card.normal_texture = Some(2);
    let single = Material::diffuse("single-sided card", [0.1, 0.9, 0.1, 1.0], None);
    let ball = ground.clone();
    let tile = |x: f32, z: f32| Mat4::from_translation(Vec3::new(x, 0.01, z));
    // A quad standing up facing -z (its front away from the camera at +z).
    let card_at = |x: f32| Mat4::from_translation(Vec3::new(x, 0.7, -2.5)) * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let parts: Vec<(Mesh, Material, Mat4)> = vec![
        (plane("ground", 40.0, 8.0), ground, Mat4::IDENTITY),
        (plane("tile", 1.2, 1.0), mr, tile(-1.5, 0.8)),
        (plane("tile", 1.2, 1.0), glow, tile(0.0, 0.8)),
        (plane("tile", 1.2, 1.0), bump_u, tile(1.5, 0.8)),
        (plane("tile", 1.2, 1.0), bump_v, tile(3.0, 0.8)),
        (sphere("ball", 16, 32), ball, Mat4::from_scale_rotation_translation(Vec3::splat(0.6), Quat::IDENTITY, Vec3::new(-0.5, 0.6, -1.0))),
        // Mirrored (negative determinant): its faces keep their object-space front.
        (
            cube("box"),
            Material::diffuse("box", [0.3, 0.4, 0.9, 1.0], Some(0)),
            Mat4::from_scale_rotation_translation(Vec3::new(-0.8, 0.8, 0.8), Quat::from_rotation_y(0.5), Vec3::new(2.2, 0.4, -1.2)),
        ),
        (plane("card", 1.0, 1.0), card, card_at(-2.0)),
        (plane("card", 1.0, 1.0), single, card_at(-3.2)),
    ];
    let camera = Camera::look(Vec3::new(0.5, 2.6, 4.5), Vec3::new(0.3, 0.2, -0.5), 60.0, 0.05, 200.0);
    let mut scene = Scene::new("metallic-roughness", camera);
    *scene.textures_mut() = textures;
    scene.presets_mut().push(("test".into(), camera));
    *scene.light_mut() = Light { direction: Vec3::new(-0.4, 0.8, 0.45).normalize(), color: Vec3::ONE, intensity: 3.0, ambient: 0.3 };
    super::add_parts(&mut scene, parts);
    let probes = vec![
        ("mr", Vec3::new(-1.5, 0.01, 0.8)),
        ("emissive", Vec3::new(0.0, 0.01, 0.8)),
        ("normal +u", Vec3::new(1.5, 0.01, 0.8)),
        ("normal +y", Vec3::new(3.0, 0.01, 0.8)),
    ];
    (scene, probes)
}
