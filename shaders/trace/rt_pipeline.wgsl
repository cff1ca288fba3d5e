// Back-end `rt-pipeline`: the ray-tracing pipeline (DXR's model, Vulkan's
// VK_KHR_ray_tracing_pipeline through wgpu-hal; src/accel/rt_pipeline.rs). The pass's compute
// entry point becomes the pipeline's ray-generation shader (the runtime rewrites its stage and
// its global_invocation_id into ray_invocation_id); this module adds the miss and closest-hit
// shaders of the shader binding table. A BLAS per mesh, a TLAS of instances whose custom data
// is the scene instance index; geometry is built opaque.
//
// Ray types, as in the paper: closest-hit rays (primary, reflection) run the closest-hit
// shader, which writes the hit into the payload; shadow and AO rays (trace_any) set
// TERMINATE_ON_FIRST_HIT and SKIP_CLOSEST_HIT_SHADER, so no hit shader runs for them: their
// payload starts as "hit" and only the miss shader changes it.
//
// naga's hit shaders have no hit-attribute variable, so the closest-hit shader computes the
// barycentrics from the object-space ray and the triangle's vertices (accel_positions,
// accel_indices), which it finds through the instance's first triangle
// (accel_first_triangle[instance]) and the primitive index. With `Accel(merge: true)` the TLAS
// holds one identity instance (custom data ACCEL_MERGED) over every instance's world-space
// triangles; accel_owners[primitive] names each triangle's instance and primitive (bit 31: a
// mirrored instance, whose triangles are stored wound back).
enable wgpu_ray_tracing_pipeline;
enable primitive_index;
//#include "trace/common.wgsl"

@group(2) @binding(0) var accel_tlas: acceleration_structure;
@group(2) @binding(1) var<storage, read_write> accel_stats: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read> accel_positions: array<f32>;
@group(2) @binding(3) var<storage, read> accel_indices: array<u32>;
@group(2) @binding(4) var<storage, read> accel_first_triangle: array<u32>;
@group(2) @binding(5) var<storage, read> accel_owners: array<vec2<u32>>;

const ACCEL_MERGED: u32 = 0xffffffu;

const TRACE_FLAG_FORCE_OPAQUE: u32 = 1u;
const TRACE_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 4u;
const TRACE_FLAG_SKIP_CLOSEST_HIT_SHADER: u32 = 8u;
const TRACE_HIT_KIND_FRONT_FACING: u32 = 0xfeu;

struct TracePayload {
    t: f32,
    // The scene instance, or NO_HIT (written by the miss shader).
    instance: u32,
    primitive: u32,
    front_face: u32,
    bary: vec2<f32>,
}

var<ray_payload> trace_payload: TracePayload;
var<incoming_ray_payload> trace_incoming: TracePayload;

fn trace_closest_flags(ray: Ray, flags: u32) -> Hit {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return trace_miss();
    }
    trace_count_closest++;
    trace_payload = TracePayload(-1.0, NO_HIT, 0u, 0u, vec2<f32>(0.0));
    let ray_flags = TRACE_FLAG_FORCE_OPAQUE | (flags & TRACE_CULL_BACK_FACES);
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
    // "Hit" unless the miss shader says otherwise: no hit shader runs for these rays.
    trace_payload.instance = 0u;
    let ray_flags = TRACE_FLAG_FORCE_OPAQUE | TRACE_FLAG_TERMINATE_ON_FIRST_HIT | TRACE_FLAG_SKIP_CLOSEST_HIT_SHADER | (flags & TRACE_CULL_BACK_FACES);
    traceRay(accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir), &trace_payload);
    let hit = trace_payload.instance != NO_HIT;
    if hit {
        trace_count_hits++;
    }
    return hit;
}

@miss @incoming_payload(trace_incoming)
fn trace_miss_shader() {
    trace_incoming.instance = NO_HIT;
}

fn trace_vertex(i: u32) -> vec3<f32> {
    return vec3<f32>(accel_positions[3u * i], accel_positions[3u * i + 1u], accel_positions[3u * i + 2u]);
}

@closest_hit @incoming_payload(trace_incoming)
fn trace_closest_hit_shader(
    @builtin(instance_custom_data) instance: u32,
    @builtin(primitive_index) primitive: u32,
    @builtin(hit_kind) hit_kind: u32,
    @builtin(ray_t_current_max) t: f32,
    @builtin(object_ray_origin) origin: vec3<f32>,
    @builtin(object_ray_direction) dir: vec3<f32>,
) {
    var tri = primitive;
    var scene_instance = instance;
    var scene_primitive = primitive;
    var mirrored = false;
    if instance == ACCEL_MERGED {
        let owner = accel_owners[primitive];
        scene_instance = owner.x;
        scene_primitive = owner.y & 0x7fffffffu;
        mirrored = (owner.y >> 31u) != 0u;
    } else {
        tri = accel_first_triangle[instance] + primitive;
    }
    let v0 = trace_vertex(accel_indices[3u * tri]);
    let v1 = trace_vertex(accel_indices[3u * tri + 1u]);
    let v2 = trace_vertex(accel_indices[3u * tri + 2u]);
    // Barycentrics of the object-space ray's hit (Moller-Trumbore without the range test: the
    // driver has already decided that the ray hits this triangle at t).
    let e1 = v1 - v0;
    let e2 = v2 - v0;
    let p = cross(dir, e2);
    let inv_det = 1.0 / dot(e1, p);
    let s = origin - v0;
    let q = cross(s, e1);
    var b = clamp(vec2<f32>(dot(s, p), dot(dir, q)) * inv_det, vec2<f32>(0.0), vec2<f32>(1.0));
    if mirrored {
        // Stored as (v0, v2, v1): the weights of the mesh's own second and third vertices.
        b = b.yx;
    }
    trace_incoming = TracePayload(t, scene_instance, scene_primitive, select(0u, 1u, hit_kind == TRACE_HIT_KIND_FRONT_FACING), b);
}
