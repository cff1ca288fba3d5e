// Scene instance records, bound as `scene_instances`. Mirrors InstanceUniforms in
// src/runtime/uniforms.rs. `texture` is a layer of `scene_textures` (0 = white).
struct Instance {
    model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
    base_color: vec4<f32>,
    texture: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}
