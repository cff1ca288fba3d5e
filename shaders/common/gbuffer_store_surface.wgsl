// The surface half of the G-buffer (common/gbuffer_store.wgsl): `position`, `normal`,
// `geo_normal` and `albedo`, storage textures the main shader declares.

// Pixel `p` shows surface `s` of scene instance `instance`: the position's w is the instance
// + 1 (0 is the sky), which the motion layer reads.
fn store_gbuffer_surface(p: vec2<u32>, s: Surface, instance: u32) {
    textureStore(position, p, vec4<f32>(s.position, f32(instance + 1u)));
    textureStore(normal, p, vec4<f32>(s.normal, 0.0));
    // w: how far shadow rays leave above the surface (the shadow-terminator offset).
    textureStore(geo_normal, p, vec4<f32>(s.geo_normal, s.shadow_offset));
    textureStore(albedo, p, vec4<f32>(s.albedo, 1.0));
}

fn store_gbuffer_surface_miss(p: vec2<u32>) {
    textureStore(position, p, vec4<f32>(0.0));
    textureStore(normal, p, vec4<f32>(0.0));
    textureStore(geo_normal, p, vec4<f32>(0.0));
    textureStore(albedo, p, vec4<f32>(0.0));
}
