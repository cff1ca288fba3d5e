// The path-traced reference (layers/rt_path.ron): `samples` paths a pixel, each through a
// random point of the pixel, of any length (Russian roulette from the fourth vertex on, at most
// `max_bounces` bounces). At every vertex:
//   - the emissive triangles (common/emitters.wgsl) by next-event estimation of one triangle
//     picked by power and a uniform point on it, combined by the power heuristic with the
//     emission the BSDF's own directions hit (an unlit surface's albedo counts whole);
//   - every punctual light (the sun among them) with its own shadow ray (hit_direct_light:
//     delta lights, which only next-event estimation can reach);
//   - the sky (radiance frame.ambient x sky_color, common/lighting.wgsl) by next-event
//     estimation with a cosine-weighted direction, or the environment map (`--env`) with a
//     direction drawn by its luminance (common/environment_sampling.wgsl), combined with the
//     BSDF's own sampling by the power heuristic (multiple importance sampling);
//   - the next direction from the shared BSDF (common/bsdf_sampling.wgsl).
// BLEND surfaces are passed with the probability their coverage leaves (tinted by a
// transmissive one's colour), back faces of single-sided materials always (as every mode
// culls them). A camera ray that meets nothing leaves the pixel's alpha at 0: the backdrop is
// the tone map's, as in every mode; `radiance` holds the mean premultiplied radiance and its
// alpha the share of paths that met geometry. Textures are read at their finest level (width-0
// ray cones): the pixel's footprint is integrated by the random points within it, not by mip
// levels.
//#include "common/scene_bindings.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "common/lighting.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/hit_lighting.wgsl"
//#include "common/bsdf_sampling.wgsl"
//#include "common/emitters.wgsl"
//#include "common/environment_sampling.wgsl"

struct Params {
    samples: u32,
    max_bounces: u32,
    seed: u32,
    light_candidates: u32,
}

// Bindings 0-6: common/scene_bindings.wgsl.
@group(0) @binding(7) var<uniform> params: Params;
@group(0) @binding(8) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(9) var radiance: texture_storage_2d<rgba32float, write>;
@group(0) @binding(10) var<storage, read> scene_emitters: array<u32>;

// How many surfaces (back faces of single-sided materials, BLEND surfaces passed) one path
// segment goes through before it ends.
const PATH_PASSES: u32 = 16u;
// Russian roulette starts at this vertex.
const ROULETTE_FROM: u32 = 3u;

// The sky's radiance towards `dir` (what every mode's ambient term integrates).
fn sky_radiance(dir: vec3<f32>) -> vec3<f32> {
    if has_environment() {
        return environment_radiance(dir);
    }
    return frame.ambient * sky_color(dir);
}

// Density of the sky's next-event directions at `sp`: the environment map's sampler's, or
// cosine-weighted about the normal.
fn sky_pdf(sp: ShadingPoint, l: vec3<f32>) -> f32 {
    if has_environment() {
        return environment_pdf(l);
    }
    return max(dot(sp.normal, l), 0.0) / PI;
}

// A next-event direction towards the sky at `sp`: drawn from the environment map, or
// cosine-weighted about the normal.
fn sky_direction(sp: ShadingPoint, rng: ptr<function, u32>) -> vec3<f32> {
    if has_environment() {
        return environment_sample(vec3<f32>(next_random2(rng), next_random1(rng))).dir;
    }
    return cosine_hemisphere(sp.normal, next_random2(rng));
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    return a2 / max(a2 + b * b, 1e-30);
}

// A segment's hit: the surface a path meets, and the tint of what it passed on the way.
struct PathHit {
    hit: Hit,
    tint: vec3<f32>,
}

// The closest surface `ray` stops at: back faces of single-sided materials passed, BLEND
// surfaces passed with probability 1 - coverage.
fn path_hit(ray_in: Ray, rng: ptr<function, u32>) -> PathHit {
    var ray = ray_in;
    var out = PathHit(trace_closest(ray), vec3<f32>(1.0));
    for (var i = 0u; i < PATH_PASSES; i++) {
        if out.hit.instance == NO_HIT {
            return out;
        }
        let flags = scene_materials[scene_instances[out.hit.instance].material].flags;
        let back_culled = !out.hit.front_face && (flags & MATERIAL_DOUBLE_SIDED) == 0u;
        let coverage = hit_blend_coverage(out.hit);
        if !back_culled && (coverage < 0.0 || next_random1(rng) < coverage) {
            return out;
        }
        if !back_culled && (flags & MATERIAL_TRANSMISSION) != 0u {
            out.tint *= surface_at_cone(ray, out.hit, 0.0).albedo;
        }
        ray.t_min = blend_past(out.hit.t);
        out.hit = trace_closest(ray);
    }
    // Too many surfaces passed: the path ends here, bringing nothing.
    out.hit.instance = NO_HIT;
    out.tint = vec3<f32>(0.0);
    return out;
}

// The camera ray through image point `at` (in pixels from the top left corner).
fn camera_ray_through(at: vec2<f32>) -> Ray {
    let origin = camera_origin_at(at);
    return Ray(origin, 0.0, normalize(camera_unproject_at(at, 1.0) - origin), 3.0e38);
}

// The sky's light at `s` by one cosine-weighted next-event direction, MIS-weighted against
// the BSDF's sampling of the same direction.
fn sky_next_event(s: Surface, sp: ShadingPoint, rng: ptr<function, u32>) -> vec3<f32> {
    if !has_environment() && frame.ambient <= 0.0 {
        return vec3<f32>(0.0);
    }
    let l = sky_direction(sp, rng);
    let pdf = sky_pdf(sp, l);
    if pdf <= 0.0 || dot(l, s.geo_normal) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let f_cos = bsdf_cos(sp, l);
    if all(f_cos == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let visible = trace_transmittance(Ray(offset_ray_origin(s.position, s.geo_normal), 0.0, l, 3.0e38));
    return visible * f_cos * sky_radiance(l) * power_heuristic(pdf, bsdf_pdf(sp, l)) / pdf;
}

// The density (solid angle, seen from `origin`) with which next-event estimation picks the point
// `at` on `instance`'s triangle `primitive`; 0 for a triangle that is no emitter.
fn emitter_pdf(instance: u32, primitive: u32, origin: vec3<f32>, at: vec3<f32>) -> f32 {
    let record = hit_emitter(instance, primitive);
    if record == NO_EMITTERS {
        return 0.0;
    }
    let probability = emitter_probability(record);
    if probability <= 0.0 {
        return 0.0;
    }
    return emitter_density(probability, emitter_triangle(record).normal, at - origin);
}

// The light of one emissive triangle picked by power at `s` (one point, one shadow ray),
// MIS-weighted against the BSDF's sampling of the same direction. The emission is the
// texture's at the point (the table's mean only picks the triangle).
fn emitter_next_event(s: Surface, sp: ShadingPoint, rng: ptr<function, u32>) -> vec3<f32> {
    if emitter_count() == 0u {
        return vec3<f32>(0.0);
    }
    let picked = emitter_pick(next_random1(rng));
    let record = emitter_record(picked);
    let instance = scene_emitters[record];
    let primitive = scene_emitters[record + 1u];
    let bary = uniform_barycentrics(next_random2(rng));
    let triangle = emitter_triangle(picked);
    let at = emitter_point(triangle, bary);
    let origin = offset_ray_origin(s.position, s.geo_normal);
    let to = at - origin;
    let d = length(to);
    let l = to / max(d, 1e-30);
    let front = dot(l, triangle.normal) < 0.0;
    let material = scene_materials[scene_instances[instance].material];
    if d <= 0.0 || dot(l, s.geo_normal) <= 0.0 || (!front && (material.flags & MATERIAL_DOUBLE_SIDED) == 0u) {
        return vec3<f32>(0.0);
    }
    let f_cos = bsdf_cos(sp, l);
    let probability = emitter_probability(picked);
    let pdf = select(0.0, emitter_density(probability, triangle.normal, to), probability > 0.0);
    if all(f_cos == vec3<f32>(0.0)) || pdf <= 0.0 {
        return vec3<f32>(0.0);
    }
    // The barycentrics of the point in the object's corner order (a mirroring transform
    // swapped the table's last two corners).
    let inst = scene_instances[instance];
    let mirrored = determinant(mat3x3<f32>(inst.model[0].xyz, inst.model[1].xyz, inst.model[2].xyz)) < 0.0;
    let light = Hit(d, instance, primitive, select(bary, bary.yx, mirrored), front);
    let emission = surface_at_cone(Ray(origin, 0.0, l, d), light, 0.0).emissive;
    let visible = trace_transmittance(Ray(origin, 0.0, l, d * 0.9999));
    return visible * f_cos * emission * power_heuristic(pdf, bsdf_pdf(sp, l)) / pdf;
}

// One path from camera ray `camera`: rgb the radiance it brings, a 1 if it met geometry.
fn trace_path(camera: Ray, rng: ptr<function, u32>) -> vec4<f32> {
    var ray = camera;
    var throughput = vec3<f32>(1.0);
    var sum = vec3<f32>(0.0);
    // The shading point the ray left and the BSDF's density of its direction (0: the camera).
    var from_point: ShadingPoint;
    var from_pdf = 0.0;
    for (var bounce = 0u; ; bounce++) {
        let found = path_hit(ray, rng);
        throughput *= found.tint;
        if found.hit.instance == NO_HIT {
            if bounce == 0u {
                return vec4<f32>(0.0);
            }
            let weight = power_heuristic(from_pdf, sky_pdf(from_point, ray.dir));
            return vec4<f32>(sum + throughput * sky_radiance(ray.dir) * weight, 1.0);
        }
        let s = surface_at_cone(ray, found.hit, 0.0);
        if s.unlit {
            return vec4<f32>(sum + throughput * s.albedo, 1.0);
        }
        var emitted = 1.0;
        if bounce > 0u {
            emitted = power_heuristic(from_pdf, emitter_pdf(found.hit.instance, found.hit.primitive, ray.origin, s.position));
        }
        sum += throughput * s.emissive * emitted;
        if bounce >= params.max_bounces {
            break;
        }
        let sp = hit_shading_point(s, -ray.dir);
        sum += throughput * (hit_direct_light(s, sp) + sky_next_event(s, sp, rng) + emitter_next_event(s, sp, rng));
        let b = bsdf_sample(sp, next_random1(rng), next_random2(rng));
        if b.pdf <= 0.0 || dot(b.dir, s.geo_normal) <= 0.0 {
            break;
        }
        throughput *= b.f_cos / b.pdf;
        if bounce >= ROULETTE_FROM {
            let keep = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95);
            if next_random1(rng) >= keep {
                break;
            }
            throughput /= keep;
        }
        from_point = sp;
        from_pdf = b.pdf;
        ray = Ray(offset_ray_origin(s.position, s.geo_normal), 0.0, b.dir, 3.0e38);
    }
    return vec4<f32>(sum, 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(radiance);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    var rng = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(params.seed ^ pcg_hash(frame.frame_index))));
    // Next-event estimation at each vertex (common/hit_lighting.wgsl): every light, or one
    // picked from `light_candidates`.
    hit_light_candidates = params.light_candidates;
    hit_light_state = pcg_hash(rng ^ 0x9e3779b9u);
    var sum = vec4<f32>(0.0);
    for (var i = 0u; i < params.samples; i++) {
        let path = trace_path(camera_ray_through(vec2<f32>(id.xy) + next_random2(&rng)), &rng);
        // A path whose value is not finite (an overflow in a throughput) counts as 0: one such
        // value would stay in the pixel's mean for good.
        if all(path == path) && all(abs(path) < vec4<f32>(1e30)) {
            sum += path;
        }
    }
    textureStore(radiance, id.xy, sum / f32(max(params.samples, 1u)));
    trace_flush_stats();
}
