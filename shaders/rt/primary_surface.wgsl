// Primary rays (common/primary_rays.wgsl) writing the surface half of the G-buffer: `position`,
// `normal`, `geo_normal`, `albedo`. With rt/primary_material.wgsl, the primary rays of a device
// with fewer than the six storage textures per stage rt/primary.wgsl writes
// (layers/primary_split.ron): each pass traces the same rays.
//#include "common/primary_rays.wgsl"
//#include "common/gbuffer_store_surface.wgsl"

// Bindings 0 to 6: the frame and the scene (common/primary_rays.wgsl).
@group(0) @binding(7) var position: texture_storage_2d<rgba32float, write>;
@group(0) @binding(8) var normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var geo_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var albedo: texture_storage_2d<rgba8unorm, write>;

fn primary_output_size() -> vec2<u32> {
    return textureDimensions(position);
}

fn store_primary_hit(p: vec2<u32>, s: Surface, instance: u32) {
    store_gbuffer_surface(p, s, instance);
}

fn store_primary_miss(p: vec2<u32>) {
    store_gbuffer_surface_miss(p);
}
