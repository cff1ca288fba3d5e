// The spread AO schedule's lane count (layers/rt_ao_spread.ron: rt/ao_spread.wgsl and
// rt/ao_spread_sum.wgsl compute it alike): how many lanes share one listed pixel's rays this
// frame. Enough (pixel, lane) items for one an image pixel, as a power of two from AO_LANES
// (a frame mostly covered: rt_ao's four lanes) up to AO_SPREAD_MAX_LANES, and no more than the
// rays (rounded up to a power of two). A model covering 2% of the frame gets 64 lanes a pixel:
// its rays run side by side instead of in a chain of 16 a lane. Item i of the pass is lane
// i % lanes of list entry i / lanes, stored at texel (i % width, i / width) of `partial` (four
// texels a pixel: lanes x listed never exceeds them).
//#include "common/ao_params.wgsl"

const AO_SPREAD_MAX_LANES: u32 = 64u;

fn ao_spread_lanes(listed: u32, pixels: u32, rays: u32) -> u32 {
    let wanted = (pixels + max(listed, 1u) - 1u) / max(listed, 1u);
    let most = max(AO_LANES, min(AO_SPREAD_MAX_LANES, ao_power_of_two_at_least(rays)));
    return clamp(ao_power_of_two_at_least(wanted), AO_LANES, most);
}

fn ao_power_of_two_at_least(x: u32) -> u32 {
    if x <= 1u {
        return 1u;
    }
    return 1u << (32u - countLeadingZeros(x - 1u));
}

// The texel of `partial` holding item `item`.
fn ao_spread_texel(item: u32, width: u32) -> vec2<u32> {
    return vec2<u32>(item % width, item / width);
}
