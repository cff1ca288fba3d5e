//! Alpha-tested geometry for the ray tracers: which instances run the test, the data the trace
//! module's `trace_alpha_visible` reads (`accel_alpha`, see `shaders/trace/alpha.wgsl`), and
//! the same test on the CPU for [`crate::accel::cpu_traverse`] and [`crate::accel::reference`].
//!
//! A material is alpha-tested when its alpha mode is MASK (its cutoff) or BLEND (or it is
//! transmissive). Its alpha is `base_color.a` x the vertex colours' alpha (`COLOR_0`) x the
//! base texture's alpha. A BLEND
//! surface is translucent: the traversal keeps its hits wherever its coverage is at least
//! `crate::scene::BLEND_MIN_COVERAGE` (a texel below it is empty), and the passes composite it
//! (`shaders/common/ray_blend.wgsl`: skipped by primary rays, attenuating shadow and AO rays by one
//! minus its coverage, composited front to back over the opaque surface behind it). A hit is kept when `base_color.a` x the base texture's alpha, read at mip level 0 with
//! bilinear filtering and the base colour slot's wrap modes at the interpolated TEXCOORD_0
//! through that slot's uv transform, is at least the cutoff. The CPU reads the file's own
//! texels: that is what the GPU reads when textures are a
//! binding array; the texture-array fallback resamples every texture to 256x256 first, which
//! moves alpha edges by at most a fraction of a source texel.

use crate::scene::texture_pool::texture_ref;
use crate::scene::{Material, Scene, SlotSampling, TextureImage, Wrap, LOBE_TRANSMISSION};

/// Record word of an instance that is not alpha-tested (`TRACE_ALPHA_OPAQUE`).
pub const ALPHA_OPAQUE: u32 = u32::MAX;

/// Bit of a record's second word that marks a BLEND instance (`TRACE_ALPHA_BLEND`).
pub(crate) const ALPHA_BLEND_BIT: u32 = 1 << 28;

/// Bit of a record's second word that marks an instance whose transmission texture is drawn
/// (`TRACE_ALPHA_TRANSMISSION`): its fourth word is then the index of a word holding the
/// texture's layer and wrap bits, the transmitted share and the cutoff.
pub(crate) const ALPHA_TRANSMISSION_BIT: u32 = 1 << 29;

/// The cutoff of an alpha-tested material, `None` for an opaque one
/// (`Material::alpha_cutoff`).
pub fn cutoff(m: &Material) -> Option<f32> {
    m.alpha_cutoff()
}

/// Whether scene instance `i` runs the alpha test (its material is alpha-tested).
pub(crate) fn instance_tested(scene: &Scene, i: usize) -> bool {
    scene.instances().get(i).and_then(|inst| scene.materials().get(inst.material)).is_some_and(|m| cutoff(m).is_some())
}

/// Per mesh, whether an alpha-tested instance uses it (a mesh used by both kinds counts as
/// alpha-tested: the driver back-ends build it non-opaque).
pub fn tested_meshes(scene: &Scene) -> Vec<bool> {
    let mut out = vec![false; scene.meshes().len()];
    for (i, inst) in scene.instances().iter().enumerate() {
        if instance_tested(scene, i) {
            if let Some(m) = out.get_mut(inst.mesh) {
                *m = true;
            }
        }
    }
    out
}

/// The `accel_alpha` buffer's words (see `shaders/trace/alpha.wgsl`): one record per scene
/// instance, then the uvs of every mesh an alpha-tested instance uses, two words per triangle.
/// A scene without alpha-tested instances is one opaque record (never read). Textures are named
/// by `refs` (`crate::scene::texture_pool::texture_refs`: as the scene's textures are bound).
pub fn gpu_words(scene: &Scene, refs: &[u32]) -> Vec<[u32; 4]> {
    let tested: Vec<bool> = (0..scene.instances().len()).map(|i| instance_tested(scene, i)).collect();
    if !tested.iter().any(|&t| t) {
        return vec![[ALPHA_OPAQUE; 4]];
    }
    let mut words = vec![[ALPHA_OPAQUE; 4]; scene.instances().len()];
    // Per (mesh, the base slot's uv transform): where its uvs start.
    let mut uv_base: std::collections::HashMap<(usize, Option<[u32; 6]>), u32> = Default::default();
    for (i, inst) in scene.instances().iter().enumerate() {
        let (true, Some(mesh), Some(m)) = (tested[i], scene.meshes().get(inst.mesh), scene.materials().get(inst.material)) else { continue };
        let sampling = &m.sampling[0];
        let key = (inst.mesh, sampling.transform.map(|[a, b]| [a[0], a[1], a[2], b[0], b[1], b[2]].map(f32::to_bits)));
        let base = *uv_base.entry(key).or_insert_with(|| {
            let b = words.len() as u32;
            for tri in mesh.indices.chunks_exact(3) {
                let uv = |k: u32| sampling.apply(mesh.vertices.get(k as usize).map_or([0.0; 2], |v| v.uv)).map(f32::to_bits);
                let (a, b, c) = (uv(tri[0]), uv(tri[1]), uv(tri[2]));
                let alphas = tri.iter().enumerate().map(|(k, &i)| vertex_alpha_byte(mesh, i) << (8 * k)).sum::<u32>();
                words.push([a[0], a[1], b[0], b[1]]);
                words.push([c[0], c[1], alphas, 0]);
            }
            b
        });
        let layer = texture_ref(refs, m.texture);
        let wrap = sampling.wrap_bits();
        let (blend, factor) = if m.translucent() { (ALPHA_BLEND_BIT, m.coverage_factor()) } else { (0, m.base_color[3]) };
        let cutoff = cutoff(m).unwrap_or(0.0).to_bits();
        words[i] = [base, layer | wrap << 24 | blend, factor.to_bits(), cutoff];
        if let (true, Some(t)) = (m.transmission_texture_drawn(), m.lobes.textures[LOBE_TRANSMISSION]) {
            let transmission = [texture_ref(refs, Some(t)) | m.sampling[5 + LOBE_TRANSMISSION].wrap_bits() << 24, m.transmitted_share().to_bits(), cutoff, 0];
            words[i][1] |= ALPHA_TRANSMISSION_BIT;
            words[i][3] = words.len() as u32;
            words.push(transmission);
        }
    }
    words
}

/// The alpha of vertex `i`'s colour (`COLOR_0`; 1 without one) as the records hold it: 8-bit
/// unorm (three to a word, `trace_alpha_corners` in `shaders/trace/alpha.wgsl`).
fn vertex_alpha_byte(mesh: &crate::scene::Mesh, i: u32) -> u32 {
    mesh.extras.as_ref().and_then(|e| e.get(i as usize)).map_or(255, |x| (x.color[3].clamp(0.0, 1.0) * 255.0).round() as u32)
}

/// Level-0 bilinear alpha of `img` at `uv`, wrapped per axis as `sampling` wraps:
/// `scene_alpha_level0` in `shaders/common/alpha_read.wgsl`, in f64. A malformed image reads as
/// opaque (the GPU's fallback texture is).
pub fn bilinear_alpha(img: &TextureImage, uv: [f64; 2], sampling: &SlotSampling) -> f64 {
    bilinear_channel(img, uv, sampling, 3)
}

/// [`bilinear_alpha`] of channel `channel` (0 red to 3 alpha; a data texture, read as stored).
pub(crate) fn bilinear_channel(img: &TextureImage, uv: [f64; 2], sampling: &SlotSampling, channel: usize) -> f64 {
    let (w, h) = (img.width as usize, img.height as usize);
    if w == 0 || h == 0 || img.rgba.len() < w * h * 4 {
        return 1.0;
    }
    let texel = |x: usize, y: usize| img.rgba[(y * w + x) * 4 + channel] as f64 / 255.0;
    let axis = |c: f64, n: usize, wrap: Wrap| {
        let x = c * n as f64 - 0.5;
        let f = x.floor();
        (wrap.texel_index(f, n), wrap.texel_index(f + 1.0, n), x - f)
    };
    let (x0, x1, wx) = axis(uv[0], w, sampling.wrap_s);
    let (y0, y1, wy) = axis(uv[1], h, sampling.wrap_t);
    let top = texel(x0, y0) + (texel(x1, y0) - texel(x0, y0)) * wx;
    let bottom = texel(x0, y1) + (texel(x1, y1) - texel(x0, y1)) * wx;
    top + (bottom - top) * wy
}

/// Whether a hit on triangle `prim` of scene instance `instance` at barycentrics `bary` (of
/// vertices 1 and 2) is kept: true for instances that are not alpha-tested.
pub fn visible(scene: &Scene, instance: usize, prim: usize, bary: [f64; 2]) -> bool {
    excess(scene, instance, prim, bary).is_none_or(|e| e >= 0.0)
}

/// The coverage of a translucent surface at such a hit (`Material::coverage_factor` x texture
/// alpha, times 1 - the transmitted share x the transmission texel where that texture is
/// drawn), `None` where the instance's material is not translucent: `trace_blend_coverage` in
/// `shaders/trace/alpha.wgsl`.
pub fn blend_coverage(scene: &Scene, instance: usize, prim: usize, bary: [f64; 2]) -> Option<f64> {
    let inst = scene.instances().get(instance)?;
    let m = scene.materials().get(inst.material)?;
    if !m.translucent() {
        return None;
    }
    let coverage = excess(scene, instance, prim, bary)? + cutoff(m).unwrap_or(0.0) as f64;
    let texture = m.lobes.textures[LOBE_TRANSMISSION].and_then(|t| scene.textures().get(t)).filter(|_| m.transmission_texture_drawn());
    let Some((img, mesh)) = texture.zip(scene.meshes().get(inst.mesh)) else { return Some(coverage) };
    let uv = hit_uv(mesh, prim, bary, &m.sampling[0]);
    Some(coverage * (1.0 - m.transmitted_share() as f64 * bilinear_channel(img, uv, &m.sampling[5 + LOBE_TRANSMISSION], 0)))
}

/// The uv of a hit on triangle `prim` of `mesh` at barycentrics `bary` through `sampling`'s
/// transform, the vertices' in f32 as the GPU's records hold them.
fn hit_uv(mesh: &crate::scene::Mesh, prim: usize, bary: [f64; 2], sampling: &SlotSampling) -> [f64; 2] {
    let uv = |k: usize| mesh.indices.get(3 * prim + k).and_then(|&i| mesh.vertices.get(i as usize)).map_or([0.0; 2], |v| sampling.apply(v.uv).map(f64::from));
    let w = [1.0 - bary[0] - bary[1], bary[0], bary[1]];
    let (a, b, c) = (uv(0), uv(1), uv(2));
    [0, 1].map(|k| a[k] * w[0] + b[k] * w[1] + c[k] * w[2])
}

/// `base_color.a` x texture alpha minus the cutoff at such a hit (kept when >= 0), `None` where
/// the instance is not alpha-tested.
pub(crate) fn excess(scene: &Scene, instance: usize, prim: usize, bary: [f64; 2]) -> Option<f64> {
    let inst = scene.instances().get(instance)?;
    let m = scene.materials().get(inst.material)?;
    let cutoff = cutoff(m)?;
    let mesh = scene.meshes().get(inst.mesh)?;
    let sampling = &m.sampling[0];
    let w = [1.0 - bary[0] - bary[1], bary[0], bary[1]];
    let p = hit_uv(mesh, prim, bary, sampling);
    let tex = m.texture.and_then(|t| scene.textures().get(t)).map_or(1.0, |img| bilinear_alpha(img, p, sampling));
    let factor = if m.translucent() { m.coverage_factor() } else { m.base_color[3] };
    // The vertex colours' alpha (COLOR_0), interpolated from the records' 8-bit copies.
    let corner = |k: usize| mesh.indices.get(3 * prim + k).map_or(1.0, |&i| vertex_alpha_byte(mesh, i) as f64 / 255.0);
    let vertex = corner(0) * w[0] + corner(1) * w[1] + corner(2) * w[2];
    Some(factor as f64 * vertex * tex - cutoff as f64)
}
