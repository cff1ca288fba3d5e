// Depth of the scene from one light, for shadow maps: every instance through the
// view-projection of a shadow slot (`frame.shadow_view_proj`): a directional or spot light's map,
// or one face of a point light's cube map. The slot is the pipeline constant SHADOW_SLOT, which
// the executor sets from the pass's `shadow_slot` (one pass per slot in layers/shadow_map.ron);
// the pass of a slot no light uses is not recorded, and would draw nothing (every vertex is
// clipped). Alpha-tested materials drop the texels the alpha test cuts
// (common/raster_alpha_test.wgsl, the test of every mode). The pass writes only its depth
// attachment, so the fragment stage has no colour outputs.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures_texels.wgsl"
//#include "common/raster_alpha_test.wgsl"
//#include "common/vertex_extras.wgsl"

override SHADOW_SLOT: u32 = 0u;

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

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, @builtin(instance_index) instance: u32, @builtin(vertex_index) vertex: u32) -> VertexOut {
    var out: VertexOut;
    out.uv = uv;
    out.material = scene_instances[instance].material;
    out.alpha = 1.0;
    if RASTER_ALPHA_TEST {
        out.alpha = vertex_extras(scene_instances[instance], vertex, uv).color.a;
    }
    out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
    if ((frame.shadow_slots >> SHADOW_SLOT) & 1u) != 0u {
        out.clip = frame.shadow_view_proj[SHADOW_SLOT] * (scene_instances[instance].model * vec4<f32>(position, 1.0));
    }
    return out;
}

@fragment
fn fs_main(in: VertexOut) {
    if !material_alpha_visible(in.material, in.uv, in.clip.xy, in.alpha) {
        discard;
    }
}
