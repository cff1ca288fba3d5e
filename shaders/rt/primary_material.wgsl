// Primary rays (rt/primary.wgsl) writing the material half of the G-buffer: `material`,
// `emissive` (layers/primary_split.ron, with rt/primary_surface.wgsl).
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/primary_hit.wgsl"
//#include "common/gbuffer_store_material.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(4) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(6) var linear_sampler: sampler;
@group(0) @binding(7) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(8) var emissive: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var lobes: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(material);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ray = Ray(camera_origin(id.xy), 0.0, camera_dir(id.xy), 3.0e38);
    let hit = closest_visible(ray);
    if hit.instance == NO_HIT {
        store_gbuffer_material_miss(id.xy);
    } else {
        store_gbuffer_material(id.xy, surface_at_cone(ray, hit, camera_cone_width(id.xy, hit.t)));
    }
    trace_flush_stats();
}
