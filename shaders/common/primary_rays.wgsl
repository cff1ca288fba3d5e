// The primary-ray kernel (rt/primary.wgsl, and the two passes of layers/primary_split.ron,
// rt/primary_surface.wgsl and rt/primary_material.wgsl): primary rays through pixel centres
// (the rasterizer's sample positions), closest hit, the G-buffer channels of the Deferred layer
// from the hit, every material input read as the rasterizer reads it (common/surface.wgsl).
// Textures are sampled at the mip level of the pixel's ray cone (its spread: the angle between
// neighbouring pixels' rays), as the rasterizer's derivatives pick. Back faces of single-sided
// materials are culled, as the rasterizer culls them: the ray goes on past them
// (common/primary_hit.wgsl).
// The scene's bindings 0 to 6 come with common/scene_bindings.wgsl; the main shader declares
// the storage textures it writes (from binding 7) and what a pixel stores:
//   fn primary_output_size() -> vec2<u32>           the size of the textures written
//   fn store_primary_hit(p: vec2<u32>, s: Surface, instance: u32)
//                                                    pixel `p` shows surface `s` of instance
//                                                    `instance`
//   fn store_primary_miss(p: vec2<u32>)              pixel `p` shows no geometry (the sky)
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_bindings.wgsl"
//#include "common/scene_textures.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/primary_hit.wgsl"

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = primary_output_size();
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ray = Ray(camera_origin(id.xy), 0.0, camera_dir(id.xy), 3.0e38);
    let hit = closest_visible(ray);
    if hit.instance == NO_HIT {
        store_primary_miss(id.xy);
    } else {
        store_primary_hit(id.xy, surface_at_cone(ray, hit, camera_cone_width(id.xy, hit.t)), hit.instance);
    }
    trace_flush_stats();
}
