// One shadow ray per light, shared by rt/shadow.wgsl and the reflection hits. Needs
// common/lighting.wgsl, common/sampling.wgsl and trace/trace.wgsl.

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

// Whether the ray from `origin` to one point of an area light reaches it: for a directional
// light a direction uniform in the cone of angular radius `sun_radius` (radians) around it,
// for a point or spot light a point uniform on the disc of radius `radius` around it facing
// the origin (a sphere light seen from there), chosen by the uniform numbers `u`. With both
// sizes 0 it is `light_visible`'s ray.
fn area_light_visible(light: Light, origin: vec3<f32>, geo: vec3<f32>, radius: f32, sun_radius: f32, u: vec2<f32>) -> bool {
    let ls = light_sample(light, origin);
    if all(ls.e == vec3<f32>(0.0)) {
        return false;
    }
    if light.kind == LIGHT_DIRECTIONAL {
        let l = select(ls.l, uniform_cone(ls.l, cos(sun_radius), u), sun_radius > 0.0);
        return dot(geo, l) > 0.0 && !trace_any(Ray(origin, 0.0, l, ls.distance));
    }
    let aim = light.position + radius * uniform_disc(ls.l, u);
    let to_aim = aim - origin;
    let d = length(to_aim);
    let l = select(ls.l, to_aim / d, radius > 0.0);
    let t_max = select(ls.distance, d, radius > 0.0) * 0.9999;
    return dot(geo, l) > 0.0 && !trace_any(Ray(origin, 0.0, l, t_max));
}
