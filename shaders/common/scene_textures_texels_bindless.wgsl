enable wgpu_binding_array;
// The scene's textures as a binding array of 2D array textures, where the device has texture
// binding arrays with non-uniform indexing: the textures of one size and encoding share an
// element, one per layer (src/scene/texture_pool.rs). A texture's reference, as the records
// hold it, is element << TEXTURE_REF_LAYER_BITS | layer (0: plain white). Same interface as
// common/scene_textures_texels.wgsl, which it replaces through an include substitution.
alias SceneTextures = binding_array<texture_2d_array<f32>>;

@group(1) @binding(0) var scene_textures: SceneTextures;

// src/scene/texture_pool.rs's TEXTURE_REF_LAYER_BITS.
const TEXTURE_REF_LAYER_BITS: u32 = 11u;

// The element of the binding array that holds the texture `layer` refers to.
fn scene_texture_element(layer: u32) -> u32 {
    return layer >> TEXTURE_REF_LAYER_BITS;
}

// The layer of its element.
fn scene_texture_layer(layer: u32) -> u32 {
    return layer & ((1u << TEXTURE_REF_LAYER_BITS) - 1u);
}

// Level 0 of a texture: its size in texels, and one texel.
fn scene_texture_size0(layer: u32) -> vec2<u32> {
    return textureDimensions(scene_textures[scene_texture_element(layer)], 0);
}

fn scene_texel0(layer: u32, texel: vec2<u32>) -> vec4<f32> {
    return textureLoad(scene_textures[scene_texture_element(layer)], texel, scene_texture_layer(layer), 0);
}
