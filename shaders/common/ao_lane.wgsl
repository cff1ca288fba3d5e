// One lane of a pixel's AO rays (layers/rt_ao.ron and its variants): lane k of `lanes`
// traces rays k, k + lanes, ... (in rounds: every lane runs the same number, so the lanes of a
// subgroup trace together) from the offset position `p` along `n`, and returns how much of
// them got through, added in ray order. Every schedule (rt/ao.wgsl, rt/ao_items.wgsl,
// rt/ao_persistent.wgsl, rt/ao_spread.wgsl) calls this, so a (pixel, lane, lanes) gives the
// same bits whoever runs it, and a ray its own samples whatever the lane count.
// The includer declares `frame` (common/frame.wgsl) and `params` (common/ao_params.wgsl).
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/ray_blend.wgsl"
//#include "common/ao_params.wgsl"

fn ao_lane_open(pixel: vec2<u32>, lane: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return ao_lane_open_of(pixel, lane, AO_LANES, p, n);
}

fn ao_lane_open_of(pixel: vec2<u32>, lane: u32, lanes: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let origin = offset_ray_origin(p, n);
    let range = params.range + params.range_scale * frame.scene_sphere.w;
    // Every ray of the lane stays within `range` of `origin`: they start together below the
    // root (trace/common.wgsl).
    let start = trace_start_within(origin, range);
    let rotation = pixel_random2(pixel, params.seed);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    var state = pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(params.seed + 0x9e3779b9u + frame_offset * 0x85ebca6bu)));
    // Each ray counts by how much of it gets through: 1 or 0, or the transmittance of the
    // BLEND surfaces it meets (common/ray_blend.wgsl).
    var open = 0.0;
    let rounds = (params.rays + lanes - 1u) / lanes;
    for (var round = 0u; round < rounds; round++) {
        let i = round * lanes + lane;
        var u: vec2<f32>;
        if params.sampling == 0u {
            // One stream per pixel, drawn in ray order by every lane: each ray keeps its
            // numbers (lane k takes the k-th of each `lanes` draws).
            for (var k = 0u; k < lanes; k++) {
                let drawn = next_random2(&state);
                if k == lane {
                    u = drawn;
                }
            }
        } else {
            u = fract(r2_sample(i + frame_offset * params.rays) + rotation);
        }
        if i < params.rays {
            open += trace_transmittance_within(Ray(origin, 0.0, cosine_hemisphere(n, u), range), start, TRACE_FLAGS_NONE);
        }
    }
    return open;
}

// The texel of `partial` (twice the frame in each axis) that holds lane `lane` of `pixel`:
// (2x + i, 2y + j) for lane i + 2j.
fn ao_partial_texel(pixel: vec2<u32>, lane: u32) -> vec2<u32> {
    return 2u * pixel + vec2<u32>(lane & 1u, lane >> 1u);
}
