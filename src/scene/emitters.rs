//! The emissive triangles of a scene as lights: a table the path tracer samples them from in
//! proportion to their power (`scene_emitters`, `shaders/common/emitters.wgsl`). A triangle's
//! power is its world-space area times the luminance of its material's emission (the emissive
//! factor times the mean of its emissive texture, decoded from sRGB). Every triangle of an
//! instance whose material emits gets a record, in primitive order, so a shader finds a hit's
//! record from the instance's first one; triangles that emit nothing keep a probability of 0.
//!
//! Layout, in 32-bit words: `[emitter count, instance count]`, then per instance its first
//! record ([`NO_EMITTERS`] where its material does not emit), then per record `[instance,
//! primitive, cumulative probability (f32 bits), probability (f32 bits)]`.

use super::{Scene, TextureImage};

/// An instance without emitting triangles.
pub const NO_EMITTERS: u32 = u32::MAX;
/// Words per record.
pub const EMITTER_WORDS: usize = 4;

/// The mean linear RGB of an sRGB image (`lut`: each 8-bit value decoded).
fn mean_linear(image: &TextureImage, lut: &[f64]) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    for texel in image.rgba.chunks_exact(4) {
        for c in 0..3 {
            sum[c] += lut[texel[c] as usize];
        }
    }
    let n = (image.rgba.len() / 4).max(1) as f64;
    sum.map(|s| (s / n) as f32)
}

/// The mean emitted radiance's luminance of every material (0 for those that emit nothing).
fn material_emission(scene: &Scene) -> Vec<f32> {
    let mut texture_means: Vec<Option<[f32; 3]>> = vec![None; scene.textures().len()];
    let lut: Vec<f64> = (0..=255u8).map(|c| crate::util::srgb_to_linear(c) as f64).collect();
    scene
        .materials()
        .iter()
        .map(|m| {
            // An unlit surface shows its base colour only: it lights nothing.
            if m.unlit {
                return 0.0;
            }
            let mut e = m.emissive;
            if let Some(t) = m.emissive_texture.filter(|&t| t < scene.textures().len()) {
                let mean = *texture_means[t].get_or_insert_with(|| mean_linear(&scene.textures()[t], &lut));
                e = [e[0] * mean[0], e[1] * mean[1], e[2] * mean[2]];
            }
            crate::util::luminance(e).max(0.0)
        })
        .collect()
}

/// The table of `scene`'s emitting triangles (layout in the module's doc).
pub fn emitter_table(scene: &Scene) -> Vec<u32> {
    let emission = material_emission(scene);
    let instances = scene.instances();
    let mut first = vec![NO_EMITTERS; instances.len()];
    // (instance, primitive, power)
    let mut records: Vec<(u32, u32, f64)> = Vec::new();
    for (i, inst) in instances.iter().enumerate() {
        let e = emission.get(inst.material).copied().unwrap_or(0.0);
        let Some(mesh) = scene.meshes().get(inst.mesh).filter(|_| e > 0.0 && e.is_finite()) else { continue };
        first[i] = records.len() as u32;
        let p = |v: u32| inst.transform.transform_point3(glam::Vec3::from(mesh.vertices.get(v as usize).map_or([0.0; 3], |v| v.position)));
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            let area = 0.5 * (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0])).length();
            let power = if area.is_finite() { (area * e) as f64 } else { 0.0 };
            records.push((i as u32, t as u32, power));
        }
    }
    let total: f64 = records.iter().map(|r| r.2).sum();
    let mut words = vec![records.len() as u32, instances.len() as u32];
    words.extend(&first);
    let mut cumulative = 0.0f64;
    for (instance, primitive, power) in records {
        let probability = if total > 0.0 { power / total } else { 0.0 };
        cumulative += probability;
        words.extend([instance, primitive, (cumulative as f32).to_bits(), (probability as f32).to_bits()]);
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin::{cube, default_scene};
    use crate::scene::{Instance, Material};
    use glam::{Mat4, Vec3};

    #[test]
    fn triangles_are_picked_in_proportion_to_area_times_emission() {
        let mut s = default_scene();
        s.set_meshes(vec![cube("a")]);
        *s.textures_mut() = Vec::new();
        let mut bright = Material::diffuse("bright", [1.0; 4], None);
        bright.emissive = [2.0; 3];
        let mut dim = bright.clone();
        dim.emissive = [1.0; 3];
        *s.materials_mut() = vec![Material::diffuse("dark", [1.0; 4], None), bright, dim];
        // A dark cube, a bright one, and a dim one twice as large (four times the area).
        *s.instances_mut() = vec![
            Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY },
            Instance { mesh: 0, material: 1, transform: Mat4::IDENTITY },
            Instance { mesh: 0, material: 2, transform: Mat4::from_scale(Vec3::splat(2.0)) },
        ];
        let words = emitter_table(&s);
        assert_eq!(&words[..5], &[24, 3, NO_EMITTERS, 0, 12]);
        let record = |i: usize| &words[5 + EMITTER_WORDS * i..5 + EMITTER_WORDS * (i + 1)];
        let probability = |i: usize| f32::from_bits(record(i)[3]);
        // Power 2 x area against 1 x 4 area: the dim cube's triangles are twice as likely.
        assert!((probability(0) - 1.0 / 36.0).abs() < 1e-6 && (probability(12) - 2.0 / 36.0).abs() < 1e-6);
        assert_eq!((record(13)[0], record(13)[1]), (2, 1));
        assert!((f32::from_bits(record(23)[2]) - 1.0).abs() < 1e-5, "the cumulative probability ends at 1");
    }
}
