// One-bounce diffuse global illumination (layers/rt_gi.ron): cosine-weighted closest-hit rays
// from the G-buffer, each hit lit directly (a shadow ray per light) and by its own emission.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "common/lighting.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/hit_lighting.wgsl"

struct Params {
    rays: u32,
    per_frame: u32,
    seed: u32,
    emission: u32,
    light_candidates: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(3) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(4) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(5) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(6) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(7) var linear_sampler: sampler;
@group(0) @binding(8) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(9) var position: texture_2d<f32>;
@group(0) @binding(10) var geo_normal: texture_2d<f32>;
@group(0) @binding(11) var normal: texture_2d<f32>;
@group(0) @binding(12) var gi: texture_storage_2d<rgba16float, write>;

// The radiance leaving hit surface `s` towards `v`: every light with its own shadow ray, and
// the emission where `params.emission` asks for it (no sky ambient: that is the resolve's).
fn hit_radiance(s: Surface, v: vec3<f32>) -> vec3<f32> {
    if s.unlit {
        return s.albedo;
    }
    return hit_direct_light(s, hit_shading_point(s, v)) + select(vec3<f32>(0.0), s.emissive, params.emission != 0u);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gi);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    // How hits are lit (common/hit_lighting.wgsl): every light, or one picked from
    // `light_candidates` (new picks every frame with `per_frame`).
    hit_light_candidates = params.light_candidates;
    hit_light_state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(frame_seed(params.seed, frame.frame_index, params.per_frame) ^ 0x9e3779b9u)));
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(gi, id.xy, vec4<f32>(0.0));
        return;
    }
    let geo = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    let n = normalize(textureLoad(normal, id.xy, 0).xyz);
    let origin = offset_ray_origin(p.xyz, geo);
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    let rotation = pixel_random2(id.xy, params.seed);
    let path = distance(frame.camera_pos.xyz, p.xyz);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < params.rays; i++) {
        var dir = cosine_hemisphere(n, fract(r2_sample(i + frame_offset * params.rays) + rotation));
        if dot(dir, geo) <= 0.0 {
            dir = reflect(dir, geo); // keep the ray above the surface it leaves
        }
        let ray = Ray(origin, 0.0, dir, 3.0e38);
        let hit = trace_closest(ray);
        if hit.instance != NO_HIT {
            sum += hit_radiance(surface_at_cone(ray, hit, camera_cone_width(id.xy, path + hit.t)), -dir);
        }
    }
    textureStore(gi, id.xy, vec4<f32>(sum / f32(max(params.rays, 1u)), 1.0));
    trace_flush_stats();
}
