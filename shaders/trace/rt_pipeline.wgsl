// Back-end `rt-pipeline`: the ray-tracing pipeline (DXR's model, Vulkan's
// VK_KHR_ray_tracing_pipeline through wgpu-hal; src/accel/rt_pipeline.rs). The pass's compute
// entry point becomes the pipeline's ray-generation shader (the runtime rewrites its stage and
// its global_invocation_id into ray_invocation_id); this module adds the miss, closest-hit and
// any-hit shaders of the shader binding table. A BLAS per mesh, a TLAS of instances whose
// custom data is the scene instance index.
//
// Alpha (trace/alpha.wgsl). Geometry of alpha-tested instances is built without the OPAQUE
// flag, every other instance is forced opaque (TLAS instance flag), and rays no longer force
// opaque: the driver runs the any-hit shader only on candidates of alpha-tested geometry, so
// opaque geometry pays nothing. The any-hit shader rejects a candidate whose texel is below the
// cutoff. naga cannot express that rejection, so the runtime compiles trace_any_hit_shader to
// SPIR-V itself and patches it (src/accel/rt_pipeline/any_hit.rs): the store to
// trace_ignore_intersection becomes OpIgnoreIntersectionKHR, and trace_hit_attribute becomes
// the HitAttributeKHR variable (the triangle's barycentrics).
//
// Ray types, as in the paper: closest-hit rays (primary, reflection) run the closest-hit
// shader, which writes the hit into the payload; shadow and AO rays (trace_any) set
// TERMINATE_ON_FIRST_HIT and SKIP_CLOSEST_HIT_SHADER, so only the any-hit shader runs for them
// (it rejects transparent texels before the termination): their payload starts as "hit" and
// only the miss shader changes it. wgpu-hal's pipeline takes one miss shader and naga's
// traceRay has no miss index, so the one miss shader branches on the payload's ray_type: it
// stands in for one miss shader per ray type.
//
// naga's closest-hit shader has no hit-attribute variable, so it computes the barycentrics
// from the object-space ray and the triangle's vertices (accel_positions, accel_indices),
// which it finds through the geometry's first triangle and the primitive index
// (trace_triangle). With `Accel(merge: true)` the TLAS holds one identity instance (custom
// data ACCEL_MERGED) over every instance's world-space triangles, in two geometries (opaque
// triangles, then alpha-tested ones; accel_first_triangle[geometry] is each one's first
// triangle); accel_owners[triangle] names each triangle's instance and primitive (bit 31: a
// mirrored instance, whose triangles are stored wound back).
enable wgpu_ray_tracing_pipeline;
enable primitive_index;
//#include "trace/common.wgsl"
//#include "trace/alpha.wgsl"

@group(2) @binding(0) var accel_tlas: acceleration_structure;
@group(2) @binding(1) var<storage, read_write> accel_stats: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read> accel_positions: array<f32>;
@group(2) @binding(3) var<storage, read> accel_indices: array<u32>;
@group(2) @binding(4) var<storage, read> accel_first_triangle: array<u32>;
@group(2) @binding(5) var<storage, read> accel_owners: array<vec2<u32>>;

const ACCEL_MERGED: u32 = 0xffffffu;

const TRACE_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 4u;
const TRACE_FLAG_SKIP_CLOSEST_HIT_SHADER: u32 = 8u;
const TRACE_HIT_KIND_FRONT_FACING: u32 = 0xfeu;

// The payload's ray_type: which miss shader the miss stands for.
const TRACE_RAY_CLOSEST: u32 = 0u;
const TRACE_RAY_ANY: u32 = 1u;
// A transmittance ray (trace_transmittance_flags): an any-hit ray whose any-hit shader passes
// BLEND surfaces, multiplying `transmittance` by what each lets through.
const TRACE_RAY_TRANSMITTANCE: u32 = 2u;
// A closest-hit ray with TRACE_PASS_BLEND: its any-hit shader passes every BLEND surface.
const TRACE_RAY_CLOSEST_PAST_BLEND: u32 = 3u;

// Whether the pass traces closest-hit rays (its ray-generation shader calls
// trace_closest_flags): false compiles the any-hit shader's branch for TRACE_RAY_CLOSEST_PAST_BLEND
// out of the pipelines of passes that trace only shadow and AO rays, whose any-hit shader then
// carries no code of a ray type they never trace. Set by the runtime for the any-hit stage alone
// (src/accel/rt_pipeline/any_hit.rs); the default keeps the branch.
override TRACE_CLOSEST_RAYS: bool = true;

struct TracePayload {
    ray_type: u32,
    t: f32,
    // The scene instance, or NO_HIT (written by the miss shader).
    instance: u32,
    primitive: u32,
    front_face: u32,
    bary: vec2<f32>,
    // Transmittance rays: what the BLEND surfaces passed so far let through.
    transmittance: f32,
}

var<ray_payload> trace_payload: TracePayload;
var<incoming_ray_payload> trace_incoming: TracePayload;

fn trace_closest_flags(ray: Ray, flags: u32) -> Hit {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return trace_miss();
    }
    trace_count_closest++;
    trace_payload.ray_type = select(TRACE_RAY_CLOSEST, TRACE_RAY_CLOSEST_PAST_BLEND, (flags & TRACE_PASS_BLEND) != 0u);
    let ray_flags = flags & TRACE_CULL_BACK_FACES;
    traceRay(accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir), &trace_payload);
    let p = trace_payload;
    if p.instance == NO_HIT {
        return trace_miss();
    }
    trace_count_hits++;
    return Hit(p.t, p.instance, p.primitive, p.bary, p.front_face != 0u);
}

fn trace_any_flags(ray: Ray, flags: u32) -> bool {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return false;
    }
    trace_count_any++;
    // "Hit" unless the miss shader says otherwise: no closest-hit shader runs for these rays.
    trace_payload.ray_type = TRACE_RAY_ANY;
    trace_payload.instance = 0u;
    let ray_flags = TRACE_FLAG_TERMINATE_ON_FIRST_HIT | TRACE_FLAG_SKIP_CLOSEST_HIT_SHADER | (flags & TRACE_CULL_BACK_FACES);
    traceRay(accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir), &trace_payload);
    let hit = trace_payload.instance != NO_HIT;
    if hit {
        trace_count_hits++;
    }
    return hit;
}

fn trace_transmittance_flags(ray: Ray, flags: u32) -> f32 {
    if !trace_transmittance_starts(ray) {
        return 1.0;
    }
    // "Stopped" unless the miss shader says otherwise, as for trace_any_flags; the any-hit
    // shader passes the BLEND surfaces and accepts the candidate that stops the ray.
    trace_payload.ray_type = TRACE_RAY_TRANSMITTANCE;
    trace_payload.instance = 0u;
    trace_payload.transmittance = 1.0;
    let ray_flags = TRACE_FLAG_TERMINATE_ON_FIRST_HIT | TRACE_FLAG_SKIP_CLOSEST_HIT_SHADER | (flags & TRACE_CULL_BACK_FACES);
    traceRay(accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir), &trace_payload);
    trace_transmitted = trace_payload.transmittance;
    return trace_transmittance_result(trace_payload.instance != NO_HIT);
}

// The miss shader of every ray type (see the module comment).
@miss @incoming_payload(trace_incoming)
fn trace_miss_shader() {
    if trace_incoming.ray_type == TRACE_RAY_ANY || trace_incoming.ray_type == TRACE_RAY_TRANSMITTANCE {
        // Shadow and AO rays: only "nothing hit" matters (and what a transmittance ray's
        // payload has let through).
        trace_incoming.instance = NO_HIT;
    } else {
        trace_incoming = TracePayload(TRACE_RAY_CLOSEST, -1.0, NO_HIT, 0u, 0u, vec2<f32>(0.0), 1.0);
    }
}

fn trace_vertex(i: u32) -> vec3<f32> {
    return vec3<f32>(accel_positions[3u * i], accel_positions[3u * i + 1u], accel_positions[3u * i + 2u]);
}

// A hit's triangle: its index in accel_positions/accel_indices, its scene instance and
// primitive, and whether it is stored wound back (a mirrored instance in the merged layout).
struct TraceTriangle {
    index: u32,
    instance: u32,
    primitive: u32,
    mirrored: bool,
}

fn trace_triangle(custom_data: u32, geometry: u32, primitive: u32) -> TraceTriangle {
    if custom_data == ACCEL_MERGED {
        let index = accel_first_triangle[geometry] + primitive;
        let owner = accel_owners[index];
        return TraceTriangle(index, owner.x, owner.y & 0x7fffffffu, (owner.y >> 31u) != 0u);
    }
    return TraceTriangle(accel_first_triangle[custom_data] + primitive, custom_data, primitive, false);
}

@closest_hit @incoming_payload(trace_incoming)
fn trace_closest_hit_shader(
    @builtin(instance_custom_data) instance: u32,
    @builtin(geometry_index) geometry: u32,
    @builtin(primitive_index) primitive: u32,
    @builtin(hit_kind) hit_kind: u32,
    @builtin(ray_t_current_max) t: f32,
    @builtin(object_ray_origin) origin: vec3<f32>,
    @builtin(object_ray_direction) dir: vec3<f32>,
) {
    let tri = trace_triangle(instance, geometry, primitive);
    let v0 = trace_vertex(accel_indices[3u * tri.index]);
    let v1 = trace_vertex(accel_indices[3u * tri.index + 1u]);
    let v2 = trace_vertex(accel_indices[3u * tri.index + 2u]);
    // Barycentrics of the object-space ray's hit (Moller-Trumbore without the range test: the
    // driver has already decided that the ray hits this triangle at t).
    let e1 = v1 - v0;
    let e2 = v2 - v0;
    let p = cross(dir, e2);
    let inv_det = 1.0 / dot(e1, p);
    let s = origin - v0;
    let q = cross(s, e1);
    var b = clamp(vec2<f32>(dot(s, p), dot(dir, q)) * inv_det, vec2<f32>(0.0), vec2<f32>(1.0));
    if tri.mirrored {
        // Stored as (v0, v2, v1): the weights of the mesh's own second and third vertices.
        b = b.yx;
    }
    let front = select(0u, 1u, hit_kind == TRACE_HIT_KIND_FRONT_FACING);
    trace_incoming = TracePayload(TRACE_RAY_CLOSEST, t, tri.instance, tri.primitive, front, b, 1.0);
}

// Patched by the runtime (src/accel/rt_pipeline/any_hit.rs): the HitAttributeKHR variable
// holding the candidate's barycentrics (weights of its stored second and third vertices), and
// the marker whose store becomes OpIgnoreIntersectionKHR. Only trace_any_hit_shader uses them,
// and only as written here: trace_hit_attribute loaded whole, the marker stored once.
var<private> trace_hit_attribute: vec2<f32>;
var<private> trace_ignore_intersection: u32;

// Runs on candidates of alpha-tested (non-opaque) geometry only: rejects a transparent texel;
// a closest-hit ray with TRACE_PASS_BLEND passes every BLEND surface; a transmittance ray
// passes a BLEND surface (trace_transmittance_passes on the payload's transmittance; the
// geometry is built NO_DUPLICATE_ANY_HIT_INVOCATION, so no surface is taken out twice).
@any_hit @incoming_payload(trace_incoming)
fn trace_any_hit_shader(
    @builtin(instance_custom_data) instance: u32,
    @builtin(geometry_index) geometry: u32,
    @builtin(primitive_index) primitive: u32,
) {
    let tri = trace_triangle(instance, geometry, primitive);
    var b = trace_hit_attribute;
    if tri.mirrored {
        b = b.yx;
    }
    var ignore: bool;
    if trace_incoming.ray_type == TRACE_RAY_TRANSMITTANCE {
        trace_transmitted = trace_incoming.transmittance;
        ignore = trace_transmittance_passes(tri.instance, tri.primitive, b);
        trace_incoming.transmittance = trace_transmitted;
    } else if TRACE_CLOSEST_RAYS && trace_incoming.ray_type == TRACE_RAY_CLOSEST_PAST_BLEND {
        ignore = trace_visible_passes(tri.instance, tri.primitive, b);
    } else {
        ignore = !trace_alpha_visible(tri.instance, tri.primitive, b);
    }
    if ignore {
        trace_ignore_intersection = 1u;
    }
}

// Rays within a sphere start at the root here (trace/common.wgsl).
fn trace_start_within(origin: vec3<f32>, radius: f32) -> TraceStart {
    return TraceStart(TRACE_START_ROOT, origin, origin);
}

fn trace_transmittance_within(ray: Ray, start: TraceStart, flags: u32) -> f32 {
    return trace_transmittance_flags(ray, flags);
}
