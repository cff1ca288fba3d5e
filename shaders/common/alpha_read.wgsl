// The alpha test's texture read (docs/ARCHITECTURE.md, "Alpha-tested geometry"), shared by the
// raster side (common/alpha.wgsl) and the trace side (trace/alpha.wgsl): the alpha channel of
// a scene texture at mip level 0, bilinear, repeat wrap, read texel by texel (textureLoad: no
// sampler, and the CPU references in src/accel/alpha.rs do the same arithmetic). A texel is
// kept when base_color.a x that alpha >= the cutoff.
//#include "common/scene_textures_texels.wgsl"

// Level-0 bilinear alpha of `layer` at `uv`, repeat wrap.
fn scene_alpha_level0(layer: u32, uv: vec2<f32>) -> f32 {
    let size = scene_texture_size0(layer);
    let sizef = vec2<f32>(size);
    let x = uv * sizef - 0.5;
    let f = floor(x);
    let w = x - f;
    // f modulo the size (floor-based), clamped against rounding at the top end.
    let wrapped = f - sizef * floor(f / sizef);
    let i0 = min(vec2<u32>(max(wrapped, vec2<f32>(0.0))), size - 1u);
    let i1 = select(i0 + 1u, vec2<u32>(0u), i0 + 1u >= size);
    let a00 = scene_texel0(layer, vec2<u32>(i0.x, i0.y)).a;
    let a10 = scene_texel0(layer, vec2<u32>(i1.x, i0.y)).a;
    let a01 = scene_texel0(layer, vec2<u32>(i0.x, i1.y)).a;
    let a11 = scene_texel0(layer, vec2<u32>(i1.x, i1.y)).a;
    let top = a00 + (a10 - a00) * w.x;
    let bottom = a01 + (a11 - a01) * w.x;
    return top + (bottom - top) * w.y;
}

// Whether a texel of alpha `factor` x the texture's alpha at `uv` is kept.
fn alpha_kept(layer: u32, factor: f32, cutoff: f32, uv: vec2<f32>) -> bool {
    return factor * scene_alpha_level0(layer, uv) >= cutoff;
}
