// ReSTIR DI (Bitterli, Wyman, Pharr, Shirley, Lefohn, Jarosz, "Spatiotemporal reservoir
// resampling for real-time ray tracing with dynamic direct lighting", SIGGRAPH 2020), shared by
// rt/restir_initial.wgsl, rt/restir_temporal.wgsl and rt/restir_spatial.wgsl
// (layers/restir_di.ron).
//
// A light sample is a punctual light (its index), a point of an emissive triangle (its record
// and barycentrics) or a direction of the environment map (`--env`). Their domains are
// disjoint, so a candidate's source density is the chance of its kind times its density within
// it: a punctual light drawn uniformly, an emitter point by the triangle's power
// (common/emitters.wgsl) and uniformly on it (area measure), a direction from the map's alias
// table (common/environment_sampling.wgsl; solid angle). The target function is the luminance
// of the sample's unshadowed light at the shading point (the map's diffuse light alone).
//
// A reservoir (one Rgba32Uint texel): the sample (a punctual light's index, RESTIR_EMITTER |
// an emitter's record, RESTIR_ENVIRONMENT, or RESTIR_NONE), its barycentrics or direction as two
// 16-bit unorms, its unbiased contribution weight W and its candidate
// count M. The temporal pass combines a pixel's reservoir with its previous one by weights
// target x W x M normalised by the summed M; the spatial pass weights each reused sample by the
// generalised balance heuristic over the surfaces (rt/restir_spatial.wgsl). Both are the biased
// variant: no shadow ray enters the weights, so a neighbour's sample blocked here, or a sample
// the visibility reuse dropped there, shifts the estimate (ACCURACY.md, "Many lights at equal
// time", measures it).
//
// Needs the includer's G-buffer bindings (position, geo_normal, normal, albedo, material,
// lobes), `frame`, `scene_lights`, `scene_emitters`, `scene_instances`, `scene_materials` and
// `params.reflection_roughness`; common/lighting.wgsl, common/emitters.wgsl,
// common/gbuffer_lobes.wgsl, common/camera.wgsl and common/ray_offset.wgsl. The shadow rays are
// in common/restir_visibility.wgsl (passes that trace).

const RESTIR_NONE: u32 = 0xffffffffu;
const RESTIR_EMITTER: u32 = 0x80000000u;
// The environment map: a direction, its octahedral coordinates in the barycentrics' place.
const RESTIR_ENVIRONMENT: u32 = 0x40000000u;

fn restir_is_punctual(light: u32) -> bool {
    return light < RESTIR_ENVIRONMENT;
}

// Whether the environment map is among the sources: a map with its sampling table.
fn restir_environment() -> bool {
    return has_environment() && scene_environment_params.sampled != 0u;
}

// The world direction of an environment sample.
fn restir_environment_direction(uv: vec2<f32>) -> vec3<f32> {
    return octahedral_decode(uv * 2.0 - 1.0);
}

struct Reservoir {
    light: u32,
    uv: vec2<f32>,
    // The unbiased contribution weight W (0: the sample brings nothing, or was found blocked).
    weight: f32,
    // Candidates it stands for (M).
    count: f32,
}

fn reservoir_empty() -> Reservoir {
    return Reservoir(RESTIR_NONE, vec2<f32>(0.0), 0.0, 0.0);
}

fn reservoir_unpack(t: vec4<u32>) -> Reservoir {
    return Reservoir(t.x, unpack2x16unorm(t.y), bitcast<f32>(t.z), bitcast<f32>(t.w));
}

fn reservoir_pack(r: Reservoir) -> vec4<u32> {
    return vec4<u32>(r.light, pack2x16unorm(r.uv), bitcast<u32>(r.weight), bitcast<u32>(r.count));
}

// A shading point from the G-buffer at `id`, with what its shadow rays need.
struct RestirSurface {
    s: ShadingPoint,
    geo: vec3<f32>,
    offset: f32,
    facing: vec3<f32>,
    flat_origin: vec3<f32>,
    valid: bool,
}

fn restir_surface(id: vec2<u32>) -> RestirSurface {
    var out: RestirSurface;
    let p = textureLoad(position, id, 0);
    out.valid = p.w != 0.0;
    if !out.valid {
        return out;
    }
    let g = textureLoad(geo_normal, id, 0);
    let m = textureLoad(material, id, 0);
    out.geo = normalize(g.xyz);
    out.offset = g.w;
    var s: ShadingPoint;
    s.position = p.xyz;
    s.normal = normalize(textureLoad(normal, id, 0).xyz);
    s.view = camera_view_dir(p.xyz);
    s.albedo = textureLoad(albedo, id, 0).rgb;
    s.metallic = m.r;
    s.roughness = m.g;
    s.unlit = gbuffer_unlit(m.a);
    shading_lobes(&s, gbuffer_lobes(m.a, textureLoad(lobes, id, 0), s.normal));
    out.s = s;
    // Where geo_normal.w holds a shadow-terminator offset, the shading normal decides which
    // lights the surface faces (common/shadow_ray.wgsl's shadow_facing).
    out.facing = select(out.geo, out.s.normal, g.w > 0.0);
    out.flat_origin = offset_ray_origin(p.xyz, out.geo);
    return out;
}

// A sample's unshadowed light at a surface: its radiance towards the eye (per unit area of the
// emitter for an emitter point, per light for a punctual one), and the shadow ray's direction
// and length.
struct RestirLight {
    radiance: vec3<f32>,
    l: vec3<f32>,
    distance: f32,
}

fn restir_light(at: RestirSurface, light: u32, uv: vec2<f32>) -> RestirLight {
    var out = RestirLight(vec3<f32>(0.0), vec3<f32>(0.0, 1.0, 0.0), 0.0);
    if light == RESTIR_NONE {
        return out;
    }
    if light == RESTIR_ENVIRONMENT {
        out.l = restir_environment_direction(uv);
        out.distance = 3.0e38;
        if dot(out.l, at.facing) > 0.0 {
            // Per steradian, in light_radiance's units (a solid angle's irradiance over pi); the
            // diffuse part alone: the reflection pass and the resolve's split sum bring the map's
            // specular light.
            out.radiance = diffuse_radiance(at.s, out.l, environment_radiance(out.l) / PI);
        }
        return out;
    }
    if restir_is_punctual(light) {
        let ls = light_sample(scene_lights[light], at.s.position);
        out.l = ls.l;
        out.distance = ls.distance;
        if dot(at.facing, ls.l) > 0.0 {
            out.radiance = light_radiance(at.s, ls);
        }
        return out;
    }
    let i = light & (RESTIR_EMITTER - 1u);
    let t = emitter_triangle(i);
    let to = emitter_point(t, uv) - at.flat_origin;
    let d = length(to);
    if d <= 0.0 {
        return out;
    }
    out.l = to / d;
    out.distance = d;
    let material = scene_materials[scene_instances[scene_emitters[emitter_record(i)]].material];
    let cosine = -dot(out.l, normalize(t.normal));
    let seen = cosine > 0.0 || (material.flags & MATERIAL_DOUBLE_SIDED) != 0u;
    if !seen || dot(out.l, at.facing) <= 0.0 {
        return out;
    }
    // Irradiance at normal incidence from a unit area of the emitter, in light_radiance's units
    // (rt/shadow.wgsl's emitter_light divides the same by the point's area density).
    let e = t.emission * abs(cosine) / (PI * d * d);
    if at.s.roughness > params.reflection_roughness {
        out.radiance = light_radiance(at.s, LightSample(out.l, e, d));
    } else {
        out.radiance = diffuse_radiance(at.s, out.l, e);
    }
    return out;
}

fn restir_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The target function: the luminance of a sample's unshadowed light at a surface.
fn restir_target(at: RestirSurface, light: u32, uv: vec2<f32>) -> f32 {
    return restir_luminance(restir_light(at, light, uv).radiance);
}

// Streaming resampling: the sample picked so far and the running sums.
struct RestirStream {
    picked: Reservoir,
    picked_target: f32,
    weight_sum: f32,
    count: f32,
}

fn restir_stream() -> RestirStream {
    return RestirStream(reservoir_empty(), 0.0, 0.0, 0.0);
}

// Offers `r` (with its target `goal` at the stream's surface) to the stream, as a reservoir of
// `count` candidates; `u` uniform in [0, 1).
fn restir_offer(stream: ptr<function, RestirStream>, r: Reservoir, goal: f32, count: f32, u: f32) {
    let w = goal * r.weight * count;
    (*stream).count += count;
    if w > 0.0 {
        (*stream).weight_sum += w;
        if u * (*stream).weight_sum < w {
            (*stream).picked = r;
            (*stream).picked_target = goal;
        }
    }
}

// The stream's reservoir: its sample with W = the summed weights over (M x its target).
fn restir_finish(stream: RestirStream) -> Reservoir {
    var r = stream.picked;
    r.count = stream.count;
    r.weight = select(0.0, stream.weight_sum / (stream.count * stream.picked_target), stream.picked_target > 0.0 && stream.count > 0.0);
    if r.weight == 0.0 {
        r.light = RESTIR_NONE;
    }
    return r;
}
