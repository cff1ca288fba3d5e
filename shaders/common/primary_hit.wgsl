// The closest surface a primary ray sees, back faces of single-sided materials culled as the
// rasterizer culls them (common/primary_rays.wgsl, the kernel of the primary-ray passes), and
// BLEND surfaces passed (the G-buffer holds the first opaque surface; the rt_blend layer
// composites the translucent ones in front of it, common/ray_blend.wgsl).
// Needs the main shader to declare the scene's instances and materials and to include
// trace/trace.wgsl.
//#include "common/ray_blend.wgsl"

// How many culled back faces a primary ray passes before it gives up (a miss).
const MAX_CULLED: u32 = 16u;

// Whether a primary ray goes on past `hit`: a back face of a single-sided material. (BLEND
// surfaces are never hit: the traversal passes them, TRACE_PASS_BLEND.)
fn primary_culled(hit: Hit) -> bool {
    let flags = scene_materials[scene_instances[hit.instance].material].flags;
    return !hit.front_face && (flags & MATERIAL_DOUBLE_SIDED) == 0u;
}

// The closest hit that is neither a back face of a single-sided material nor a BLEND surface.
// The traversal itself passes BLEND surfaces (TRACE_PASS_BLEND); a culled back face is passed
// by a new traversal just past it.
fn closest_visible(ray_in: Ray) -> Hit {
    var ray = ray_in;
    let flags = select(TRACE_FLAGS_NONE, TRACE_PASS_BLEND, SCENE_BLEND);
    var hit = trace_closest_flags(ray, flags);
    for (var i = 0u; i < MAX_CULLED && hit.instance != NO_HIT && primary_culled(hit); i++) {
        // Past the passed triangle: 64 ulps of its distance.
        ray.t_min = blend_past(hit.t);
        hit = trace_closest_flags(ray, flags);
    }
    if hit.instance != NO_HIT && primary_culled(hit) {
        hit.instance = NO_HIT;
    }
    return hit;
}
