// How a material's texture slots are sampled: each slot's glTF sampler (wrap modes per axis,
// NEAREST or LINEAR magnification and minification, the mipmap mode) and its
// KHR_texture_transform, the same in the fragment stage (explicit gradients,
// `sample_material_grad`) and at ray hits (the ray cone's level, `sample_material_level`).
// Slots whose sampler is glTF's default (REPEAT, LINEAR, LINEAR_MIPMAP_LINEAR) and without a
// transform take the plain hardware sample (the same fetch as before either existed).
// Wrap modes other than REPEAT are applied to the coordinates before the scene's one repeating
// linear sampler reads them: CLAMP_TO_EDGE clamps (and MIRRORED_REPEAT folds, then clamps) the
// coordinate to the centres of the edge texels of the level read, so bilinear filtering never
// reaches across the edge; NEAREST snaps the coordinate to the centre of its texel of that level.
// Needs common/scene.wgsl and common/scene_textures.wgsl (or its bindless substitute) included;
// the slot constants, sampler bits and transforms are in common/texture_slots.wgsl.

//#include "common/texture_slots.wgsl"

// One coordinate wrapped by `mode` for a level `texels` wide (REPEAT is left to the sampler).
fn wrap_coordinate(u: f32, mode: u32, texels: f32) -> f32 {
    let half = 0.5 / texels;
    if mode == WRAP_CLAMP {
        return clamp(u, half, 1.0 - half);
    }
    if mode == WRAP_MIRROR {
        let t = u - 2.0 * floor(u * 0.5);
        return clamp(select(t, 2.0 - t, t > 1.0), half, 1.0 - half);
    }
    return u;
}

// Where and at which level sampler bits `bits` read texture `layer` at `uv` (transformed
// already) for a footprint of mip level `lod` (unclamped: below 0 magnifies): xy the
// coordinate, z the level.
fn sampler_read(layer: u32, uv: vec2<f32>, lod: f32, bits: u32) -> vec3<f32> {
    var level = max(lod, 0.0);
    let mipmap = (bits >> 6u) & 3u;
    if mipmap == MIPMAP_NONE {
        level = 0.0;
    } else if mipmap == MIPMAP_NEAREST {
        level = round(level);
    }
    let size = vec2<f32>(scene_texture_size_at(layer, u32(level)));
    var st = vec2<f32>(wrap_coordinate(uv.x, bits & 3u, size.x), wrap_coordinate(uv.y, (bits >> 2u) & 3u, size.y));
    let nearest = select((bits & SAMPLER_MAG_NEAREST) != 0u, (bits & SAMPLER_MIN_NEAREST) != 0u, lod > 0.0);
    if nearest {
        st = (floor(st * size) + 0.5) / size;
    }
    return vec3<f32>(st, level);
}

// Slot `slot` of material `m` (an index of `scene_materials`; its texture `layer`) at `uv` in the fragment stage, with the
// uv's screen-space gradients `dx`, `dy` (taken in uniform control flow by the caller).
fn sample_material_grad(m: u32, slot: u32, layer: u32, uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    if !material_sampling_custom(m) {
        return sample_scene_texture_grad(layer, uv, dx, dy);
    }
    let bits = slot_sampler(m, slot);
    let size0 = vec2<f32>(scene_texture_size_at(layer, 0u));
    let tx = slot_uv_delta(m, slot, dx) * size0;
    let ty = slot_uv_delta(m, slot, dy) * size0;
    let lod = 0.5 * log2(max(max(dot(tx, tx), dot(ty, ty)), 1e-30));
    let read = sampler_read(layer, slot_uv(m, slot, uv), lod, bits);
    return sample_scene_texture_level(layer, read.xy, read.z);
}

// Slot `slot` of material `m` (an index of `scene_materials`; its texture `layer`) at `uv` at a ray hit whose footprint is
// 2^lod_uv in uv units (the ray cone's; -1e9: level 0).
// One texture read either way (small shaders compile faster, on software WebGPU above all).
fn sample_material_level(m: u32, slot: u32, layer: u32, uv: vec2<f32>, lod_uv: f32) -> vec4<f32> {
    var read = vec3<f32>(uv, max(lod_uv + scene_texture_log2_size(layer), 0.0));
    if material_sampling_custom(m) {
        let lod = lod_uv + slot_footprint_log2(m, slot) + scene_texture_log2_size(layer);
        read = sampler_read(layer, slot_uv(m, slot, uv), lod, slot_sampler(m, slot));
    }
    return sample_scene_texture_level(layer, read.xy, read.z);
}
