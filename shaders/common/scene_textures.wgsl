// Scene textures as one `texture_2d_array<f32>` (every texture resampled to 256x256 with a
// mip chain): works on every adapter. `scene_textures` is declared by the included
// common/scene_textures_texels.wgsl; declare `var linear_sampler: sampler;`, then call
// `sample_scene_texture(layer, uv)`.
// Devices with texture binding arrays get common/scene_textures_bindless.wgsl instead.
//#include "common/scene_textures_texels.wgsl"

fn sample_scene_texture(layer: u32, uv: vec2<f32>) -> vec4<f32> {
    return textureSample(scene_textures, linear_sampler, uv, layer);
}

fn sample_scene_texture_level(layer: u32, uv: vec2<f32>, lod: f32) -> vec4<f32> {
    return textureSampleLevel(scene_textures, linear_sampler, uv, layer, lod);
}

fn sample_scene_texture_grad(layer: u32, uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    return textureSampleGrad(scene_textures, linear_sampler, uv, layer, dx, dy);
}

// The size in texels of mip `level` of a layer (clamped to the last level).
fn scene_texture_size_at(layer: u32, level: u32) -> vec2<u32> {
    return textureDimensions(scene_textures, min(level, textureNumLevels(scene_textures) - 1u));
}

// log2 of the texture's side in texels (the geometric mean of width and height), for choosing a
// mip level from a footprint in uv units.
fn scene_texture_log2_size(layer: u32) -> f32 {
    let d = vec2<f32>(textureDimensions(scene_textures));
    return 0.5 * log2(d.x * d.y);
}
