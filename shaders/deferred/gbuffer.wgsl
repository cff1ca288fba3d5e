// The Deferred layer's G-buffer from the rasterizer's visibility buffer
// (visibility/visibility.wgsl): per pixel, the camera ray through the pixel centre meets the
// triangle kept there (common/visible_hit.wgsl), and the surface at that hit is written as
// primary rays write theirs (common/primary_rays.wgsl, common/surface.wgsl: every material
// input, textures at the mip level of the pixel's ray cone). Hybrid and full ray tracing then
// differ only in which triangle each pixel shows. `deferred/deferred.wgsl` writes the same
// channels in the fragment stage.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_bindings.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/surface.wgsl"
//#include "common/visible_hit.wgsl"
//#include "common/gbuffer_store.wgsl"

// Bindings 0 to 6: the frame and the scene (common/scene_bindings.wgsl).
@group(0) @binding(7) var visibility: texture_2d<u32>;
@group(0) @binding(8) var position: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var geo_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var albedo: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(12) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(13) var emissive: texture_storage_2d<rgba16float, write>;
@group(0) @binding(14) var lobes: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(position);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let seen = visible_decode(textureLoad(visibility, id.xy, 0).xy);
    if !seen.drawn {
        store_gbuffer_miss(id.xy);
        return;
    }
    store_gbuffer(id.xy, visible_surface(id.xy, seen), seen.instance);
}
