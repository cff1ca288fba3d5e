// ReSTIR DI, spatial reuse (common/restir.wgsl): each pixel's reservoir combined
// with those of `spatial_samples` random pixels within `spatial_radius` whose surfaces are
// alike (normals within 25 degrees, depths within 10%), each weighted by the generalised
// balance heuristic over the surfaces (a sample's share is its surface's M x what its light
// brings there over the sum over every surface's: a neighbour's sample that is dim there and
// bright here does not count for more than it is worth, as the M-normalised sum lets it; with
// that sum the reservoirs' W grew without bound over the frames in tests/restir.rs). The combined
// reservoir is kept for the next frame's temporal reuse (as it is: keeping W = 0 where the
// shading pass's ray is blocked moved tests/restir.rs's mean from +1.5% to -2.2%, the noise
// unchanged) and shaded by rt/restir_shade.wgsl.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/lighting.wgsl"
//#include "common/scene.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/sampling.wgsl"
//#include "common/emitters.wgsl"
//#include "common/restir_bindings.wgsl"
//#include "common/restir.wgsl"

@group(0) @binding(12) var temporal: texture_2d<u32>;
@group(0) @binding(13) var reservoirs: texture_storage_2d<rgba32uint, write>;
// The same, for rt/restir_shade.wgsl (layers/restir_di.ron says why).
@group(0) @binding(14) var kept: texture_storage_2d<rgba32uint, write>;

// Whether the surface at `q` is alike enough to `at`'s for its reservoir to be reused.
fn alike(at: RestirSurface, q: vec2<u32>) -> bool {
    let p = textureLoad(position, q, 0);
    if p.w == 0.0 {
        return false;
    }
    let n = normalize(textureLoad(normal, q, 0).xyz);
    let depth = distance(frame.camera_pos.xyz, at.s.position);
    return dot(n, at.s.normal) > 0.906 && abs(distance(frame.camera_pos.xyz, p.xyz) - depth) < 0.1 * depth;
}

// Most neighbours a pixel reuses (the layer's `spatial_samples` maximum).
const MOST_NEIGHBOURS: u32 = 8u;

// The pixel's own reservoir and its alike neighbours', with their surfaces' positions, normals
// and the luminance of their albedos (0 where unlit), for the balance heuristic's weights.
// Private variables, not a struct handed to functions: its copies at each call, indexed in
// loops, cost 14 ms at 2560x1440 on the H200.
var<private> reuse_reservoirs: array<Reservoir, 9>;
var<private> reuse_positions: array<vec3<f32>, 9>;
var<private> reuse_normals: array<vec3<f32>, 9>;
var<private> reuse_reflectances: array<f32, 9>;
var<private> reuse_count: u32;

// The luminance of the diffuse albedo at `q` (the albedo less its metallic share), 0 where the
// surface is unlit.
fn reflectance(q: vec2<u32>) -> f32 {
    let m = textureLoad(material, q, 0);
    return select(restir_luminance(textureLoad(albedo, q, 0).rgb) * (1.0 - m.r), 0.0, gbuffer_unlit(m.a));
}

fn gather(at: RestirSurface, id: vec2<u32>, size: vec2<u32>, state: ptr<function, u32>) {
    reuse_reservoirs[0] = reservoir_unpack(textureLoad(temporal, id, 0));
    reuse_positions[0] = at.s.position;
    reuse_normals[0] = at.s.normal;
    reuse_count = 1u;
    for (var k = 0u; k < min(params.spatial_samples, MOST_NEIGHBOURS); k++) {
        let offset = (next_random2(state) * 2.0 - 1.0) * params.spatial_radius;
        let q = vec2<i32>(vec2<f32>(id) + offset);
        if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size)) || all(vec2<u32>(q) == id) || !alike(at, vec2<u32>(q)) {
            continue;
        }
        reuse_reservoirs[reuse_count] = reservoir_unpack(textureLoad(temporal, q, 0));
        reuse_positions[reuse_count] = textureLoad(position, q, 0).xyz;
        reuse_normals[reuse_count] = normalize(textureLoad(normal, q, 0).xyz);
        reuse_reflectances[reuse_count] = reflectance(vec2<u32>(q));
        reuse_count += 1u;
    }
}

// The balance heuristic's weight of gathered sample `i` among the surfaces: M_i x g_i over
// the sum of M_j x g_j, where g_j is the luminance of the irradiance the sample's light would
// bring surface j (its position and normal, no shadows) times its diffuse albedo's luminance (a
// Lambert stand-in for its BRDF: 0 where the target is 0 on black and unlit surfaces), and for
// the pixel itself (j = 0) its full target `here`. The weights of the surfaces sum to one
// whatever g is, so a cheap stand-in for the neighbours' targets keeps the combination's
// normalisation. Where it is far above a neighbour's target, that neighbour's rare samples
// weigh as if it drew them often: fireflies (the albedo without the metallic share, on the
// helmet's metal under a map, whose diffuse light is its target there: relMSE 98 against 0.09
// trimmed); where it is 0 and the target is not (a metal's or a black surface's specular lobe),
// that neighbour's samples are left out, which costs noise, not the mean. The estimate shifts (tests/emissive_lights.rs, the emissive disk beside its black occluder:
// the floor's mean deviation -0.0032 with this stand-in, -0.0046 with the irradiance alone,
// -0.0016 with every surface's full target, which cost 11 ms at 2560x1440 on the H200).
fn balance_weight(i: u32, here: f32) -> f32 {
    let r = reuse_reservoirs[i];
    // The pixel itself by its full target (which the caller has).
    var all_surfaces = reuse_reservoirs[0].count * here;
    var own = select(0.0, all_surfaces, i == 0u);
    if r.light == RESTIR_ENVIRONMENT {
        let l = restir_environment_direction(r.uv);
        let radiance = restir_luminance(environment_radiance(l)) / PI;
        for (var j = 1u; j < reuse_count; j++) {
            let g = reuse_reservoirs[j].count * reuse_reflectances[j] * radiance * max(dot(reuse_normals[j], l), 0.0);
            all_surfaces += g;
            own = select(own, g, j == i);
        }
    } else if restir_is_punctual(r.light) {
        let light = scene_lights[r.light];
        for (var j = 1u; j < reuse_count; j++) {
            let ls = light_sample(light, reuse_positions[j]);
            let g = reuse_reservoirs[j].count * reuse_reflectances[j] * restir_luminance(ls.e) * max(dot(reuse_normals[j], ls.l), 0.0);
            all_surfaces += g;
            own = select(own, g, j == i);
        }
    } else {
        let t = emitter_triangle(r.light & (RESTIR_EMITTER - 1u));
        let x = emitter_point(t, r.uv);
        let facing = normalize(t.normal);
        let radiance = restir_luminance(t.emission);
        for (var j = 1u; j < reuse_count; j++) {
            let to = x - reuse_positions[j];
            let d2 = max(dot(to, to), 1e-12);
            let l = to * inverseSqrt(d2);
            let g = reuse_reservoirs[j].count * reuse_reflectances[j] * radiance * abs(dot(l, facing)) / d2 * max(dot(reuse_normals[j], l), 0.0);
            all_surfaces += g;
            own = select(own, g, j == i);
        }
    }
    return select(0.0, own / all_surfaces, all_surfaces > 0.0);
}

// The gathered reservoirs resampled into one for the pixel: sample i's weight is its
// balance-heuristic weight x its target here x its W; W = the summed weights over the kept
// sample's target here.
fn combine(at: RestirSurface, state: ptr<function, u32>) -> Reservoir {
    var stream = restir_stream();
    for (var i = 0u; i < reuse_count; i++) {
        let r = reuse_reservoirs[i];
        stream.count += r.count;
        if r.light == RESTIR_NONE || r.weight <= 0.0 {
            continue;
        }
        let here = restir_target(at, r.light, r.uv);
        let w = balance_weight(i, here) * here * r.weight;
        if w > 0.0 {
            stream.weight_sum += w;
            if next_random1(state) * stream.weight_sum < w {
                stream.picked = r;
                stream.picked_target = here;
            }
        }
    }
    var out = stream.picked;
    out.count = stream.count;
    out.weight = select(0.0, stream.weight_sum / stream.picked_target, stream.picked_target > 0.0);
    if out.weight == 0.0 {
        out.light = RESTIR_NONE;
    }
    return out;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(reservoirs);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let at = restir_surface(id.xy);
    var r = reservoir_empty();
    if at.valid {
        var state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(0x85ebca6bu ^ frame_seed(params.seed, frame.frame_index, params.per_frame))));
        gather(at, id.xy, size, &state);
        r = combine(at, &state);
    }
    textureStore(reservoirs, id.xy, reservoir_pack(r));
    textureStore(kept, id.xy, reservoir_pack(r));
}
