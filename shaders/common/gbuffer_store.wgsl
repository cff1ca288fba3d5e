// The G-buffer channels of a surface, written by compute passes (primary rays, rt/primary.wgsl;
// the rasterizer's visibility buffer, deferred/gbuffer.wgsl) as the Deferred layer declares
// them. Needs the main shader to declare the storage textures `position`, `normal`,
// `geo_normal`, `albedo`, `material` and `emissive`, and to include common/surface.wgsl.
// The two halves are written separately by the primary rays of devices with fewer than six
// storage textures per stage (layers/primary_split.ron).
//#include "common/gbuffer_store_surface.wgsl"
//#include "common/gbuffer_store_material.wgsl"

// Pixel `p` shows surface `s` of scene instance `instance`.
fn store_gbuffer(p: vec2<u32>, s: Surface, instance: u32) {
    store_gbuffer_surface(p, s, instance);
    store_gbuffer_material(p, s);
}

// Pixel `p` shows no geometry (the sky).
fn store_gbuffer_miss(p: vec2<u32>) {
    store_gbuffer_surface_miss(p);
    store_gbuffer_material_miss(p);
}
