// Depth of the scene from one light, for shadow maps: every instance through the
// view-projection of a shadow-map slot (`frame.shadow_view_proj`). One vertex entry point per
// slot (`vs_slot0` .. `vs_slot3`, one pass each in layers/shadow_map.ron); a slot no light uses
// draws nothing (every vertex is clipped). The pass writes only its depth attachment, so the
// fragment stage has no colour outputs.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;

fn shadow_vertex(slot: u32, position: vec3<f32>, instance: u32) -> vec4<f32> {
    if slot >= frame.shadow_count {
        return vec4<f32>(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
    }
    return frame.shadow_view_proj[slot] * (scene_instances[instance].model * vec4<f32>(position, 1.0));
}

@vertex
fn vs_slot0(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return shadow_vertex(0u, position, instance);
}

@vertex
fn vs_slot1(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return shadow_vertex(1u, position, instance);
}

@vertex
fn vs_slot2(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return shadow_vertex(2u, position, instance);
}

@vertex
fn vs_slot3(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return shadow_vertex(3u, position, instance);
}

@fragment
fn fs_main() {}
