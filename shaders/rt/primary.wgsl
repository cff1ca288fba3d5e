// Primary rays through pixel centres (the rasterizer's sample positions), closest hit, the
// G-buffer channels of the Deferred layer from the hit, every material input read as the
// rasterizer reads it (common/surface.wgsl). Textures are sampled at the mip level of the
// pixel's ray cone (its spread: the angle between neighbouring pixels' rays), as the
// rasterizer's derivatives pick. Back faces of single-sided materials are culled, as the
// rasterizer culls them: the ray goes on past them.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/gbuffer_store.wgsl"
//#include "common/primary_hit.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(4) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(6) var linear_sampler: sampler;
@group(0) @binding(7) var position: texture_storage_2d<rgba32float, write>;
@group(0) @binding(8) var normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var geo_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var albedo: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(11) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(12) var emissive: texture_storage_2d<rgba16float, write>;
@group(0) @binding(13) var lobes: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(position);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ray = Ray(camera_origin(id.xy), 0.0, camera_dir(id.xy), 3.0e38);
    let hit = closest_visible(ray);
    if hit.instance == NO_HIT {
        store_gbuffer_miss(id.xy);
    } else {
        store_gbuffer(id.xy, surface_at_cone(ray, hit, camera_cone_width(id.xy, hit.t)), hit.instance);
    }
    trace_flush_stats();
}
