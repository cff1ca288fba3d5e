// G-buffer of the simple deferred layer: world position, shading normal, geometric normal
// (from screen-space derivatives of the position, turned towards the camera) and albedo.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(1) @binding(0) var scene_textures: SceneTextures;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) instance: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) instance: u32,
) -> VertexOut {
    let inst = scene_instances[instance];
    let world = inst.model * vec4<f32>(position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (inst.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    return out;
}

struct GBuffer {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) geo_normal: vec4<f32>,
    @location(3) albedo: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> GBuffer {
    let material = scene_materials[scene_instances[in.instance].material];
    let albedo = material.base_color.rgb * sample_scene_texture(material.base_texture, in.uv).rgb;
    let to_camera = frame.camera_pos.xyz - in.world;
    var geo = normalize(cross(dpdx(in.world), dpdy(in.world)));
    if dot(geo, to_camera) < 0.0 {
        geo = -geo;
    }
    var n = normalize(in.normal);
    if dot(n, geo) < 0.0 {
        n = -n; // back side of a double-sided surface
    }
    var out: GBuffer;
    out.position = vec4<f32>(in.world, 1.0);
    out.normal = vec4<f32>(n, 0.0);
    out.geo_normal = vec4<f32>(geo, 0.0);
    out.albedo = vec4<f32>(albedo, 1.0);
    return out;
}
