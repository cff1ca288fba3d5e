// Per-frame uniforms, bound as `frame`. Mirrors FrameUniforms in src/uniforms.rs.
// The lights themselves are records of `scene_lights` (common/lighting.wgsl).
struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz the camera's position; w 1 for a perspective camera, 0 for an orthographic one
    camera_pos: vec4<f32>,
    // width, height, 1/width, 1/height
    resolution: vec4<f32>,
    // xyz scene bounds centre, w half diagonal
    scene_sphere: vec4<f32>,
    // view-projection of each raster shadow slot (`Light::shadow_map`): slots 0-3 the shadow
    // maps of directional and spot lights, then six a cube map of a point light (its faces
    // +x, -x, +y, -y, +z, -z)
    shadow_view_proj: array<mat4x4<f32>, 16>,
    // intensity of the sky's ambient light
    ambient: f32,
    // number of records in `scene_lights`
    light_count: u32,
    // the shadow slots in use: bit `slot` set where a light has it
    shadow_slots: u32,
    frame_index: u32,
    // 1 when history resources hold the previous frame; 0 on an executor's first frame and on
    // a camera cut (their contents are then undefined)
    history_valid: u32,
    // the previous frame's view_proj (this frame's when history_valid is 0)
    prev_view_proj: mat4x4<f32>,
}
