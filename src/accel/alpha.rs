//! Alpha-tested geometry for the ray tracers: which instances run the test, the data the trace
//! module's `trace_alpha_visible` reads (`accel_alpha`, see `shaders/trace/alpha.wgsl`), and
//! the same test on the CPU for [`crate::accel::cpu_traverse`] and [`crate::accel::reference`].
//!
//! A material is alpha-tested when its alpha mode is MASK (its cutoff) or BLEND (a cutout at
//! 0.5). A hit is kept when `base_color.a` x the base texture's alpha, read at mip level 0 with
//! bilinear filtering and repeat wrapping at the interpolated TEXCOORD_0, is at least the
//! cutoff. The CPU reads the file's own texels: that is what the GPU reads when textures are a
//! binding array; the texture-array fallback resamples every texture to 256x256 first, which
//! moves alpha edges by at most a fraction of a source texel.

use crate::scene::{AlphaMode, Scene, TextureImage};

/// Record word of an instance that is not alpha-tested (`TRACE_ALPHA_OPAQUE`).
pub const ALPHA_OPAQUE: u32 = u32::MAX;

/// The cutoff of an alpha-tested material, `None` for an opaque one.
pub fn cutoff(mode: AlphaMode) -> Option<f32> {
    match mode {
        AlphaMode::Opaque => None,
        AlphaMode::Mask(c) => Some(c),
        AlphaMode::Blend => Some(0.5),
    }
}

/// Whether scene instance `i` runs the alpha test (its material is alpha-tested).
pub fn instance_tested(scene: &Scene, i: usize) -> bool {
    scene.instances.get(i).and_then(|inst| scene.materials.get(inst.material)).is_some_and(|m| cutoff(m.alpha_mode).is_some())
}

/// Per mesh, whether an alpha-tested instance uses it (a mesh used by both kinds counts as
/// alpha-tested: the driver back-ends build it non-opaque).
pub fn tested_meshes(scene: &Scene) -> Vec<bool> {
    let mut out = vec![false; scene.meshes.len()];
    for (i, inst) in scene.instances.iter().enumerate() {
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
/// A scene without alpha-tested instances is one opaque record (never read).
pub fn gpu_words(scene: &Scene) -> Vec<[u32; 4]> {
    let tested: Vec<bool> = (0..scene.instances.len()).map(|i| instance_tested(scene, i)).collect();
    if !tested.iter().any(|&t| t) {
        return vec![[ALPHA_OPAQUE; 4]];
    }
    let mut words = vec![[ALPHA_OPAQUE; 4]; scene.instances.len()];
    let mut uv_base: Vec<Option<u32>> = vec![None; scene.meshes.len()];
    for (i, inst) in scene.instances.iter().enumerate() {
        let (true, Some(mesh), Some(m)) = (tested[i], scene.meshes.get(inst.mesh), scene.materials.get(inst.material)) else { continue };
        let base = match uv_base[inst.mesh] {
            Some(b) => b,
            None => {
                let b = words.len() as u32;
                for tri in mesh.indices.chunks_exact(3) {
                    let uv = |k: u32| mesh.vertices.get(k as usize).map_or([0.0; 2], |v| v.uv).map(f32::to_bits);
                    let (a, b, c) = (uv(tri[0]), uv(tri[1]), uv(tri[2]));
                    words.push([a[0], a[1], b[0], b[1]]);
                    words.push([c[0], c[1], 0, 0]);
                }
                uv_base[inst.mesh] = Some(b);
                b
            }
        };
        let layer = m.texture.map_or(0, |t| t as u32 + 1);
        words[i] = [base, layer, m.base_color[3].to_bits(), cutoff(m.alpha_mode).unwrap_or(0.0).to_bits()];
    }
    words
}

/// Level-0 bilinear alpha of `img` at `uv`, repeat wrap: `scene_alpha_level0` in
/// `shaders/common/alpha_read.wgsl`, in f64. A malformed image reads as opaque (the GPU's
/// fallback texture is).
pub fn bilinear_alpha(img: &TextureImage, uv: [f64; 2]) -> f64 {
    let (w, h) = (img.width as usize, img.height as usize);
    if w == 0 || h == 0 || img.rgba.len() < w * h * 4 {
        return 1.0;
    }
    let texel = |x: usize, y: usize| img.rgba[(y * w + x) * 4 + 3] as f64 / 255.0;
    let axis = |c: f64, n: usize| {
        let x = c * n as f64 - 0.5;
        let f = x.floor();
        let i0 = (f.rem_euclid(n as f64) as usize).min(n - 1);
        (i0, (i0 + 1) % n, x - f)
    };
    let (x0, x1, wx) = axis(uv[0], w);
    let (y0, y1, wy) = axis(uv[1], h);
    let top = texel(x0, y0) + (texel(x1, y0) - texel(x0, y0)) * wx;
    let bottom = texel(x0, y1) + (texel(x1, y1) - texel(x0, y1)) * wx;
    top + (bottom - top) * wy
}

/// Whether a hit on triangle `prim` of scene instance `instance` at barycentrics `bary` (of
/// vertices 1 and 2) is kept: true for instances that are not alpha-tested.
pub fn visible(scene: &Scene, instance: usize, prim: usize, bary: [f64; 2]) -> bool {
    excess(scene, instance, prim, bary).is_none_or(|e| e >= 0.0)
}

/// `base_color.a` x texture alpha minus the cutoff at such a hit (kept when >= 0), `None` where
/// the instance is not alpha-tested.
pub fn excess(scene: &Scene, instance: usize, prim: usize, bary: [f64; 2]) -> Option<f64> {
    let inst = scene.instances.get(instance)?;
    let m = scene.materials.get(inst.material)?;
    let cutoff = cutoff(m.alpha_mode)?;
    let mesh = scene.meshes.get(inst.mesh)?;
    let uv = |k: usize| mesh.indices.get(3 * prim + k).and_then(|&i| mesh.vertices.get(i as usize)).map_or([0.0; 2], |v| v.uv.map(f64::from));
    let w = [1.0 - bary[0] - bary[1], bary[0], bary[1]];
    let (a, b, c) = (uv(0), uv(1), uv(2));
    let p = [0, 1].map(|k| a[k] * w[0] + b[k] * w[1] + c[k] * w[2]);
    let tex = m.texture.and_then(|t| scene.textures.get(t)).map_or(1.0, |img| bilinear_alpha(img, p));
    Some(m.base_color[3] as f64 * tex - cutoff as f64)
}
