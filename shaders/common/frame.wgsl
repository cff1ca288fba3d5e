// Per-frame uniforms, bound as `frame`. Mirrors FrameUniforms in src/runtime/uniforms.rs.
struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    // xyz: unit direction towards the light, w: intensity
    light_dir: vec4<f32>,
    // rgb: light colour, a: ambient intensity
    light_color: vec4<f32>,
    // width, height, 1/width, 1/height
    resolution: vec4<f32>,
    // orthographic view-projection of the directional light, covering the scene (shadow maps)
    light_view_proj: mat4x4<f32>,
    // xyz position, w intensity (0: no point light)
    point_light: vec4<f32>,
    // rgb colour
    point_color: vec4<f32>,
    // xyz scene bounds centre, w half diagonal
    scene_sphere: vec4<f32>,
    frame_index: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}
