// Shadows: from the offset G-buffer position one any-hit ray to every light (to its position
// for point and spot lights, stopping just short of it; along the light for directional ones),
// where the surface faces the light and the light reaches it. With an area (`light_radius`,
// `light_width` and `light_height`, `sun_angle` above 0), each of `rays` rays goes to one random point of it
// (common/shadow_ray.wgsl): a stochastic estimate of a soft shadow per pixel and light, for the temporal and spatial filters. Writes the
// shadowed direct light of all lights (common/lighting.wgsl) and a mask of the first four; with
// `split`, also the unshadowed light and the ratio of the two (layers/rt_shadow.ron). With an
// environment map (`--env`), `environment_rays` directions (drawn from its alias table,
// common/environment_sampling.wgsl, and cosine-weighted) give its visibility: the
// irradiance-weighted fraction of them that no surface blocks (a ratio estimator), stored as
// `direct`'s a = 2 + visibility (WebGPU allows four storage textures a stage); the resolve
// puts it on the map's irradiance in place of AO. With emissive triangles (common/emitters.wgsl),
// `emitter_rays` points on them picked by power, each with its shadow ray, add their light to
// `direct` (and `unshadowed`): all of it on surfaces rougher than `reflection_roughness`, the
// diffuse part alone on smoother ones, whose specular part the reflection pass's rays bring
// (they see the emitters' emission). With `light_candidates` above 0, one light picked by
// resampled importance sampling stands for all of them (`pick_light`): one shadow ray a pixel
// however many lights there are (common/light_pick.wgsl).
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/lighting.wgsl"
//#include "common/scene.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/environment_sampling.wgsl"
//#include "common/emitters.wgsl"
//#include "common/light_pick.wgsl"

struct Params {
    light_radius: f32,
    sun_angle: f32,
    per_frame: u32,
    seed: u32,
    rays: u32,
    light_width: f32,
    light_height: f32,
    split: u32,
    environment_rays: u32,
    emitter_rays: u32,
    reflection_roughness: f32,
    light_candidates: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(9) var<uniform> params: Params;
@group(0) @binding(1) var position: texture_2d<f32>;
@group(0) @binding(2) var geo_normal: texture_2d<f32>;
@group(0) @binding(3) var normal: texture_2d<f32>;
@group(0) @binding(4) var albedo: texture_2d<f32>;
@group(0) @binding(5) var material: texture_2d<f32>;
@group(0) @binding(6) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(7) var shadow: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(8) var direct: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(11) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(12) var lobes: texture_2d<u32>;
@group(0) @binding(13) var unshadowed: texture_storage_2d<rgba16float, write>;
@group(0) @binding(14) var visibility: texture_storage_2d<rgba16float, write>;
@group(0) @binding(15) var<storage, read> scene_emitters: array<u32>;

// The environment map's visibility at a point of shading normal `n` and geometric normal
// `geo`: of `params.environment_rays` directions, the share of their irradiance estimates
// (cos x luminance / density) whose ray from `origin` no surface blocks (BLEND surfaces by
// their transmittance). Half the directions (the odd one out included) are drawn from the map,
// half cosine-weighted about `n`, each weighted by the mixture's density (the balance
// heuristic): the map's sun gets its rays, and some always lie above the surface. 1 where no
// direction brings light.
fn environment_visibility(origin: vec3<f32>, geo: vec3<f32>, n: vec3<f32>, state: ptr<function, u32>) -> f32 {
    let rays = params.environment_rays;
    let from_map = f32((rays + 1u) / 2u) / f32(rays);
    var seen = 0.0;
    var total = 0.0;
    for (var k = 0u; k < rays; k++) {
        var dir = cosine_hemisphere(n, next_random2(state));
        if k % 2u == 0u {
            dir = environment_sample(vec3<f32>(next_random2(state), next_random1(state))).dir;
        }
        let cos_n = dot(n, dir);
        let density = from_map * environment_pdf(dir) + (1.0 - from_map) * max(cos_n, 0.0) / PI;
        if density <= 0.0 || cos_n <= 0.0 || dot(geo, dir) <= 0.0 {
            continue;
        }
        let w = cos_n * dot(environment_radiance(dir), vec3<f32>(0.2126, 0.7152, 0.0722)) / density;
        total += w;
        seen += w * trace_transmittance(Ray(origin, 0.0, dir, 3.0e38));
    }
    return select(1.0, seen / total, total > 0.0);
}

// Where a pixel's shadow rays leave from: its G-buffer position, geometric normal and
// terminator offset, the flat offset origin, the side lights must be on, the area lights' sizes
// and the rays a light gets.
struct ShadowPoint {
    p: vec3<f32>,
    geo: vec3<f32>,
    offset: f32,
    flat_origin: vec3<f32>,
    facing: vec3<f32>,
    sizes: AreaLights,
    area: bool,
    samples: u32,
}

// One light's light at a pixel: shadowed (x the fraction of its rays that reach the point,
// each by the transmittance of the BLEND surfaces on its way) and unshadowed (written only
// where some ray reaches it or `split` asks for it).
struct LightResult {
    shadowed: vec3<f32>,
    unshadowed: vec3<f32>,
    fraction: f32,
}

fn light_result(i: u32, s: ShadingPoint, at: ShadowPoint, state: ptr<function, u32>) -> LightResult {
    // Rays towards this light leave from the part of the offset its angle asks for (no work
    // where there is none: flat triangles, the fragment-stage G-buffer).
    let origin = shadow_ray_origin(at.flat_origin, at.p, at.geo, s.normal, at.offset, scene_lights[i]);
    var seen = 0.0;
    if at.area {
        for (var k = 0u; k < at.samples; k++) {
            seen += area_light_transmittance(scene_lights[i], origin, at.facing, at.sizes, next_random2(state));
        }
    } else {
        seen = light_transmittance(scene_lights[i], origin, at.facing);
    }
    var out = LightResult(vec3<f32>(0.0), vec3<f32>(0.0), seen / f32(at.samples));
    if seen > 0.0 || params.split != 0u {
        // (exactly 1 for an unshadowed hard shadow)
        out.unshadowed = light_radiance(s, light_sample(scene_lights[i], at.p));
        out.shadowed = out.fraction * out.unshadowed;
    }
    return out;
}

// The emissive triangles' light at `s` (shading normal `s.normal`, lit from the side of
// `facing`), by `params.emitter_rays` points picked by power, each a ray from `origin`:
// x the shadowed light, y the unshadowed one (each the mean over the points).
fn emitter_light(s: ShadingPoint, origin: vec3<f32>, facing: vec3<f32>, state: ptr<function, u32>) -> array<vec3<f32>, 2> {
    var out = array<vec3<f32>, 2>(vec3<f32>(0.0), vec3<f32>(0.0));
    let rays = params.emitter_rays;
    if emitter_count() == 0u || rays == 0u {
        return out;
    }
    let whole = s.roughness > params.reflection_roughness;
    for (var k = 0u; k < rays; k++) {
        let picked = emitter_pick(next_random1(state));
        let t = emitter_triangle(picked);
        let to = emitter_point(t, uniform_barycentrics(next_random2(state))) - origin;
        let d = length(to);
        let l = to / max(d, 1e-30);
        let material = scene_materials[scene_instances[scene_emitters[emitter_record(picked)]].material];
        let front = dot(l, t.normal) < 0.0;
        let probability = emitter_probability(picked);
        if d <= 0.0 || dot(l, facing) <= 0.0 || probability <= 0.0 || (!front && (material.flags & MATERIAL_DOUBLE_SIDED) == 0u) {
            continue;
        }
        // Irradiance at normal incidence in light_radiance's units (a light of `e` lights a
        // white Lambert surface facing it to e): the radiance over pi x the point's density.
        let e = t.emission / (PI * emitter_density(probability, t.normal, to));
        var light = diffuse_radiance(s, l, e);
        if whole {
            light = light_radiance(s, LightSample(l, e, d));
        }
        if any(light > vec3<f32>(0.0)) {
            out[0] += light * trace_transmittance(Ray(origin, 0.0, l, d * 0.9999));
            out[1] += light;
        }
    }
    out[0] /= f32(rays);
    out[1] /= f32(rays);
    return out;
}

// `shadowed` over `unshadowed` per channel; where a channel of `unshadowed` is 0, the ratio of
// the luminances (the channel's product is 0 either way; this keeps the filters' luminance
// weights meaningful there); 0 where no light reaches at all.
fn visibility_ratio(shadowed: vec3<f32>, unshadowed: vec3<f32>) -> vec3<f32> {
    let luma = vec3<f32>(0.2126, 0.7152, 0.0722);
    let total = dot(unshadowed, luma);
    let overall = select(0.0, dot(shadowed, luma) / total, total > 0.0);
    let per_channel = shadowed / max(unshadowed, vec3<f32>(1e-30));
    return min(select(vec3<f32>(overall), per_channel, unshadowed > vec3<f32>(0.0)), vec3<f32>(1.0));
}

// The split outputs (`params.split`): the unshadowed light and the visibility ratio.
fn store_split(id: vec2<u32>, shadowed: vec3<f32>, light: vec3<f32>, on_geometry: f32) {
    if params.split != 0u {
        textureStore(unshadowed, id, vec4<f32>(light, on_geometry));
        textureStore(visibility, id, vec4<f32>(visibility_ratio(shadowed, light), on_geometry));
    }
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shadow);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(shadow, id.xy, vec4<f32>(1.0));
        textureStore(direct, id.xy, vec4<f32>(0.0));
        store_split(id.xy, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
        return;
    }
    let g = textureLoad(geo_normal, id.xy, 0);
    let geo = normalize(g.xyz);
    let m = textureLoad(material, id.xy, 0);
    var s: ShadingPoint;
    s.position = p.xyz;
    s.normal = normalize(textureLoad(normal, id.xy, 0).xyz);
    s.view = camera_view_dir(p.xyz);
    s.albedo = textureLoad(albedo, id.xy, 0).rgb;
    s.metallic = m.r;
    s.roughness = m.g;
    s.unlit = gbuffer_unlit(m.a);
    shading_lobes(&s, gbuffer_lobes(m.a, textureLoad(lobes, id.xy, 0), s.normal));
    // Where geo_normal.w holds a shadow-terminator offset, the shading normal decides which
    // lights the surface faces.
    let facing = shadow_facing(geo, s.normal, g.w);
    let flat_origin = offset_ray_origin(p.xyz, geo);
    var mask = vec4<f32>(0.0);
    var radiance = vec3<f32>(0.0);
    var light_alone = vec3<f32>(0.0);
    let sizes = AreaLights(params.light_radius, radians(params.sun_angle) * 0.5, params.light_width, params.light_height);
    let area = sizes.radius > 0.0 || sizes.sun_radius > 0.0 || (sizes.width > 0.0 && sizes.height > 0.0);
    var state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(frame_seed(params.seed, frame.frame_index, params.per_frame))));
    let at = ShadowPoint(p.xyz, geo, g.w, flat_origin, facing, sizes, area, select(1u, max(params.rays, 1u), area));
    // Every light, or the one picked for all of them: one loop, so that the traversal is
    // compiled in once (the compute back-end inlines it at every call).
    let picking = params.light_candidates > 0u;
    var picked = PickedLight(0u, 1.0);
    if picking {
        picked = pick_light(s, p.xyz, params.light_candidates, &state);
    }
    let lights = select(frame.light_count, select(1u, 0u, picked.index == NO_LIGHT), picking);
    for (var k = 0u; k < lights; k++) {
        let i = select(k, picked.index, picking);
        let r = light_result(i, s, at, &state);
        radiance += picked.weight * r.shadowed;
        light_alone += picked.weight * r.unshadowed;
        if i < 4u {
            mask[i] = r.fraction;
        }
    }
    let emitted = emitter_light(s, flat_origin, facing, &state);
    radiance += emitted[0];
    light_alone += emitted[1];
    textureStore(shadow, id.xy, mask);
    // a = 1: the direct light was computed here (the resolve's fallback has a = 0); 2 + the
    // environment map's visibility where it was traced.
    var computed = 1.0;
    if has_environment() && params.environment_rays > 0u {
        computed = 2.0 + environment_visibility(flat_origin, geo, s.normal, &state);
    }
    textureStore(direct, id.xy, vec4<f32>(radiance, computed));
    store_split(id.xy, radiance, light_alone, 1.0);
    trace_flush_stats();
}
