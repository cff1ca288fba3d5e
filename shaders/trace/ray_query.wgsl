// Back-end `ray-query`: wgpu's EXPERIMENTAL_RAY_QUERY (a BLAS per mesh, a TLAS of instances
// whose custom data is the scene instance index). Shadow and AO rays set
// TERMINATE_ON_FIRST_HIT, the paper's shadow-ray flag. The trace interface's
// TRACE_CULL_BACK_FACES is the driver's RAY_FLAG_CULL_BACK_FACING (facing decided in object
// space, as the compute back-end does).
// Alpha test: meshes used by an alpha-tested instance are built without the OPAQUE geometry
// flag (src/accel/cache.rs), every other mesh opaque, so only their hits come back as
// candidates; the candidate loop confirms those trace_alpha_visible keeps (it keeps opaque
// instances' hits at once, a mesh may be used by both kinds). With TERMINATE_ON_FIRST_HIT the
// first confirmed (visible) hit ends an any-hit ray.
enable wgpu_ray_query;
//#include "trace/common.wgsl"
//#include "trace/alpha.wgsl"

@group(2) @binding(0) var accel_tlas: acceleration_structure;
@group(2) @binding(1) var<storage, read_write> accel_stats: array<atomic<u32>>;

const TRACE_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 4u;

fn trace_closest_flags(ray: Ray, flags: u32) -> Hit {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return trace_miss();
    }
    trace_count_closest++;
    var rq: ray_query;
    let ray_flags = flags & TRACE_CULL_BACK_FACES;
    rayQueryInitialize(&rq, accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir));
    // The candidate loop (naga takes a ray query only as a local variable, so it is written
    // out in both entry points): confirm the candidates the alpha test keeps, with
    // TRACE_PASS_BLEND none on a BLEND surface.
    let pass_blend = (flags & TRACE_PASS_BLEND) != 0u;
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        var passed: bool;
        if pass_blend {
            passed = trace_visible_passes(c.instance_custom_data, c.primitive_index, c.barycentrics);
        } else {
            passed = !trace_alpha_visible(c.instance_custom_data, c.primitive_index, c.barycentrics);
        }
        if !passed {
            rayQueryConfirmIntersection(&rq);
        }
    }
    let x = rayQueryGetCommittedIntersection(&rq);
    if x.kind == RAY_QUERY_INTERSECTION_NONE {
        return trace_miss();
    }
    trace_count_hits++;
    return Hit(x.t, x.instance_custom_data, x.primitive_index, x.barycentrics, x.front_face);
}

fn trace_any_flags(ray: Ray, flags: u32) -> bool {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return false;
    }
    trace_count_any++;
    var rq: ray_query;
    let ray_flags = TRACE_FLAG_TERMINATE_ON_FIRST_HIT | (flags & TRACE_CULL_BACK_FACES);
    rayQueryInitialize(&rq, accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir));
    // The candidate loop (naga takes a ray query only as a local variable, so it is written
    // out in both entry points): confirm the candidates the alpha test keeps.
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        if trace_alpha_visible(c.instance_custom_data, c.primitive_index, c.barycentrics) {
            rayQueryConfirmIntersection(&rq);
        }
    }
    let hit = rayQueryGetCommittedIntersection(&rq).kind != RAY_QUERY_INTERSECTION_NONE;
    if hit {
        trace_count_hits++;
    }
    return hit;
}

fn trace_transmittance_flags(ray: Ray, flags: u32) -> f32 {
    if !trace_transmittance_starts(ray) {
        return 1.0;
    }
    var rq: ray_query;
    let ray_flags = TRACE_FLAG_TERMINATE_ON_FIRST_HIT | (flags & TRACE_CULL_BACK_FACES);
    rayQueryInitialize(&rq, accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir));
    // Candidates of BLEND surfaces are passed (their coverage taken out of trace_transmitted);
    // the first one that stops the ray is confirmed, which ends it.
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        if !trace_transmittance_passes(c.instance_custom_data, c.primitive_index, c.barycentrics) {
            rayQueryConfirmIntersection(&rq);
        }
    }
    return trace_transmittance_result(rayQueryGetCommittedIntersection(&rq).kind != RAY_QUERY_INTERSECTION_NONE);
}

// Rays within a sphere start at the root here (trace/common.wgsl).
fn trace_start_within(origin: vec3<f32>, radius: f32) -> TraceStart {
    return TraceStart(TRACE_START_ROOT, origin, origin);
}

fn trace_transmittance_within(ray: Ray, start: TraceStart, flags: u32) -> f32 {
    return trace_transmittance_flags(ray, flags);
}
