// The lane count of the AO layer's spread schedule (layers/rt_ao.ron: rt/ao_spread.wgsl and
// rt/ao_spread_sum.wgsl compute it alike from the list's length): how many lanes share one
// listed pixel's rays this frame. Enough (pixel, lane) items for one an image pixel, as a
// power of two from AO_LANES up to AO_SPREAD_MAX_LANES, and no more than the rays (rounded up
// to a power of two): a model covering 2% of the frame gets 16 lanes a pixel, four of its 64
// rays a lane instead of a chain of 16. More lanes than 16 pay a lane's own work (its list
// entry, the G-buffer, the start below the root, its texel and the sum's read) for too few
// rays, fewer make the chains long again (PERF.md steps 48-49). Item i is lane i % lanes of
// list entry i / lanes, stored at texel (i % width, i / width) of `spread` (four texels an
// image pixel: lanes x listed fits, as lanes < 2 x pixels / listed where that is above
// AO_LANES).
//#include "common/ao_params.wgsl"

const AO_SPREAD_MAX_LANES: u32 = 16u;

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

// The texel of `partial` holding item `item` of the spread schedule.
fn ao_spread_texel(item: u32, width: u32) -> vec2<u32> {
    return vec2<u32>(item % width, item / width);
}

// The spread schedule's item of the invocation at texel `t` of `partial` (of size `size`): the
// texels numbered 8x8 tile by tile (tiles in row order, texels in row order inside a tile,
// the edge tiles narrower), so that a full tile's 64 items, one workgroup, are consecutive and
// every item below size.x * size.y has one invocation.
fn ao_spread_item(t: vec2<u32>, size: vec2<u32>) -> u32 {
    let tile = t / 8u;
    let inside = t % 8u;
    let tile_height = min(8u, size.y - 8u * tile.y);
    let tile_width = min(8u, size.x - 8u * tile.x);
    return 8u * tile.y * size.x + tile_height * 8u * tile.x + inside.y * tile_width + inside.x;
}
