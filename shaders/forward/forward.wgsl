// Forward shading of the scene's meshes: textured Lambert under one directional light plus
// a hemisphere ambient term. Writes linear HDR colour; alpha 1 marks geometry.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(1) @binding(0) var scene_textures: SceneTextures;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_materials: array<Material>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) @interpolate(flat) instance: u32,
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
    out.world_normal = (inst.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let material = scene_materials[scene_instances[in.instance].material];
    let tex = sample_scene_texture(material.base_texture, in.uv);
    let albedo = material.base_color.rgb * tex.rgb;
    let n = normalize(in.world_normal);
    let l = frame.light_dir.xyz;
    let direct = max(dot(n, l), 0.0) * frame.light_dir.w * frame.light_color.rgb;
    let sky = mix(vec3<f32>(0.35, 0.3, 0.25), vec3<f32>(0.6, 0.75, 1.0), 0.5 + 0.5 * n.y);
    let ambient = frame.light_color.a * sky;
    return vec4<f32>(albedo * (direct + ambient), 1.0);
}
