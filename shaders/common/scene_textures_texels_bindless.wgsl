enable wgpu_binding_array;
// The scene's textures as a binding array (each texture at its own size with its own mip
// chain), where the device has texture binding arrays with non-uniform indexing. Same
// interface as common/scene_textures_texels.wgsl, which it replaces through an include
// substitution.
alias SceneTextures = binding_array<texture_2d<f32>>;

@group(1) @binding(0) var scene_textures: SceneTextures;

// Level 0 of a texture: its size in texels, and one texel.
fn scene_texture_size0(layer: u32) -> vec2<u32> {
    return textureDimensions(scene_textures[layer], 0);
}

fn scene_texel0(layer: u32, texel: vec2<u32>) -> vec4<f32> {
    return textureLoad(scene_textures[layer], texel, 0);
}
