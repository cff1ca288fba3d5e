// Depth of the scene from one light, for shadow maps: every instance through the
// view-projection of a shadow-map slot (`frame.shadow_view_proj`). One vertex entry point per
// slot (`vs_slot0` .. `vs_slot3`, one pass each in layers/shadow_map.ron); the pass of a
// slot no light uses is not recorded (`shadow_slot`), and would draw nothing (every vertex is
// clipped). Alpha-tested materials drop the texels the alpha
// test cuts (common/raster_alpha_test.wgsl, the test of every mode). The pass writes only its depth
// attachment, so the fragment stage has no colour outputs.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures_texels.wgsl"
//#include "common/raster_alpha_test.wgsl"
//#include "common/vertex_extras.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(4) var<storage, read> scene_vertices: array<SceneVertex>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) material: u32,
    // The vertex colours' alpha (COLOR_0), for the alpha test: read only in the pipelines of
    // alpha-tested draws (RASTER_ALPHA_TEST), 1 in the others.
    @location(2) alpha: f32,
}

fn shadow_vertex(slot: u32, position: vec3<f32>, uv: vec2<f32>, instance: u32, vertex: u32) -> VertexOut {
    var out: VertexOut;
    out.uv = uv;
    out.material = scene_instances[instance].material;
    out.alpha = 1.0;
    if RASTER_ALPHA_TEST {
        out.alpha = vertex_extras(scene_instances[instance], vertex, uv).color.a;
    }
    out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
    if slot < frame.shadow_count {
        out.clip = frame.shadow_view_proj[slot] * (scene_instances[instance].model * vec4<f32>(position, 1.0));
    }
    return out;
}

@vertex
fn vs_slot0(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, @builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> VertexOut {
    return shadow_vertex(0u, position, uv, instance, vertex);
}

@vertex
fn vs_slot1(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, @builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> VertexOut {
    return shadow_vertex(1u, position, uv, instance, vertex);
}

@vertex
fn vs_slot2(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, @builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> VertexOut {
    return shadow_vertex(2u, position, uv, instance, vertex);
}

@vertex
fn vs_slot3(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, @builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> VertexOut {
    return shadow_vertex(3u, position, uv, instance, vertex);
}

@fragment
fn fs_main(in: VertexOut) {
    if !material_alpha_visible(in.material, in.uv, in.clip.xy, in.alpha) {
        discard;
    }
}
