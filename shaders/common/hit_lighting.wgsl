// The direct light at a secondary hit, shared by reflection and GI rays and the blended
// surfaces: the hit as a shading point seen from direction `v`, and every light with its own
// shadow ray (or one light picked for all, `hit_light_candidates`); and the BLEND surfaces
// along a ray composited front to back. Needs common/lighting.wgsl, common/sampling.wgsl,
// common/surface.wgsl, common/shadow_ray.wgsl, and `scene_lights`, `scene_materials`,
// `scene_instances` and `frame` declared by the main shader.
//#include "common/light_pick.wgsl"

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
    shading_lobes(&sp, s.lobes);
    return sp;
}

// How hits are lit: 0, every light with its own shadow ray; above 0, one light picked by
// resampling from this many candidates (common/light_pick.wgsl) with one ray, drawn from
// `hit_light_state`. The main shader sets both from its parameters.
var<private> hit_light_candidates: u32 = 0u;
var<private> hit_light_state: u32 = 0u;

// The light of every light that reaches hit `s` (one shadow ray each; or of one picked light,
// `hit_light_candidates`), reflected towards `sp.view`.
fn hit_direct_light(s: Surface, sp: ShadingPoint) -> vec3<f32> {
    // With a shadow-terminator offset, the shading normal decides which lights the hit faces,
    // and each light's ray leaves from the part of the offset its angle asks for (as
    // rt/shadow.wgsl).
    let facing = shadow_facing(s.geo_normal, s.normal, s.shadow_offset);
    let flat_origin = offset_ray_origin(s.position, s.geo_normal);
    // Every light, or the one picked for all of them: one loop, so that the traversal is
    // compiled in once (the compute back-end inlines it at every call).
    let picking = hit_light_candidates > 0u;
    var picked = PickedLight(0u, 1.0);
    if picking {
        var state = hit_light_state;
        picked = pick_light(sp, s.position, hit_light_candidates, &state);
        hit_light_state = state;
    }
    let lights = select(frame.light_count, select(1u, 0u, picked.index == NO_LIGHT), picking);
    var direct = vec3<f32>(0.0);
    for (var k = 0u; k < lights; k++) {
        let i = select(k, picked.index, picking);
        let origin = shadow_ray_origin(flat_origin, s.position, s.geo_normal, s.normal, s.shadow_offset, scene_lights[i]);
        let transmittance = light_transmittance(scene_lights[i], origin, facing);
        if transmittance > 0.0 {
            direct += picked.weight * transmittance * light_radiance(sp, light_sample(scene_lights[i], s.position));
        }
    }
    return direct;
}

// A hit shaded with the model of every mode (common/lighting.wgsl): every light with its own
// shadow ray, sky ambient, emission; seen from direction v.
fn shade_hit(s: Surface, v: vec3<f32>) -> vec3<f32> {
    let sp = hit_shading_point(s, v);
    return surface_radiance(sp, hit_direct_light(s, sp), 1.0);
}

// The translucent surfaces along a ray (BLEND, transmissive), composited front to back:
// `radiance` is what they add (each shaded by shade_hit times its coverage and the
// transmittance in front of it), `transmittance` the share of whatever lies behind them that
// still shows (per channel: a transmissive surface tints what it lets through by its base
// colour), and `hit` the first surface that is neither (or a miss).
struct BlendComposite {
    radiance: vec3<f32>,
    transmittance: vec3<f32>,
    hit: Hit,
}

// Composites the translucent surfaces `ray` meets (common/ray_blend.wgsl: at most BLEND_LAYERS;
// back faces of single-sided materials passed as the rasterizer culls them) until its first
// other surface. `cone_start` and `cone_spread`: the ray cone's width is cone_start + cone_spread x
// distance (textures' mip level, as the ray's own surface takes it).
fn composite_blend(ray_in: Ray, cone_start: f32, cone_spread: f32) -> BlendComposite {
    var ray = ray_in;
    var out = BlendComposite(vec3<f32>(0.0), vec3<f32>(1.0), trace_closest(ray));
    if !SCENE_BLEND {
        return out;
    }
    for (var layer = 0u; layer < BLEND_LAYERS && out.hit.instance != NO_HIT; layer++) {
        let coverage = hit_blend_coverage(out.hit);
        if coverage < 0.0 {
            break;
        }
        let flags = scene_materials[scene_instances[out.hit.instance].material].flags;
        if out.hit.front_face || (flags & MATERIAL_DOUBLE_SIDED) != 0u {
            let s = surface_at_cone(ray, out.hit, cone_start + cone_spread * out.hit.t);
            let c = min(coverage, 1.0);
            out.radiance += out.transmittance * c * shade_hit(s, -ray.dir);
            let tint = select(vec3<f32>(1.0), s.albedo, (flags & MATERIAL_TRANSMISSION) != 0u);
            out.transmittance *= (1.0 - c) * tint;
        }
        ray.t_min = blend_past(out.hit.t);
        out.hit = trace_closest(ray);
    }
    return out;
}
