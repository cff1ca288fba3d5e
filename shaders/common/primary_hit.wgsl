// The closest surface a primary ray sees, back faces of single-sided materials culled as the
// rasterizer culls them (rt/primary.wgsl, and the two passes of layers/primary_split.ron).
// Needs the main shader to declare the scene's instances and materials and to include
// trace/trace.wgsl.

// How many culled back faces a primary ray passes before it gives up (a miss).
const MAX_CULLED: u32 = 16u;

// The closest hit that is not a back face of a single-sided material.
fn closest_visible(ray_in: Ray) -> Hit {
    var ray = ray_in;
    var hit = trace_closest(ray);
    for (var i = 0u; i < MAX_CULLED && hit.instance != NO_HIT && !hit.front_face; i++) {
        if (scene_materials[scene_instances[hit.instance].material].flags & MATERIAL_DOUBLE_SIDED) != 0u {
            break;
        }
        // Past the culled triangle: 64 ulps of its distance.
        ray.t_min = bitcast<f32>(bitcast<u32>(hit.t) + 64u);
        hit = trace_closest(ray);
    }
    if hit.instance != NO_HIT && !hit.front_face && (scene_materials[scene_instances[hit.instance].material].flags & MATERIAL_DOUBLE_SIDED) == 0u {
        hit.instance = NO_HIT;
    }
    return hit;
}
