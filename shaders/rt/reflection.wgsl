// Reflections: closest-hit rays along the mirror direction (glossy: a cosine-power lobe whose
// width follows the roughness), hit points shaded with the model of every mode
// (common/lighting.wgsl) and a shadow ray to every light; further bounces weighted by the
// Fresnel term. BLEND surfaces along each ray are composited over what lies behind them
// (common/hit_lighting.wgsl's composite_blend). Hit textures are sampled at the mip level of the pixel's ray cone, grown along
// the whole path (camera to the first surface, then every bounce; surfaces taken as flat).
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
    bounces: u32,
    glossy: u32,
    max_roughness: f32,
    seed: u32,
    per_frame: u32,
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
@group(0) @binding(8) var position: texture_2d<f32>;
@group(0) @binding(9) var normal: texture_2d<f32>;
@group(0) @binding(10) var geo_normal: texture_2d<f32>;
@group(0) @binding(11) var material: texture_2d<f32>;
@group(0) @binding(12) var reflection: texture_storage_2d<rgba16float, write>;
@group(0) @binding(13) var<storage, read> scene_lights: array<Light>;

// A direction around the mirror direction r: exact for roughness 0, a cosine-power lobe
// (exponent 2/roughness^4 - 2, the Blinn-Phong equivalent of GGX) otherwise.
fn glossy_direction(r: vec3<f32>, roughness: f32, u: vec2<f32>) -> vec3<f32> {
    if params.glossy == 0u || roughness < 0.03 {
        return r;
    }
    let a = roughness * roughness;
    let exponent = max(2.0 / (a * a) - 2.0, 1.0);
    let cos_t = pow(u.x, 1.0 / (exponent + 1.0));
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 6.28318530718 * u.y;
    let s = select(-1.0, 1.0, r.z >= 0.0);
    let k = -1.0 / (s + r.z);
    let b = r.x * r.y * k;
    let t = vec3<f32>(1.0 + s * r.x * r.x * k, s * b, -s * r.x);
    let bt = vec3<f32>(b, s + r.y * r.y * k, -r.y);
    return normalize(t * (sin_t * cos(phi)) + bt * (sin_t * sin(phi)) + r * cos_t);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(reflection);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    // How hits are lit (common/hit_lighting.wgsl): every light, or one picked from
    // `light_candidates` (new picks every frame with `per_frame`).
    hit_light_candidates = params.light_candidates;
    hit_light_state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(frame_seed(params.seed, frame.frame_index, params.per_frame) ^ 0x9e3779b9u)));
    let p = textureLoad(position, id.xy, 0);
    let m = textureLoad(material, id.xy, 0);
    // No reflection off the sky, rough surfaces and unlit ones (material a 0).
    if p.w == 0.0 || m.g > params.max_roughness || gbuffer_unlit(m.a) {
        textureStore(reflection, id.xy, vec4<f32>(0.0));
        return;
    }
    var n = normalize(textureLoad(normal, id.xy, 0).xyz);
    var geo = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    var origin = offset_ray_origin(p.xyz, geo);
    var v = camera_view_dir(p.xyz);
    var roughness = m.g;
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    // New glossy directions every frame with `per_frame` (for the temporal filter).
    let rnd = pixel_random2(id.xy, frame_seed(params.seed, frame.frame_index, params.per_frame));
    var path = distance(frame.camera_pos.xyz, p.xyz);
    for (var bounce = 0u; bounce < params.bounces; bounce++) {
        var dir = glossy_direction(reflect(-v, n), roughness, fract(rnd + r2_sample(bounce)));
        if dot(dir, geo) <= 0.0 {
            dir = reflect(dir, geo); // keep the ray above the surface it leaves
        }
        let ray = Ray(origin, 0.0, dir, 3.0e38);
        // BLEND surfaces on the way add their share and let the rest through.
        let cone = camera_cone_width(id.xy, path);
        let layers = composite_blend(ray, cone, camera_cone_width(id.xy, path + 1.0) - cone);
        radiance += throughput * layers.radiance;
        throughput *= layers.transmittance;
        let hit = layers.hit;
        if hit.instance == NO_HIT {
            radiance += throughput * sky_color(dir);
            break;
        }
        path += hit.t;
        let s = surface_at_cone(ray, hit, camera_cone_width(id.xy, path));
        radiance += throughput * shade_hit(s, -dir);
        if s.unlit {
            break; // an unlit surface reflects nothing
        }
        // The next bounce leaves the hit point, weighted by its Fresnel reflectance.
        let f = point_fresnel(hit_shading_point(s, -dir), dot(s.normal, -dir));
        throughput *= f;
        if s.roughness > params.max_roughness || max(throughput.x, max(throughput.y, throughput.z)) < 0.01 {
            break;
        }
        n = s.normal;
        geo = s.geo_normal;
        origin = offset_ray_origin(s.position, s.geo_normal);
        v = -dir;
        roughness = s.roughness;
    }
    textureStore(reflection, id.xy, vec4<f32>(radiance, 1.0));
    trace_flush_stats();
}
