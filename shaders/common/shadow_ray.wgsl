// One shadow ray per light, shared by rt/shadow.wgsl and the reflection hits. Needs
// common/lighting.wgsl and trace/trace.wgsl.

// Whether `light` reaches `origin` (a ray origin already offset from a surface with geometric
// normal `geo`): false where the surface faces away, the light's range or cone does not reach,
// or an any-hit ray finds an occluder (stopping just short of a point or spot light: nothing
// behind it can shadow).
fn light_visible(light: Light, origin: vec3<f32>, geo: vec3<f32>) -> bool {
    let ls = light_sample(light, origin);
    if dot(geo, ls.l) <= 0.0 || all(ls.e == vec3<f32>(0.0)) {
        return false;
    }
    let t_max = select(ls.distance * 0.9999, ls.distance, light.kind == LIGHT_DIRECTIONAL);
    return !trace_any(Ray(origin, 0.0, ls.l, t_max));
}
