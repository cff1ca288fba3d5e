// The trace interface every trace pass uses, whatever the back-end:
//   trace_closest(ray) -> Hit   closest hit in [t_min, t_max]
//   trace_any(ray) -> bool      any hit in [t_min, t_max]; stops at the first (shadow/AO rays)
//   trace_transmittance_flags(ray, flags) -> f32
//                               what gets through [t_min, t_max]: the product of one minus
//                               the coverage of the BLEND surfaces passed (trace/alpha.wgsl's
//                               trace_transmittance_passes), 0 at an opaque one; one any-hit
//                               traversal, counted as one any-hit ray (common/ray_blend.wgsl)
//   trace_closest_flags(ray, flags), trace_any_flags(ray, flags)
//                               the same with per-ray flags (TRACE_CULL_BACK_FACES;
//                               TRACE_PASS_BLEND for trace_closest_flags)
//   trace_start_within(origin, radius) -> TraceStart
//   trace_transmittance_within(ray, start, flags) -> f32
//                               trace_transmittance_flags for rays from `origin` that reach no
//                               farther than `radius` (t_max |dir| <= radius: AO rays, whose
//                               t_max is the radius and whose directions are unit vectors):
//                               the compute back-end finds once, for all of them, the node
//                               under which every triangle they can reach lies, and starts
//                               each ray there; the same result as trace_transmittance_flags
//                               for such rays. Its merged path does not test each ray for it
//                               (the test cost the atrium's frame 2.8%, PERF.md step 43), so a
//                               ray that reaches farther may miss what lies outside the
//                               sphere's box; its two-level path sends such a ray to the whole
//                               traversal. Other back-ends trace from the root.
//   trace_flush_stats()         adds this invocation's ray counts to the GPU counters; call it
//                               once at the end of the entry point
// A pass includes "trace/trace.wgsl"; the back-end chosen at start-up substitutes its module
// (trace/compute.wgsl or trace/ray_query.wgsl), which includes this file and binds its
// acceleration structure in @group(2).
// Invalid rays (NaN/Inf origin or direction, zero direction, t_min < 0, t_max < t_min) never
// reach the traversal: they count as invalid and miss.

//#include "common/ray.wgsl"

// Where rays within a sphere start (trace_start_within): `node`, a node of the compute
// back-end's merged BLAS whose subtree holds every triangle within reach, TRACE_START_NONE
// (nothing within reach) or TRACE_START_ROOT (the whole traversal); `lo`, `hi` the box the
// rays' segments must stay in. One node: starting at two, four or eight took the pine's AO
// pass 2-16% lower but the atrium's and the helmet's at 2% of the frame 6-60% higher (H200,
// PERF.md step 24).
struct TraceStart {
    node: u32,
    lo: vec3<f32>,
    hi: vec3<f32>,
}
const TRACE_START_ROOT: u32 = 0xffffffffu;
const TRACE_START_NONE: u32 = 0xfffffffeu;

// Per-ray flags of trace_closest_flags / trace_any_flags.
const TRACE_FLAGS_NONE: u32 = 0u;
// Back faces (clockwise seen from the ray origin in object space, `Hit::front_face` false) are
// not hit: the ray passes through them. The value is the SPIR-V / WGSL ray flag
// RAY_FLAG_CULL_BACK_FACING, so the ray-query back-end passes it through.
const TRACE_CULL_BACK_FACES: u32 = 16u;
// trace_closest_flags only: BLEND surfaces (translucent materials, common/ray_blend.wgsl) are
// not hit: the ray passes them in its one traversal and finds the closest other surface, as
// the G-buffer's primary rays want it (common/primary_hit.wgsl). Not a ray flag of SPIR-V or
// WGSL: each back-end passes such candidates itself (trace/alpha.wgsl's
// trace_visible_passes), where a new traversal past each one took the pine's primary pass at
// 2% of the frame 0.45 ms against 0.17 without them (H200, PERF.md step 50).
const TRACE_PASS_BLEND: u32 = 0x10000u;

// Slots of `accel_stats`.
const STAT_CLOSEST_RAYS: u32 = 0u;
const STAT_ANY_RAYS: u32 = 1u;
const STAT_INVALID_RAYS: u32 = 2u;
const STAT_HITS: u32 = 3u;

var<private> trace_count_closest: u32 = 0u;
var<private> trace_count_any: u32 = 0u;
var<private> trace_count_invalid: u32 = 0u;
var<private> trace_count_hits: u32 = 0u;

fn trace_miss() -> Hit {
    return Hit(-1.0, NO_HIT, 0u, vec2<f32>(0.0), false);
}

// Finiteness from the bits: comparisons and min/max may not see NaN once a driver compiles
// with fast-math assumptions; an all-ones exponent is NaN or infinity whatever the compiler.
fn trace_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn trace_finite3(v: vec3<f32>) -> bool {
    return trace_finite(v.x) && trace_finite(v.y) && trace_finite(v.z);
}

fn trace_ray_is_valid(ray: Ray) -> bool {
    let dir_ok = trace_finite3(ray.dir) && any(ray.dir != vec3<f32>(0.0));
    // t_max may be +infinity; t_min must be finite and not negative (sign bit clear).
    let t_max_ok = trace_finite(ray.t_max) || bitcast<u32>(ray.t_max) == 0x7f800000u;
    let t_ok = trace_finite(ray.t_min) && (bitcast<u32>(ray.t_min) & 0x80000000u) == 0u && t_max_ok && ray.t_max >= ray.t_min;
    return trace_finite3(ray.origin) && dir_ok && t_ok;
}

// The flagless entry points; each back-end module defines trace_closest_flags and
// trace_any_flags.
fn trace_closest(ray: Ray) -> Hit {
    return trace_closest_flags(ray, TRACE_FLAGS_NONE);
}

fn trace_any(ray: Ray) -> bool {
    return trace_any_flags(ray, TRACE_FLAGS_NONE);
}

fn trace_flush_stats() {
    if trace_count_closest != 0u { atomicAdd(&accel_stats[STAT_CLOSEST_RAYS], trace_count_closest); }
    if trace_count_any != 0u { atomicAdd(&accel_stats[STAT_ANY_RAYS], trace_count_any); }
    if trace_count_invalid != 0u { atomicAdd(&accel_stats[STAT_INVALID_RAYS], trace_count_invalid); }
    if trace_count_hits != 0u { atomicAdd(&accel_stats[STAT_HITS], trace_count_hits); }
    trace_count_closest = 0u;
    trace_count_any = 0u;
    trace_count_invalid = 0u;
    trace_count_hits = 0u;
}
