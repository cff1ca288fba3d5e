// G-buffer: world position, shading normal (normal-mapped through a cotangent frame from
// screen-space derivatives, so meshes need no tangents), geometric normal (from derivatives of
// the object-space position, transformed), albedo and material. Normals face the camera.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/alpha.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var linear_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) instance: u32,
    // Object-space position: its derivatives give the face normal without the rounding of
    // large world coordinates (an instance far from the origin).
    @location(4) local: vec3<f32>,
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
    out.local = position;
    return out;
}

struct GBuffer {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) geo_normal: vec4<f32>,
    @location(3) albedo: vec4<f32>,
    @location(4) material: vec4<f32>,
}

// Perturbs n by a tangent-space normal map sample (Schüler, "Normal Mapping Without
// Precomputed Tangents", 2013).
fn perturb(n: vec3<f32>, p: vec3<f32>, uv: vec2<f32>, map: vec3<f32>, scale: f32) -> vec3<f32> {
    let dp1 = dpdx(p);
    let dp2 = dpdy(p);
    let duv1 = dpdx(uv);
    let duv2 = dpdy(uv);
    let dp2perp = cross(dp2, n);
    let dp1perp = cross(n, dp1);
    let t = dp2perp * duv1.x + dp1perp * duv2.x;
    let b = dp2perp * duv1.y + dp1perp * duv2.y;
    let invmax = inverseSqrt(max(max(dot(t, t), dot(b, b)), 1e-20));
    let m = map * 2.0 - vec3<f32>(1.0);
    let local = vec3<f32>(m.xy * scale, m.z);
    return normalize(t * invmax * local.x + b * invmax * local.y + n * local.z);
}

@fragment
fn fs_main(in: VertexOut) -> GBuffer {
    if !material_alpha_visible(scene_instances[in.instance].material, in.uv) {
        discard;
    }
    let material = scene_materials[scene_instances[in.instance].material];
    let base = sample_scene_texture(material.base_texture, in.uv);
    let mr = sample_scene_texture(material.metallic_roughness_texture, in.uv);
    let emissive = material.emissive * sample_scene_texture(material.emissive_texture, in.uv).rgb;
    let inst = scene_instances[in.instance];
    // Back faces are culled, so every fragment shows the side its vertex normals point to: the
    // face normal is oriented by them, not by a test against positions (which lose precision
    // far from the origin) nor by the sign of the derivatives (which flips in quads that
    // straddle the horizon).
    var n = normalize(in.normal);
    var geo = normalize((inst.normal_matrix * vec4<f32>(cross(dpdx(in.local), dpdy(in.local)), 0.0)).xyz);
    if dot(geo, n) < 0.0 {
        geo = -geo;
    }
    if material.normal_texture != 0u {
        let map = sample_scene_texture(material.normal_texture, in.uv).rgb;
        n = perturb(n, in.world, in.uv, map, material.normal_scale);
    }
    var out: GBuffer;
    out.position = vec4<f32>(in.world, 1.0);
    out.normal = vec4<f32>(n, 0.0);
    out.geo_normal = vec4<f32>(geo, 0.0);
    out.albedo = vec4<f32>(material.base_color.rgb * base.rgb, 1.0);
    let e = dot(emissive, vec3<f32>(0.2126, 0.7152, 0.0722));
    out.material = vec4<f32>(material.metallic * mr.b, clamp(material.roughness * mr.g, 0.02, 1.0), min(e / 16.0, 1.0), 1.0);
    return out;
}
