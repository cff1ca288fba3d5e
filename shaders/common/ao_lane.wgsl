// One lane of a pixel's AO rays (layers/rt_ao.ron and its variants): lane k of `lanes`
// traces rays k, k + lanes, ... (one batch, trace/ray_batch.wgsl) from the offset position `p` along `n`, and returns how much of
// them got through, added in ray order. Every schedule (rt/ao.wgsl, rt/ao_items.wgsl,
// rt/ao_persistent.wgsl, rt/ao_spread.wgsl) calls this, so a (pixel, lane, lanes) gives the
// same bits whoever runs it, and a ray its own samples whatever the lane count.
// The includer declares `frame` (common/frame.wgsl) and `params` (common/ao_params.wgsl).
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "trace/ray_batch.wgsl"
//#include "common/ray_blend.wgsl"
//#include "common/ao_params.wgsl"

fn ao_lane_open(pixel: vec2<u32>, lane: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return ao_lane_open_of(pixel, lane, AO_LANES, p, n);
}

fn ao_lane_open_of(pixel: vec2<u32>, lane: u32, lanes: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let origin = offset_ray_origin(p, n);
    let range = params.range + params.range_scale * frame.scene_sphere.w;
    // Every ray of the lane stays within `range` of `origin`: they start together below the
    // root (trace/common.wgsl), and are traced as one batch (trace/ray_batch.wgsl), whose
    // directions trace_batch_direction draws.
    let start = trace_start_within(origin, range);
    ao_batch_rotation = pixel_random2(pixel, params.seed);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    ao_batch_frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    ao_batch_state = pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(params.seed + 0x9e3779b9u + ao_batch_frame_offset * 0x85ebca6bu)));
    ao_batch_lane = lane;
    ao_batch_lanes = lanes;
    ao_batch_normal = n;
    // Each ray counts by how much of it gets through: 1 or 0, or the transmittance of the
    // BLEND surfaces it meets (common/ray_blend.wgsl). The lane's rays are rounds 0..count of
    // rays lane, lane + lanes, ...
    let count = select(0u, (params.rays - lane + lanes - 1u) / lanes, params.rays > lane);
    return trace_transmittance_batch_within(origin, range, start, count, TRACE_FLAGS_NONE);
}

// The lane's sampling state, set by ao_lane_open_of for trace_batch_direction.
var<private> ao_batch_state: u32;
var<private> ao_batch_rotation: vec2<f32>;
var<private> ao_batch_frame_offset: u32;
var<private> ao_batch_lane: u32;
var<private> ao_batch_lanes: u32;
var<private> ao_batch_normal: vec3<f32>;

// The direction of the lane's ray of round `round` (ray round x lanes + lane), called for
// rounds 0, 1, ... in order by the batch.
fn trace_batch_direction(round: u32) -> vec3<f32> {
    var u: vec2<f32>;
    if params.sampling == 0u {
        // One stream per pixel, drawn in ray order by every lane: each ray keeps its
        // numbers (lane k takes the k-th of each `lanes` draws).
        var state = ao_batch_state;
        for (var k = 0u; k < ao_batch_lanes; k++) {
            let drawn = next_random2(&state);
            if k == ao_batch_lane {
                u = drawn;
            }
        }
        ao_batch_state = state;
    } else {
        let i = round * ao_batch_lanes + ao_batch_lane;
        u = fract(r2_sample(i + ao_batch_frame_offset * params.rays) + ao_batch_rotation);
    }
    return cosine_hemisphere(ao_batch_normal, u);
}

// The texel of `partial` (twice the frame in each axis) that holds lane `lane` of `pixel`:
// (2x + i, 2y + j) for lane i + 2j.
fn ao_partial_texel(pixel: vec2<u32>, lane: u32) -> vec2<u32> {
    return 2u * pixel + vec2<u32>(lane & 1u, lane >> 1u);
}
