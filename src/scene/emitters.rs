//! The emissive triangles of a scene as lights: a table the path tracer and the shadow pass
//! sample them from in proportion to their power (`scene_emitters`,
//! `shaders/common/emitters.wgsl`). A triangle's emission is its material's emissive factor
//! times the mean of its emissive texture over the triangle's own texture coordinates (decoded
//! from sRGB; [`triangle_emission`]), its power that emission's luminance times its world-space
//! area. Every triangle of an instance whose material emits gets a record, in primitive order,
//! so a shader finds a hit's record from the instance's first one; triangles that emit nothing
//! keep a probability of 0.
//!
//! Layout, in 32-bit words: `[emitter count, instance count]`, then per instance its first
//! record ([`NO_EMITTERS`] where its material does not emit), then per record `[instance,
//! primitive, cumulative probability, probability, corners (3 x xyz), emission (rgb)]`, every
//! word after the second an f32's bits. The corners are in world space, in the order whose
//! counter-clockwise side is the side the object-space triangle is counter-clockwise from (a
//! mirroring transform swaps two), so that a shader needs neither the meshes nor the textures to
//! light a point with one (`rt/shadow.wgsl`). The table is written again when instances move
//! ([`emitter_table`] of the moved scene; the same size).

use super::{Material, Mesh, Scene, TextureImage};
use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;

/// An instance without emitting triangles.
pub const NO_EMITTERS: u32 = u32::MAX;
/// Words per record.
pub const EMITTER_WORDS: usize = 16;
/// The emissive texture's slot in [`Material::sampling`] (glTF's fifth).
const EMISSIVE_SLOT: usize = 4;
/// Texture reads per triangle for its mean emission: about one per texel it covers, within
/// these bounds.
const MIN_READS: usize = 4;
const MAX_READS: usize = 256;

/// One emitting triangle of an instance, before the probabilities.
struct EmitterRecord {
    instance: u32,
    primitive: u32,
    corners: [Vec3; 3],
    emission: [f32; 3],
    power: f64,
}

/// Point `k` of a sequence spread over a triangle (an R2 sequence through the square-root warp), as
/// barycentric weights of the corners.
fn spread_point(k: usize) -> [f32; 3] {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_3;
    let u = ((0.5 + A1 * k as f64) % 1.0, (0.5 + A2 * k as f64) % 1.0);
    let r = u.0.sqrt() as f32;
    let (b1, b2) = (r * (1.0 - u.1 as f32), r * u.1 as f32);
    [1.0 - b1 - b2, b1, b2]
}

/// The nearest texel of `image` at `uv`, wrapped by the slot's sampler, decoded by `lut`.
fn texel_linear(image: &TextureImage, uv: Vec2, material: &Material, lut: &[f32; 256]) -> [f32; 3] {
    let (w, h) = (image.width as usize, image.height as usize);
    if w == 0 || h == 0 || image.rgba.len() < w * h * 4 {
        return [1.0; 3];
    }
    let sampling = &material.sampling[EMISSIVE_SLOT];
    let x = sampling.wrap_s.texel_index((uv.x as f64 * w as f64).floor(), w);
    let y = sampling.wrap_t.texel_index((uv.y as f64 * h as f64).floor(), h);
    let texel = &image.rgba[(y * w + x) * 4..][..3];
    [lut[texel[0] as usize], lut[texel[1] as usize], lut[texel[2] as usize]]
}

/// The mean emission of triangle `tri` (vertex indices) of `mesh` with `material`: its factor
/// times the mean of the emissive texture over the triangle's texture coordinates (about one
/// read per texel covered, from [`MIN_READS`] to [`MAX_READS`]), or the factor alone.
pub fn triangle_emission(mesh: &Mesh, tri: [u32; 3], material: &Material, textures: &[TextureImage], lut: &[f32; 256]) -> [f32; 3] {
    let factor = material.emissive;
    let Some(image) = material.emissive_texture.and_then(|t| textures.get(t)) else { return factor };
    let sampling = &material.sampling[EMISSIVE_SLOT];
    let uv = |v: u32| -> Vec2 {
        let raw = match (sampling.tex_coord, mesh.extras.as_ref()) {
            (1, Some(extras)) => extras.get(v as usize).map_or([0.0; 2], |e| e.uv1),
            _ => mesh.vertices.get(v as usize).map_or([0.0; 2], |v| v.uv),
        };
        Vec2::from(sampling.apply(raw))
    };
    let corners = tri.map(uv);
    let texels = 0.5 * (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]).abs() * (image.width * image.height) as f32;
    let n = if texels.is_finite() { (texels.ceil() as usize).clamp(MIN_READS, MAX_READS) } else { MIN_READS };
    let mut sum = [0.0f32; 3];
    for k in 0..n {
        let w = spread_point(k);
        let at = corners[0] * w[0] + corners[1] * w[1] + corners[2] * w[2];
        let texel = texel_linear(image, at, material, lut);
        for c in 0..3 {
            sum[c] += texel[c];
        }
    }
    std::array::from_fn(|c| factor[c] * sum[c] / n as f32)
}

/// The emitting triangles of instance `index` (none where its material emits nothing).
fn instance_records(scene: &Scene, index: usize, lut: &[f32; 256]) -> Vec<EmitterRecord> {
    let inst = &scene.instances()[index];
    let (Some(material), Some(mesh)) = (scene.materials().get(inst.material), scene.meshes().get(inst.mesh)) else { return Vec::new() };
    // An unlit surface shows its base colour only: it lights nothing.
    if material.unlit || crate::util::luminance(material.emissive) <= 0.0 {
        return Vec::new();
    }
    let transform: Mat4 = inst.transform;
    let mirrored = transform.determinant() < 0.0;
    let world = |v: u32| transform.transform_point3(Vec3::from(mesh.vertices.get(v as usize).map_or([0.0; 3], |v| v.position)));
    mesh.indices
        .par_chunks_exact(3)
        .enumerate()
        .map(|(t, tri)| {
            let tri = [tri[0], tri[1], tri[2]];
            let mut corners = tri.map(world);
            if mirrored {
                corners.swap(1, 2);
            }
            let emission = triangle_emission(mesh, tri, material, scene.textures(), lut);
            let area = 0.5 * (corners[1] - corners[0]).cross(corners[2] - corners[0]).length();
            let e = crate::util::luminance(emission).max(0.0);
            let power = if area.is_finite() && e.is_finite() { (area * e) as f64 } else { 0.0 };
            EmitterRecord { instance: index as u32, primitive: t as u32, corners, emission, power }
        })
        .collect()
}

/// The table of `scene`'s emitting triangles (layout in the module's doc).
pub fn emitter_table(scene: &Scene) -> Vec<u32> {
    let lut: [f32; 256] = std::array::from_fn(|c| crate::util::srgb_to_linear(c as u8));
    let instances = scene.instances();
    let mut first = vec![NO_EMITTERS; instances.len()];
    let mut records: Vec<EmitterRecord> = Vec::new();
    for (i, slot) in first.iter_mut().enumerate() {
        let own = instance_records(scene, i, &lut);
        if !own.is_empty() {
            *slot = records.len() as u32;
            records.extend(own);
        }
    }
    let total: f64 = records.iter().map(|r| r.power).sum();
    let mut words = Vec::with_capacity(2 + first.len() + EMITTER_WORDS * records.len());
    words.extend([records.len() as u32, instances.len() as u32]);
    words.extend(&first);
    let mut cumulative = 0.0f64;
    for r in records {
        let probability = if total > 0.0 { r.power / total } else { 0.0 };
        cumulative += probability;
        words.extend([r.instance, r.primitive, (cumulative as f32).to_bits(), (probability as f32).to_bits()]);
        words.extend(r.corners.iter().flat_map(|c| c.to_array()).map(f32::to_bits));
        words.extend(r.emission.map(f32::to_bits));
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

    /// A mesh of two triangles side by side: the first's texture coordinates in the left half of
    /// the texture, the second's in the right half.
    fn two_triangles() -> crate::scene::Mesh {
        let v = |x: f32, z: f32, u: f32| crate::scene::Vertex { position: [x, 0.0, z], normal: [0.0, 1.0, 0.0], uv: [u, 0.5] };
        crate::scene::Mesh {
            name: "two".into(),
            vertices: vec![v(0.0, 0.0, 0.05), v(1.0, 0.0, 0.45), v(0.5, 1.0, 0.25), v(2.0, 0.0, 0.55), v(3.0, 0.0, 0.95), v(2.5, 1.0, 0.75)],
            indices: vec![0, 2, 1, 3, 5, 4],
            tangents: None,
            extras: None,
        }
    }

    #[test]
    fn a_triangle_emits_the_mean_of_its_own_part_of_the_texture() {
        let mut s = default_scene();
        s.set_meshes(vec![two_triangles()]);
        // 2 x 1 texels: white on the left, black on the right.
        let rgba = vec![255, 255, 255, 255, 0, 0, 0, 255];
        *s.textures_mut() = vec![TextureImage { name: "half".into(), width: 2, height: 1, rgba: std::sync::Arc::new(rgba) }];
        let mut m = Material::diffuse("lamp", [1.0; 4], None);
        m.emissive = [3.0, 2.0, 1.0];
        m.emissive_texture = Some(0);
        *s.materials_mut() = vec![m];
        *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }];
        let words = emitter_table(&s);
        let record = |i: usize| &words[3 + EMITTER_WORDS * i..3 + EMITTER_WORDS * (i + 1)];
        let emission = |i: usize| [13, 14, 15].map(|k| f32::from_bits(record(i)[k]));
        assert_eq!(emission(0), [3.0, 2.0, 1.0], "the white half: the factor");
        assert_eq!(emission(1), [0.0; 3], "the black half: nothing");
        assert_eq!((f32::from_bits(record(0)[3]), f32::from_bits(record(1)[3])), (1.0, 0.0), "all the power is the left triangle's");
    }

    #[test]
    fn corners_keep_the_emitting_side_under_a_mirroring_transform() {
        let mut s = default_scene();
        s.set_meshes(vec![two_triangles()]);
        *s.textures_mut() = Vec::new();
        let mut m = Material::diffuse("lamp", [1.0; 4], None);
        m.emissive = [1.0; 3];
        *s.materials_mut() = vec![m];
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 2.0, 1.0));
        *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 0, material: 0, transform: mirror }];
        let words = emitter_table(&s);
        let normal = |i: usize| {
            let c: Vec<Vec3> = (0..3).map(|k| Vec3::from_array([0, 1, 2].map(|j| f32::from_bits(words[4 + EMITTER_WORDS * i + 4 + 3 * k + j])))).collect();
            (c[1] - c[0]).cross(c[2] - c[0]).normalize()
        };
        // The object-space triangles are counter-clockwise seen from +y.
        let object = Vec3::Y;
        let mirrored = (mirror.inverse().transpose() * object.extend(0.0)).truncate().normalize();
        assert!(normal(0).abs_diff_eq(object, 1e-6), "identity: {}", normal(0));
        assert!(normal(2).abs_diff_eq(mirrored, 1e-6), "mirrored: {} against {mirrored}", normal(2));
    }
}
