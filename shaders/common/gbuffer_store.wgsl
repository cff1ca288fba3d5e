// The G-buffer channels of a surface, written by compute passes (primary rays, rt/primary.wgsl;
// the rasterizer's visibility buffer, deferred/gbuffer.wgsl) as the Deferred layer declares
// them. Needs the main shader to declare the storage textures `position`, `normal`,
// `geo_normal`, `albedo`, `material` and `emissive`, and to include common/surface.wgsl.

// Pixel `p` shows surface `s` of scene instance `instance`: the position's w is the instance
// + 1 (0 is the sky), which the motion layer reads.
fn store_gbuffer(p: vec2<u32>, s: Surface, instance: u32) {
    textureStore(position, p, vec4<f32>(s.position, f32(instance + 1u)));
    textureStore(normal, p, vec4<f32>(s.normal, 0.0));
    textureStore(geo_normal, p, vec4<f32>(s.geo_normal, 0.0));
    textureStore(albedo, p, vec4<f32>(s.albedo, 1.0));
    let e = dot(s.emissive, vec3<f32>(0.2126, 0.7152, 0.0722));
    textureStore(material, p, vec4<f32>(s.metallic, s.roughness, min(e / 16.0, 1.0), 1.0));
    textureStore(emissive, p, vec4<f32>(s.emissive, s.occlusion));
}

// Pixel `p` shows no geometry (the sky).
fn store_gbuffer_miss(p: vec2<u32>) {
    textureStore(position, p, vec4<f32>(0.0));
    textureStore(normal, p, vec4<f32>(0.0));
    textureStore(geo_normal, p, vec4<f32>(0.0));
    textureStore(albedo, p, vec4<f32>(0.0));
    textureStore(material, p, vec4<f32>(0.0));
    textureStore(emissive, p, vec4<f32>(0.0));
}
