// Depth of the scene from the directional light, for shadow maps: every instance through
// `frame.light_view_proj`. The pass writes only its depth attachment, so the fragment stage
// has no colour outputs.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return frame.light_view_proj * (scene_instances[instance].model * vec4<f32>(position, 1.0));
}

@fragment
fn fs_main() {}
