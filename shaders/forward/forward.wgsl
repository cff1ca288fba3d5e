// Forward shading of the scene's meshes with the shading model of every mode
// (common/lighting.wgsl: every light of `scene_lights`, sky ambient x material occlusion,
// the sky's specular reflection, emission; base colour, metallic-roughness, emissive and occlusion textures). Writes linear
// HDR colour; alpha 1 marks geometry.
//
// A light with a shadow-map slot (`Light::shadow_map`, the first four directional or spot
// lights) has its direct term multiplied by its shadow-map visibility (common/forward_shading.wgsl);
// other lights are unshadowed.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/lighting.wgsl"
//#include "common/material_inputs.wgsl"
//#include "common/raster_visibility.wgsl"
//#include "common/forward_shading.wgsl"
//#include "common/vertex_extras.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(5) var<uniform> params: Params;
@group(0) @binding(6) var shadow_map: texture_depth_2d;
@group(0) @binding(7) var shadow_map_1: texture_depth_2d;
@group(0) @binding(8) var shadow_map_2: texture_depth_2d;
@group(0) @binding(9) var shadow_map_3: texture_depth_2d;
@group(0) @binding(10) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(11) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(12) var<storage, read> scene_vertices: array<SceneVertex>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) @interpolate(flat) instance: u32,
    @location(3) world_pos: vec3<f32>,
    // Object-space position: its derivatives give the face normal and the normal map's frame
    // without the rounding of large world coordinates, as in deferred/deferred.wgsl.
    @location(4) local: vec3<f32>,
    // TEXCOORD_1 (TEXCOORD_0 without one) and COLOR_0 (white without one).
    @location(5) uv1: vec2<f32>,
    @location(6) color: vec4<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) instance: u32,
    @builtin(vertex_index) vertex: u32,
) -> VertexOut {
    let inst = scene_instances[instance];
    let extras = vertex_extras(inst, vertex, uv);
    let world = inst.model * vec4<f32>(position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_normal = (inst.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    out.world_pos = world.xyz;
    out.local = position;
    out.uv1 = extras.uv1;
    out.color = extras.color;
    return out;
}

// Material inputs and facing are read as the raster G-buffer reads them
// (deferred/deferred.wgsl, common/material_inputs.wgsl): back faces of single-sided materials
// culled, those of double-sided ones with reversed normals.
@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    let inst = scene_instances[in.instance];
    if !raster_fragment_kept(inst, in.uv, in.clip.xy, in.color.a) {
        discard;
    }
    // Before any non-uniform branch (it takes derivatives: the normal map's frame, the face
    // normal and the shadow maps' receiver plane). The geometric normal decides the shadow
    // offset direction, so smooth shading normals do not push points into neighbouring geometry.
    let r = raster_surface(inst, front_facing, in.local, in.uv, in.uv1, in.color, in.world_normal);

    var s: ShadingPoint;
    s.position = in.world_pos;
    s.normal = r.normal;
    s.view = camera_view_dir(in.world_pos);
    s.albedo = r.albedo;
    s.metallic = r.metallic;
    s.roughness = r.roughness;
    s.occlusion = r.occlusion;
    s.emissive = r.emissive;
    s.unlit = r.unlit;
    shading_lobes(&s, r.lobes);
    return vec4<f32>(forward_radiance(s, r.geo_normal, r.dp1, r.dp2), 1.0);
}
