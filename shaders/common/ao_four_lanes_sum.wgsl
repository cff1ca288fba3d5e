// How much of a pixel's AO rays got through in the four-lane schedule: its AO_LANES partial
// sums (texel (2x + i, 2y + j) of `partial` is lane i + 2j of pixel (x, y)) added in lane
// order. The last pass of layers/rt_ao_four_lanes.ron and its variants (rt/ao_sum.wgsl) and of
// layers/rt_ao.ron where it keeps four lanes (rt/ao_spread_sum.wgsl).
//#include "common/ao_params.wgsl"

fn ao_four_lanes_open(partial: texture_2d<f32>, pixel: vec2<u32>) -> f32 {
    var open = 0.0;
    for (var lane = 0u; lane < AO_LANES; lane++) {
        open += textureLoad(partial, 2u * pixel + vec2<u32>(lane & 1u, lane >> 1u), 0).r;
    }
    return open;
}
