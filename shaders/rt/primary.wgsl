// Primary rays writing every G-buffer channel of the Deferred layer in one pass
// (common/primary_rays.wgsl: the kernel, its rays and the surfaces they see).
//#include "common/primary_rays.wgsl"
//#include "common/gbuffer_store.wgsl"

// Bindings 0 to 6: the frame and the scene (common/primary_rays.wgsl).
@group(0) @binding(7) var position: texture_storage_2d<rgba32float, write>;
@group(0) @binding(8) var normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var geo_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var albedo: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(11) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(12) var emissive: texture_storage_2d<rgba16float, write>;
@group(0) @binding(13) var lobes: texture_storage_2d<rgba32uint, write>;

fn primary_output_size() -> vec2<u32> {
    return textureDimensions(position);
}

fn store_primary_hit(p: vec2<u32>, s: Surface, instance: u32) {
    store_gbuffer(p, s, instance);
}

fn store_primary_miss(p: vec2<u32>) {
    store_gbuffer_miss(p);
}
