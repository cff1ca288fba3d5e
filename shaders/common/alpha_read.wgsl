// The alpha test's texture read (docs/ARCHITECTURE.md, "Alpha-tested geometry"), shared by the
// raster side (common/raster_alpha_test.wgsl) and the trace side (trace/alpha.wgsl): the alpha
// channel of a scene texture at mip level 0, bilinear, wrapped per axis as the base colour
// slot's sampler wraps (`wrap`: bits 0-1 S, 2-3 T; 0 repeat, 1 clamp to edge, 2 mirrored
// repeat), read texel by texel (textureLoad: no sampler, and the CPU references in
// src/accel/alpha.rs do the same arithmetic). A texel is kept when base_color.a x that alpha >=
// the cutoff.
//#include "common/scene_textures_texels.wgsl"

// Texel index `f` (a whole number) of an axis `n` texels long, wrapped by `mode`.
fn alpha_texel_index(f: f32, n: f32, mode: u32) -> u32 {
    var k = f;
    if mode == 1u {
        k = clamp(f, 0.0, n - 1.0);
    } else if mode == 2u {
        // Period 2n, the second half mirrored.
        k = f - 2.0 * n * floor(f / (2.0 * n));
        if k >= n {
            k = 2.0 * n - 1.0 - k;
        }
    } else {
        // f modulo the size (floor-based).
        k = f - n * floor(f / n);
    }
    // Clamped against rounding at the ends.
    return min(u32(max(k, 0.0)), u32(n) - 1u);
}

// Level-0 bilinear alpha of `layer` at `uv`, wrapped by `wrap`.
fn scene_alpha_level0(layer: u32, uv: vec2<f32>, wrap: u32) -> f32 {
    return scene_bilinear_level0(layer, uv, wrap).a;
}

// Level-0 bilinear texel of `layer` at `uv`, wrapped by `wrap`.
fn scene_bilinear_level0(layer: u32, uv: vec2<f32>, wrap: u32) -> vec4<f32> {
    let size = scene_texture_size0(layer);
    let sizef = vec2<f32>(size);
    let x = uv * sizef - 0.5;
    let f = floor(x);
    let w = x - f;
    var i0: vec2<u32>;
    var i1: vec2<u32>;
    if wrap == 0u {
        // Repeat on both axes (glTF's default): f modulo the size, clamped against rounding at
        // the top end; the next texel wraps to 0.
        let wrapped = f - sizef * floor(f / sizef);
        i0 = min(vec2<u32>(max(wrapped, vec2<f32>(0.0))), size - 1u);
        i1 = select(i0 + 1u, vec2<u32>(0u), i0 + 1u >= size);
    } else {
        i0 = vec2<u32>(alpha_texel_index(f.x, sizef.x, wrap & 3u), alpha_texel_index(f.y, sizef.y, (wrap >> 2u) & 3u));
        i1 = vec2<u32>(alpha_texel_index(f.x + 1.0, sizef.x, wrap & 3u), alpha_texel_index(f.y + 1.0, sizef.y, (wrap >> 2u) & 3u));
    }
    let a00 = scene_texel0(layer, vec2<u32>(i0.x, i0.y));
    let a10 = scene_texel0(layer, vec2<u32>(i1.x, i0.y));
    let a01 = scene_texel0(layer, vec2<u32>(i0.x, i1.y));
    let a11 = scene_texel0(layer, vec2<u32>(i1.x, i1.y));
    let top = a00 + (a10 - a00) * w.x;
    let bottom = a01 + (a11 - a01) * w.x;
    return top + (bottom - top) * w.y;
}

// Whether a texel of alpha `factor` x the texture's alpha at `uv` (wrapped by `wrap`) is kept.
fn alpha_kept(layer: u32, factor: f32, cutoff: f32, uv: vec2<f32>, wrap: u32) -> bool {
    return factor * scene_alpha_level0(layer, uv, wrap) >= cutoff;
}
