// The direct light at a secondary hit, shared by reflection and GI rays: the hit as a shading
// point seen from direction `v`, and every light with its own shadow ray. Needs
// common/lighting.wgsl, common/surface.wgsl, common/shadow_ray.wgsl, and `scene_lights` and
// `frame` declared by the main shader.

fn hit_shading_point(s: Surface, v: vec3<f32>) -> ShadingPoint {
    var sp: ShadingPoint;
    sp.position = s.position;
    sp.normal = s.normal;
    sp.view = v;
    sp.albedo = s.albedo;
    sp.metallic = s.metallic;
    sp.roughness = s.roughness;
    sp.occlusion = s.occlusion;
    sp.emissive = s.emissive;
    sp.unlit = s.unlit;
    return sp;
}

// The light of every light that reaches hit `s` (one shadow ray each), reflected towards
// `sp.view`.
fn hit_direct_light(s: Surface, sp: ShadingPoint) -> vec3<f32> {
    // With a shadow-terminator offset, the shading normal decides which lights the hit faces,
    // and each light's ray leaves from the part of the offset its angle asks for (as
    // rt/shadow.wgsl).
    let facing = shadow_facing(s.geo_normal, s.normal, s.shadow_offset);
    let flat_origin = offset_ray_origin(s.position, s.geo_normal);
    var direct = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let origin = shadow_ray_origin(flat_origin, s.position, s.geo_normal, s.normal, s.shadow_offset, scene_lights[i]);
        if light_visible(scene_lights[i], origin, facing) {
            direct += light_radiance(sp, light_sample(scene_lights[i], s.position));
        }
    }
    return direct;
}
