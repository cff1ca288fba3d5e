// A material's texture slots (common/scene.wgsl `Material`): their sampler bits and their
// KHR_texture_transform, read alike by the sampled reads (common/texture_sampling.wgsl) and
// the alpha test's texel reads (common/raster_alpha_test.wgsl). Each function takes the
// material's index and reads only the words it needs from `scene_materials` (a copy of the
// whole record would carry its ten transform rows along). Needs common/scene.wgsl included and
// `scene_materials` declared.

const SLOT_BASE: u32 = 0u;
const SLOT_METALLIC_ROUGHNESS: u32 = 1u;
const SLOT_NORMAL: u32 = 2u;
const SLOT_OCCLUSION: u32 = 3u;
const SLOT_EMISSIVE: u32 = 4u;
// The lobe extensions' slots (src/scene/mod.rs `Lobes::textures`).
const SLOT_SPECULAR: u32 = 5u;
const SLOT_SPECULAR_COLOR: u32 = 6u;
const SLOT_CLEARCOAT: u32 = 7u;
const SLOT_CLEARCOAT_ROUGHNESS: u32 = 8u;
const SLOT_CLEARCOAT_NORMAL: u32 = 9u;
const SLOT_TRANSMISSION: u32 = 10u;

// A slot's sampler bits (`SlotSampling::sampler_bits`, src/scene/mod.rs): bits 0-1 wrap S, 2-3 wrap T,
// 4 magnification NEAREST, 5 minification NEAREST, 6-7 the mipmap mode.
const WRAP_REPEAT: u32 = 0u;
const WRAP_CLAMP: u32 = 1u;
const WRAP_MIRROR: u32 = 2u;
const SAMPLER_MAG_NEAREST: u32 = 16u;
const SAMPLER_MIN_NEAREST: u32 = 32u;
const MIPMAP_LINEAR: u32 = 0u;
const MIPMAP_NEAREST: u32 = 1u;
const MIPMAP_NONE: u32 = 2u;

fn slot_sampler(m: u32, slot: u32) -> u32 {
    var word = scene_materials[m].samplers_low;
    if slot >= 8u {
        word = scene_materials[m].slot_words.z;
    } else if slot >= 4u {
        word = scene_materials[m].samplers_high;
    }
    return (word >> (8u * (slot % 4u))) & 0xffu;
}

// The texture coordinate set slot `slot` reads: 0 or 1.
fn slot_uv_set(m: u32, slot: u32) -> u32 {
    return select(0u, (scene_materials[m].slot_words.w >> slot) & 1u, SCENE_VERTEX_EXTRAS);
}

// The texture layer of lobe slot `slot` (SLOT_SPECULAR to SLOT_TRANSMISSION) of material `m`.
fn lobe_slot_layer(m: u32, slot: u32) -> u32 {
    if slot >= SLOT_CLEARCOAT_NORMAL {
        return scene_materials[m].slot_words[slot - SLOT_CLEARCOAT_NORMAL];
    }
    return scene_materials[m].lobe_layers[slot - SLOT_SPECULAR];
}

// Whether any slot of material `m` has a sampler other than glTF's default or a transform (one
// word read: the plain read needs nothing else).
fn material_sampling_custom(m: u32) -> bool {
    return SCENE_CUSTOM_SAMPLING && (scene_materials[m].flags & (MATERIAL_SAMPLERS | MATERIAL_UV_TRANSFORM)) != 0u;
}

fn slot_transformed(m: u32) -> bool {
    return SCENE_CUSTOM_SAMPLING && (scene_materials[m].flags & MATERIAL_UV_TRANSFORM) != 0u;
}

// The slot's uv through its KHR_texture_transform (unchanged without one).
fn slot_uv(m: u32, slot: u32, uv: vec2<f32>) -> vec2<f32> {
    if !slot_transformed(m) {
        return uv;
    }
    let h = vec3<f32>(uv, 1.0);
    return vec2<f32>(dot(scene_materials[m].uv_transforms[2u * slot].xyz, h), dot(scene_materials[m].uv_transforms[2u * slot + 1u].xyz, h));
}

// A uv differential through the transform's linear part.
fn slot_uv_delta(m: u32, slot: u32, d: vec2<f32>) -> vec2<f32> {
    if !slot_transformed(m) {
        return d;
    }
    return vec2<f32>(dot(scene_materials[m].uv_transforms[2u * slot].xy, d), dot(scene_materials[m].uv_transforms[2u * slot + 1u].xy, d));
}

// log2 of how much the transform scales a footprint's side (0 without one).
fn slot_footprint_log2(m: u32, slot: u32) -> f32 {
    if !slot_transformed(m) {
        return 0.0;
    }
    let a = scene_materials[m].uv_transforms[2u * slot].xy;
    let b = scene_materials[m].uv_transforms[2u * slot + 1u].xy;
    return 0.5 * log2(max(abs(a.x * b.y - a.y * b.x), 1e-30));
}
