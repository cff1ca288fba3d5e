// The shadow ray of a ReSTIR DI sample (common/restir.wgsl), for the passes that trace
// (rt/restir_initial.wgsl, rt/restir_spatial.wgsl). Needs common/shadow_ray.wgsl and the trace
// module.

// Whether the shadow ray from `at` to a sample reaches it (its BLEND surfaces' transmittance).
fn restir_visibility(at: RestirSurface, light: u32, toward: RestirLight) -> f32 {
    if restir_is_punctual(light) {
        let origin = shadow_ray_origin(at.flat_origin, at.s.position, at.geo, at.s.normal, at.offset, scene_lights[light]);
        return light_transmittance(scene_lights[light], origin, at.facing);
    }
    return trace_transmittance(Ray(at.flat_origin, 0.0, toward.l, toward.distance * 0.9999));
}
