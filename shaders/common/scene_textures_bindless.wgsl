enable wgpu_binding_array;
// Scene textures as a binding array of 2D array textures (the textures of one size and
// encoding in one element, each with its own mip chain; common/scene_textures_texels_bindless.wgsl
// decodes a reference), used where the device has texture binding arrays with non-uniform
// indexing. Same interface as common/scene_textures.wgsl, which it replaces through an include
// substitution.
//#include "common/scene_textures_texels.wgsl"

fn sample_scene_texture(layer: u32, uv: vec2<f32>) -> vec4<f32> {
    return textureSample(scene_textures[scene_texture_element(layer)], linear_sampler, uv, scene_texture_layer(layer));
}

fn sample_scene_texture_level(layer: u32, uv: vec2<f32>, lod: f32) -> vec4<f32> {
    return textureSampleLevel(scene_textures[scene_texture_element(layer)], linear_sampler, uv, scene_texture_layer(layer), lod);
}

fn sample_scene_texture_grad(layer: u32, uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    return textureSampleGrad(scene_textures[scene_texture_element(layer)], linear_sampler, uv, scene_texture_layer(layer), dx, dy);
}

// The size in texels of mip `level` of a texture (clamped to its last level).
fn scene_texture_size_at(layer: u32, level: u32) -> vec2<u32> {
    let element = scene_texture_element(layer);
    return textureDimensions(scene_textures[element], min(level, textureNumLevels(scene_textures[element]) - 1u));
}

// log2 of the texture's side in texels (the geometric mean of width and height), for choosing a
// mip level from a footprint in uv units.
fn scene_texture_log2_size(layer: u32) -> f32 {
    let d = vec2<f32>(textureDimensions(scene_textures[scene_texture_element(layer)]));
    return 0.5 * log2(d.x * d.y);
}
