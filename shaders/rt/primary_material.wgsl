// Primary rays (common/primary_rays.wgsl) writing the material half of the G-buffer: `material`,
// `emissive` and `lobes` (layers/primary_split.ron, with rt/primary_surface.wgsl).
//#include "common/primary_rays.wgsl"
//#include "common/gbuffer_store_material.wgsl"

// Bindings 0 to 6: the frame and the scene (common/primary_rays.wgsl).
@group(0) @binding(7) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(8) var emissive: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var lobes: texture_storage_2d<rgba32uint, write>;

fn primary_output_size() -> vec2<u32> {
    return textureDimensions(material);
}

// The material half has no instance channel.
fn store_primary_hit(p: vec2<u32>, s: Surface, instance: u32) {
    store_gbuffer_material(p, s);
}

fn store_primary_miss(p: vec2<u32>) {
    store_gbuffer_material_miss(p);
}
