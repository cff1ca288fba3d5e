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
    // Every ray of the lane stays within `range` of `origin` (its t_max is `range`, its
    // direction a unit vector), as trace_transmittance_within asks: they start together below
    // the root (trace/common.wgsl).
    let start = trace_start_within(origin, range);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    let first_ray = frame_offset * params.rays;
    let state = pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(params.seed + 0x9e3779b9u + frame_offset * 0x85ebca6bu)));
    // What the sampler carries from ray to ray, two words whatever the sampling (values live
    // across the trace call cost the lanes the GPU keeps in flight: three more pairs of them
    // made the atrium's frame 9% slower, PERF.md step 27): white noise its stream's state; R2
    // the pixel's rotation (as bits); the net (sampling 2) its current ray's point where it
    // goes a round at a time (ao_net_next_round), else the pixel's scramble.
    var carried = vec2<u32>(state, 0u);
    let net_by_rounds = params.sampling == 2u && ao_net_by_rounds(params.rays, lanes);
    if params.sampling == 1u {
        carried = bitcast<vec2<u32>>(pixel_random2(pixel, params.seed));
    } else if params.sampling == 2u {
        // The net's scramble from the same seeds: a new net every frame with `per_frame`.
        let scramble = vec2<u32>(pcg_hash(state), pcg_hash(pcg_hash(state)));
        carried = select(scramble, ao_net_bits(lane, params.rays, scramble), net_by_rounds);
    }
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
            var stream = carried.x;
            for (var k = 0u; k < lanes; k++) {
                let drawn = next_random2(&stream);
                if k == lane {
                    u = drawn;
                }
            }
            carried.x = stream;
        } else if net_by_rounds {
            if round > 0u {
                carried = ao_net_next_round(carried, round, lanes, params.rays);
            }
            u = ao_net_unit(carried);
        } else if params.sampling == 2u {
            u = ao_net_point(i, params.rays, carried);
        } else {
            u = fract(r2_sample(i + first_ray) + bitcast<vec2<f32>>(carried));
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

// The even bits of `v` (0, 2, 4, ...) packed into its low half.
fn ao_even_bits(v: u32) -> u32 {
    var x = v & 0x55555555u;
    x = (x | (x >> 1u)) & 0x33333333u;
    x = (x | (x >> 2u)) & 0x0f0f0f0fu;
    x = (x | (x >> 4u)) & 0x00ff00ffu;
    return (x | (x >> 8u)) & 0x0000ffffu;
}

// Sampling 2 ("net"): the pixel's `n` rays take the points of a (0,k,2)-net, the Hammersley set
// of n = 2^k points (point j = (j's bits reversed, j / n)) with both coordinates' bits XORed with
// the pixel's `scramble`: every cell of a 2^a x 2^b grid (a = ceil(k/2), b = floor(k/2)) holds one
// point, and each point is uniform over the square. Ray i takes the point in cell i in Morton
// order, so that round j of every lane of every pixel of a subgroup samples one small square and
// their rays point about the same way (PERF.md steps 26-27: the atrium's frame 21% faster than
// the same rays in index order; the layers' default). For n not a power of two, point i of the
// scrambled Hammersley set of n (x reversed bits, y stratified), in index order.
// src/accel/reference_render.rs mirrors it.
fn ao_net_point(i: u32, n: u32, scramble: vec2<u32>) -> vec2<f32> {
    if n <= 1u {
        return ao_net_unit(scramble);
    } else if (n & (n - 1u)) != 0u {
        let y = (f32(i) + f32(scramble.y >> 8u) * (1.0 / 16777216.0)) / f32(n);
        return vec2<f32>(f32((reverseBits(i) ^ scramble.x) >> 8u) * (1.0 / 16777216.0), min(y, 0.99999994));
    }
    return ao_net_unit(ao_net_bits(i, n, scramble));
}

// A net point's 32-bit fixed-point coordinates as numbers in [0, 1) (24 bits each).
fn ao_net_unit(p: vec2<u32>) -> vec2<f32> {
    return vec2<f32>(p >> vec2<u32>(8u)) * (1.0 / 16777216.0);
}

// ao_net_point's bits for n = 2^k >= 2: the point in Morton cell i.
fn ao_net_bits(i: u32, n: u32, scramble: vec2<u32>) -> vec2<u32> {
    let k = countTrailingZeros(n);
    let a = (k + 1u) / 2u;
    let b = k / 2u;
    // Morton order: i's bits 2t and 2t + 1 are the cell's x and y bit t (t < b); for odd k
    // its top bit is x's bit b.
    let interleaved = i & ((1u << (2u * b)) - 1u);
    let cx = ao_even_bits(interleaved) | (((i >> (k - 1u)) & select(0u, 1u, a > b)) << b);
    let cy = ao_even_bits(interleaved >> 1u);
    let low = reverseBits(cx ^ (scramble.x >> (32u - a))) >> (32u - a);
    let high = select(0u, cy ^ (scramble.y >> (32u - max(b, 1u))), b > 0u);
    let j = (high << a) | low;
    return vec2<u32>(reverseBits(j), j << (32u - k)) ^ scramble;
}

// Whether a lane's net points can be taken a round at a time: n and the lanes powers of two,
// at most n lanes.
fn ao_net_by_rounds(n: u32, lanes: u32) -> bool {
    return n >= 2u && (n & (n - 1u)) == 0u && lanes >= 1u && (lanes & (lanes - 1u)) == 0u && lanes <= n;
}

// ao_net_bits is linear over XOR in the cell index and the scramble together (bits are moved,
// never combined), so the point of cell round * lanes + lane is (the lane's point, scramble
// included) ^ (cell round * lanes's point, unscrambled): the first once a lane, the second a
// round at a time. From round r - 1 to r the cell's bits m..m + t flip (m = log2(lanes), t
// the trailing zeros of r), whose points are those of the cells below 2^(m + t + 1) and below
// 2^m XORed: ao_net_low_cells, a few operations in place of ao_net_bits' forty.
fn ao_net_next_round(bits: vec2<u32>, round: u32, lanes: u32, n: u32) -> vec2<u32> {
    let m = countTrailingZeros(lanes);
    return bits ^ ao_net_low_cells(m + countTrailingZeros(round) + 1u, n) ^ ao_net_low_cells(m, n);
}

// The unscrambled net point of cell 2^c - 1 (the XOR of the points of cells 1, 2, 4, ...,
// 2^(c - 1)), c <= k: its Morton bits set x's ceil(c/2) lowest bits and y's floor(c/2), which
// the point puts in x's reversed low field and y's high field of j, as ao_net_bits does.
fn ao_net_low_cells(c: u32, n: u32) -> vec2<u32> {
    let k = countTrailingZeros(n);
    let a = (k + 1u) / 2u;
    let x_ones = (c + 1u) / 2u;
    let y_ones = c / 2u;
    let low = ((1u << a) - 1u) ^ ((1u << (a - x_ones)) - 1u);
    let j = (((1u << y_ones) - 1u) << a) | low;
    return vec2<u32>(reverseBits(j), j << (32u - k));
}
