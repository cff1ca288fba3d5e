// Back-end `ray-query`: wgpu's EXPERIMENTAL_RAY_QUERY (a BLAS per mesh, a TLAS of instances
// whose custom data is the scene instance index). Shadow and AO rays set
// TERMINATE_ON_FIRST_HIT, the paper's shadow-ray flag. Geometry is built opaque. The trace
// interface's TRACE_CULL_BACK_FACES is the driver's RAY_FLAG_CULL_BACK_FACING (facing decided
// in object space, as the compute back-end does).
enable wgpu_ray_query;
//#include "trace/common.wgsl"

@group(2) @binding(0) var accel_tlas: acceleration_structure;
@group(2) @binding(1) var<storage, read_write> accel_stats: array<atomic<u32>>;

const TRACE_FLAG_FORCE_OPAQUE: u32 = 1u;
const TRACE_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 4u;

fn trace_closest_flags(ray: Ray, flags: u32) -> Hit {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return trace_miss();
    }
    trace_count_closest++;
    var rq: ray_query;
    let ray_flags = TRACE_FLAG_FORCE_OPAQUE | (flags & TRACE_CULL_BACK_FACES);
    rayQueryInitialize(&rq, accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir));
    rayQueryProceed(&rq);
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
    let ray_flags = TRACE_FLAG_FORCE_OPAQUE | TRACE_FLAG_TERMINATE_ON_FIRST_HIT | (flags & TRACE_CULL_BACK_FACES);
    rayQueryInitialize(&rq, accel_tlas, RayDesc(ray_flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.dir));
    rayQueryProceed(&rq);
    let hit = rayQueryGetCommittedIntersection(&rq).kind != RAY_QUERY_INTERSECTION_NONE;
    if hit {
        trace_count_hits++;
    }
    return hit;
}
