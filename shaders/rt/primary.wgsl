// Primary rays through pixel centres (the rasterizer's sample positions), closest hit, the
// G-buffer channels of the Deferred layer from the hit (no normal maps: compute shaders have
// no derivatives for them). Textures are sampled at the mip level of the pixel's ray cone (its
// spread: the angle between neighbouring pixels' rays), as the rasterizer's derivatives pick.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"

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

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(position);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ray = Ray(frame.camera_pos.xyz, 0.0, camera_dir(id.xy), 3.0e38);
    let hit = trace_closest(ray);
    if hit.instance == NO_HIT {
        textureStore(position, id.xy, vec4<f32>(0.0));
        textureStore(normal, id.xy, vec4<f32>(0.0));
        textureStore(geo_normal, id.xy, vec4<f32>(0.0));
        textureStore(albedo, id.xy, vec4<f32>(0.0));
        textureStore(material, id.xy, vec4<f32>(0.0));
    } else {
        let s = surface_at_cone(ray, hit, camera_pixel_spread(id.xy) * hit.t);
        textureStore(position, id.xy, vec4<f32>(s.position, 1.0));
        textureStore(normal, id.xy, vec4<f32>(s.normal, 0.0));
        textureStore(geo_normal, id.xy, vec4<f32>(s.geo_normal, 0.0));
        textureStore(albedo, id.xy, vec4<f32>(s.albedo, 1.0));
        let e = dot(s.emissive, vec3<f32>(0.2126, 0.7152, 0.0722));
        textureStore(material, id.xy, vec4<f32>(s.metallic, s.roughness, min(e / 16.0, 1.0), 1.0));
    }
    trace_flush_stats();
}
