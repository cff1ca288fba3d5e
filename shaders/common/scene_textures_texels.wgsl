// The scene's textures as one `texture_2d_array<f32>` (every texture resampled to 256x256 with
// a mip chain; works on every adapter): the `scene_textures` declaration (@group(1)
// @binding(0)) and level-0 texel reads, which need no sampler (the alpha test reads texels by
// hand, common/alpha_read.wgsl). Included by common/scene_textures.wgsl (the sampled reads),
// so a pass and the trace module's alpha test share the one declaration. Devices with texture
// binding arrays get common/scene_textures_texels_bindless.wgsl instead.
alias SceneTextures = texture_2d_array<f32>;

@group(1) @binding(0) var scene_textures: SceneTextures;

// Level 0 of a layer: its size in texels, and one texel.
fn scene_texture_size0(layer: u32) -> vec2<u32> {
    return textureDimensions(scene_textures, 0);
}

fn scene_texel0(layer: u32, texel: vec2<u32>) -> vec4<f32> {
    return textureLoad(scene_textures, texel, layer, 0);
}
