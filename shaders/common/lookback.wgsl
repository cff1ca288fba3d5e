// Decoupled look-back (Merrill and Garland 2016), shared by accel/build.wgsl and
// accel/radix_sort.wgsl (src/accel prepends this file to each; their `//#include` line lets the
// shader tests validate them the same way). The includer declares
// `tile_status: array<atomic<u32>>`: a tile's word holds its own count flagged TILE_AGGREGATE,
// or the count of all tiles up to it flagged TILE_PREFIX; 0 while neither is known.

const TILE_AGGREGATE: u32 = 0x40000000u;
const TILE_PREFIX: u32 = 0x80000000u;
const TILE_VALUE: u32 = 0x3fffffffu;

// For one invocation of tile `tile`, whose own count is `total`, over the status words at
// `region + k * stride` (tile k): publishes it, sums the tiles before it (flag and value in one
// atomic word, so no other memory ordering is needed; a tile waits only on tiles that took
// their ticket before it), publishes the inclusive prefix and returns the exclusive one.
fn tile_prefix_strided(region: u32, stride: u32, tile: u32, total: u32) -> u32 {
    if tile == 0u {
        atomicStore(&tile_status[region], TILE_PREFIX | total);
        return 0u;
    }
    atomicStore(&tile_status[region + tile * stride], TILE_AGGREGATE | total);
    var before = 0u;
    var k = tile - 1u;
    loop {
        let status = atomicLoad(&tile_status[region + k * stride]);
        if status == 0u {
            continue;
        }
        before += status & TILE_VALUE;
        if (status & TILE_PREFIX) != 0u || k == 0u {
            break;
        }
        k -= 1u;
    }
    atomicStore(&tile_status[region + tile * stride], TILE_PREFIX | (before + total));
    return before;
}
