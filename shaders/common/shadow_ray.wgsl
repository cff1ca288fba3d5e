// One shadow ray per light, shared by rt/shadow.wgsl and the reflection hits; BLEND surfaces
// on it let part of the light through (common/ray_blend.wgsl). Needs common/lighting.wgsl,
// common/sampling.wgsl and trace/trace.wgsl.
//#include "common/ray_offset.wgsl"
//#include "common/ray_blend.wgsl"

// How much of the shadow-terminator offset `offset` (common/material_inputs.wgsl) a shadow ray
// towards `l` leaves from, for shading normal `n` and geometric normal `geo`: all of it where the
// light grazes the surface, none where it stands well above it, with the cutoff 0.1 and the
// blend of Cycles' `shadow_ray_offset` (so contact shadows away from the terminator keep their
// origin on the triangle).
fn terminator_lift(offset: f32, n: vec3<f32>, geo: vec3<f32>, l: vec3<f32>) -> f32 {
    if offset <= 0.0 {
        return 0.0;
    }
    let nl = dot(n, l);
    let ngl = dot(geo, l);
    let amount = select(clamp(1.0 - ngl / 0.1, 0.0, 1.0), clamp(2.0 - (ngl + nl) / 0.1, 0.0, 1.0), nl < 0.1);
    return offset * amount;
}

// Where the shadow ray towards `light` leaves a surface point `p` (geometric normal `geo`,
// shading normal `n`, shadow-terminator offset `offset`): `flat`, the point's usual origin
// (offset_ray_origin(p, geo), made once per point), where there is no offset; else lifted by
// the part of the offset the light's angle asks for.
fn shadow_ray_origin(flat: vec3<f32>, p: vec3<f32>, geo: vec3<f32>, n: vec3<f32>, offset: f32, light: Light) -> vec3<f32> {
    if offset <= 0.0 {
        return flat;
    }
    let lift = terminator_lift(offset, n, geo, light_sample(light, p).l);
    return offset_ray_origin(p + geo * lift, geo);
}

// The normal that decides which lights a surface point faces: the shading normal `n` where a
// shadow-terminator offset lifts its rays, else the geometric normal `geo`.
fn shadow_facing(geo: vec3<f32>, n: vec3<f32>, offset: f32) -> vec3<f32> {
    return select(geo, n, offset > 0.0);
}

// How much of `light` reaches `origin` (a ray origin already offset from a surface whose facing
// normal is `geo`: the geometric normal, or the shading normal where the shadow-terminator
// offset lifts the origin), 0 to 1: 0 where the surface faces away, the light's range or cone
// does not reach, or the ray finds an opaque occluder (stopping just short of a point or spot
// light: nothing behind it can shadow); else the transmittance of the BLEND surfaces on the
// way (1 without any).
fn light_transmittance(light: Light, origin: vec3<f32>, geo: vec3<f32>) -> f32 {
    let ls = light_sample(light, origin);
    if dot(geo, ls.l) <= 0.0 || all(ls.e == vec3<f32>(0.0)) {
        return 0.0;
    }
    let t_max = select(ls.distance * 0.9999, ls.distance, light.kind == LIGHT_DIRECTIONAL);
    return trace_transmittance(Ray(origin, 0.0, ls.l, t_max));
}

// The sizes of the area lights (rt_shadow's parameters): `radius` of the sphere of point and
// spot lights, or a `width` x `height` rectangle (both above 0; the rectangle wins) centred on
// them and facing along their direction, its width along the horizontal axis perpendicular to
// that direction (world x for a light pointing straight up or down) and its height along the
// third axis; `sun_radius`, the angular radius of directional lights (radians).
struct AreaLights {
    radius: f32,
    sun_radius: f32,
    width: f32,
    height: f32,
}

// The rectangle's width and height axes for a light shining along `d` (see `AreaLights`).
fn rectangle_axes(d: vec3<f32>) -> array<vec3<f32>, 2> {
    let w = select(normalize(cross(vec3<f32>(0.0, 1.0, 0.0), d)), vec3<f32>(1.0, 0.0, 0.0), abs(d.y) > 0.9999);
    return array<vec3<f32>, 2>(w, cross(d, w));
}

// How much of the light along the ray from `origin` to one point of an area light reaches it
// (0 to 1, as light_transmittance): for a directional
// light a direction uniform in the cone of angular radius `sun_radius` around it; for a point
// or spot light a point uniform on its rectangle (which shines only forwards, along the
// light's direction) or else on the disc of radius `radius` around it facing the origin (a
// sphere light seen from there); chosen by the uniform numbers `u`. With every size 0 it is
// `light_transmittance`'s ray.
fn area_light_transmittance(light: Light, origin: vec3<f32>, geo: vec3<f32>, area: AreaLights, u: vec2<f32>) -> f32 {
    let ls = light_sample(light, origin);
    if all(ls.e == vec3<f32>(0.0)) {
        return 0.0;
    }
    if light.kind == LIGHT_DIRECTIONAL {
        let l = select(ls.l, uniform_cone(ls.l, cos(area.sun_radius), u), area.sun_radius > 0.0);
        if dot(geo, l) <= 0.0 {
            return 0.0;
        }
        return trace_transmittance(Ray(origin, 0.0, l, ls.distance));
    }
    var aim = light.position + area.radius * uniform_disc(ls.l, u);
    var sized = area.radius > 0.0;
    if area.width > 0.0 && area.height > 0.0 {
        let axes = rectangle_axes(light.direction);
        aim = light.position + (u.x - 0.5) * area.width * axes[0] + (u.y - 0.5) * area.height * axes[1];
        sized = true;
        if dot(origin - aim, light.direction) <= 0.0 {
            return 0.0; // behind the rectangle
        }
    }
    let to_aim = aim - origin;
    let d = length(to_aim);
    let l = select(ls.l, to_aim / d, sized);
    let t_max = select(ls.distance, d, sized) * 0.9999;
    if dot(geo, l) <= 0.0 {
        return 0.0;
    }
    return trace_transmittance(Ray(origin, 0.0, l, t_max));
}
