// ReSTIR DI, first pass (common/restir.wgsl): per pixel, `params.candidates` light samples
// (punctual lights drawn uniformly, emitter points by power, directions of the environment map
// from its alias table; an equal share of each source the scene has) resampled into one reservoir by the luminance of their unshadowed light; then, with
// `visibility_reuse`, its sample's shadow ray: a blocked sample's W is 0 before any reuse.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/lighting.wgsl"
//#include "common/scene.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/emitters.wgsl"
//#include "common/environment_sampling.wgsl"
//#include "common/restir_bindings.wgsl"
//#include "common/restir.wgsl"
//#include "common/restir_visibility.wgsl"

@group(0) @binding(12) var candidates: texture_storage_2d<rgba32uint, write>;

// A candidate from the mixture of the sources present (each an equal share), with its density
// there (area measure for an emitter point, solid angle for a direction of the map).
struct Candidate {
    light: u32,
    uv: vec2<f32>,
    density: f32,
}

fn draw_candidate(state: ptr<function, u32>) -> Candidate {
    let lights = frame.light_count;
    let emitters = emitter_count();
    let sources = select(0u, 1u, lights > 0u) + select(0u, 1u, emitters > 0u) + select(0u, 1u, restir_environment());
    let share = 1.0 / f32(max(sources, 1u));
    let u = next_random1(state);
    let punctual_share = select(0.0, share, lights > 0u);
    let emitter_share = select(0.0, share, emitters > 0u);
    if u < punctual_share {
        let i = min(u32(next_random1(state) * f32(lights)), lights - 1u);
        return Candidate(i, vec2<f32>(0.0), share / f32(lights));
    }
    if u < punctual_share + emitter_share {
        let i = emitter_pick(next_random1(state));
        let uv = uniform_barycentrics(next_random2(state));
        let area = 0.5 * length(emitter_triangle(i).normal);
        return Candidate(i | RESTIR_EMITTER, uv, share * emitter_probability(i) / max(area, 1e-30));
    }
    let e = environment_sample(vec3<f32>(next_random2(state), next_random1(state)));
    return Candidate(RESTIR_ENVIRONMENT, octahedral_encode(e.dir) * 0.5 + 0.5, share * e.pdf);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(candidates);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let at = restir_surface(id.xy);
    var r = reservoir_empty();
    if at.valid && (frame.light_count > 0u || emitter_count() > 0u || restir_environment()) {
        var state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(frame_seed(params.seed, frame.frame_index, params.per_frame))));
        var stream = restir_stream();
        for (var k = 0u; k < params.candidates; k++) {
            let c = draw_candidate(&state);
            let goal = restir_target(at, c.light, c.uv);
            // As a reservoir of one candidate: W = 1 / density.
            var one = reservoir_empty();
            if c.density > 0.0 {
                one = Reservoir(c.light, c.uv, 1.0 / c.density, 1.0);
            }
            restir_offer(&stream, one, goal, 1.0, next_random1(&state));
        }
        r = restir_finish(stream);
        if params.visibility_reuse != 0u && r.light != RESTIR_NONE {
            let toward = restir_light(at, r.light, r.uv);
            if restir_visibility(at, r.light, toward) <= 0.0 {
                r.weight = 0.0;
                r.light = RESTIR_NONE;
            }
        }
    }
    textureStore(candidates, id.xy, reservoir_pack(r));
    trace_flush_stats();
}
