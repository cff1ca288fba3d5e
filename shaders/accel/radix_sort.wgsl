// Stable LSD radix sort of (u32 key, u32 value) pairs (src/accel/radix_sort.rs): up to four
// passes of 8 bits (as many as the keys' bits need; after an odd number `radix_copy` puts the
// result back), onesweep-style (Adinets and Merrill, "Onesweep: A Faster Least Significant Digit
// Radix Sort for GPUs", 2022).
//
//   radix_histogram  every pass's digit counts over all keys at once (the counts do not
//                    depend on the order), added into sort_state's histograms
//   radix_scatter    one pass: each tile of TILE keys (in the order the tiles take tickets) is
//                    sorted by the pass's digit in workgroup memory (two stable 4-bit splits),
//                    finds per digit how many keys the tiles before it hold by decoupled
//                    look-back, and writes its keys to their places in the other arrays
//
// Keys equal in the pass's digit keep their order (the tiles in array order, each tile's split
// stable), so the sort is stable and its result depends on nothing but its input.
//#include "common/lookback.wgsl"

struct SortParams {
    // The pass's digit: key >> shift & 0xff.
    shift: u32,
    // The pass (0..4): its ticket and its tile status region.
    pass_index: u32,
    // Tiles the dispatches are sized for (the status region's stride).
    tiles: u32,
    unused: u32,
}

@group(0) @binding(0) var<uniform> params: SortParams;
@group(0) @binding(1) var<storage, read_write> keys_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> vals_in: array<u32>;
@group(0) @binding(3) var<storage, read_write> keys_out: array<u32>;
@group(0) @binding(4) var<storage, read_write> vals_out: array<u32>;
// Per pass, 256 digit counts; then a ticket per pass; the pairs to sort (COUNT). Zero when the
// sort starts, but for COUNT.
@group(0) @binding(5) var<storage, read_write> sort_state: array<atomic<u32>>;
// Per pass, per tile, per digit its status (as build.wgsl's tile_status: the tile's count
// flagged TILE_AGGREGATE, or the count of all tiles up to it flagged TILE_PREFIX; 0 while
// neither is known). Zero when the sort starts.
@group(0) @binding(6) var<storage, read_write> tile_status: array<atomic<u32>>;

const GROUP: u32 = 256u;
// Keys per invocation (1 to 16; src/accel/radix_sort.rs sets it): a tile is GROUP * PER_THREAD
// keys, at most 4096 (the workgroup arrays' sizes; the packed counts hold 16 bits).
override PER_THREAD: u32 = 8u;
override TILE: u32 = GROUP * PER_THREAD;
const DIGITS: u32 = 256u;
const PASSES: u32 = 4u;
const TICKETS: u32 = 1024u;
const COUNT: u32 = 1028u;

var<workgroup> wg_keys: array<u32, TILE>;
var<workgroup> wg_vals: array<u32, TILE>;
// The histogram's counts (PASSES * DIGITS), the scatter's per-digit counts.
var<workgroup> wg_count: array<atomic<u32>, 1024>;
// Per invocation, its 16 bucket counts packed two to a word (16 bits each: a tile holds at
// most 4096 keys): word w of invocation t at w * GROUP + t.
var<workgroup> wg_scan: array<u32, 2048>;
// Per digit: where its keys start in the sorted tile, and where they go in the output.
var<workgroup> wg_local_start: array<u32, 256>;
var<workgroup> wg_global_start: array<u32, 256>;
var<workgroup> wg_uniform: u32;

fn sort_count() -> u32 {
    return atomicLoad(&sort_state[COUNT]);
}

@compute @workgroup_size(256)
fn radix_histogram(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    for (var b = lid; b < PASSES * DIGITS; b += GROUP) {
        atomicStore(&wg_count[b], 0u);
    }
    workgroupBarrier();
    let n = sort_count();
    let first = wid.x * TILE;
    for (var e = 0u; e < PER_THREAD; e++) {
        let i = first + e * GROUP + lid;
        if i < n {
            let key = keys_in[i];
            for (var p = 0u; p < PASSES; p++) {
                atomicAdd(&wg_count[p * DIGITS + ((key >> (8u * p)) & 0xffu)], 1u);
            }
        }
    }
    workgroupBarrier();
    for (var b = lid; b < PASSES * DIGITS; b += GROUP) {
        let c = atomicLoad(&wg_count[b]);
        if c != 0u {
            atomicAdd(&sort_state[b], c);
        }
    }
}

// Inclusive sums over the invocations of the 8 words each wrote to wg_scan (Hillis-Steele;
// call from uniform control flow).
fn scan_packed_counts(lid: u32) {
    for (var s = 1u; s < GROUP; s <<= 1u) {
        var add: array<u32, 8>;
        if lid >= s {
            for (var w = 0u; w < 8u; w++) {
                add[w] = wg_scan[w * GROUP + lid - s];
            }
        }
        workgroupBarrier();
        for (var w = 0u; w < 8u; w++) {
            wg_scan[w * GROUP + lid] += add[w];
        }
        workgroupBarrier();
    }
}

// The count of bucket b (0..16) in a packed word set.
fn packed(words: ptr<function, array<u32, 8>>, b: u32) -> u32 {
    return ((*words)[b >> 1u] >> (16u * (b & 1u))) & 0xffffu;
}

// One stable split of the tile (in wg_keys / wg_vals, invocation t holding positions
// t * PER_THREAD ..) by the 4 bits of the pass's digit at `nibble`: the keys move to their
// places in wg_keys / wg_vals.
fn split_tile(lid: u32, nibble: u32) {
    var key: array<u32, 16>;
    var val: array<u32, 16>;
    var mine: array<u32, 8>;
    for (var e = 0u; e < PER_THREAD; e++) {
        key[e] = wg_keys[lid * PER_THREAD + e];
        val[e] = wg_vals[lid * PER_THREAD + e];
        let b = (key[e] >> (params.shift + nibble)) & 15u;
        mine[b >> 1u] += 1u << (16u * (b & 1u));
    }
    for (var w = 0u; w < 8u; w++) {
        wg_scan[w * GROUP + lid] = mine[w];
    }
    workgroupBarrier();
    scan_packed_counts(lid);
    // Each bucket's start in the tile and this invocation's first place in it.
    var totals: array<u32, 8>;
    var before: array<u32, 8>;
    for (var w = 0u; w < 8u; w++) {
        totals[w] = wg_scan[w * GROUP + GROUP - 1u];
        before[w] = wg_scan[w * GROUP + lid] - mine[w];
    }
    var start: array<u32, 16>;
    var sum = 0u;
    for (var b = 0u; b < 16u; b++) {
        start[b] = sum + packed(&before, b);
        sum += packed(&totals, b);
    }
    workgroupBarrier();
    for (var e = 0u; e < PER_THREAD; e++) {
        let b = (key[e] >> (params.shift + nibble)) & 15u;
        let place = start[b];
        start[b] = place + 1u;
        wg_keys[place] = key[e];
        wg_vals[place] = val[e];
    }
    workgroupBarrier();
}

// Decoupled look-back (lookback.wgsl) for digit `digit` of tile `tile`, whose own count is
// `total`: the count of that digit in the tiles before it.
fn digit_prefix(tile: u32, digit: u32, total: u32) -> u32 {
    return tile_prefix_strided(params.pass_index * params.tiles * DIGITS + digit, DIGITS, tile, total);
}

// Exclusive sums over the invocations of `a` and `b` into wg_local_start / wg_global_start
// (Hillis-Steele; call from uniform control flow).
fn scan_digit_starts(lid: u32, a: u32, b: u32) {
    wg_local_start[lid] = a;
    wg_global_start[lid] = b;
    workgroupBarrier();
    for (var s = 1u; s < GROUP; s <<= 1u) {
        var add_a = 0u;
        var add_b = 0u;
        if lid >= s {
            add_a = wg_local_start[lid - s];
            add_b = wg_global_start[lid - s];
        }
        workgroupBarrier();
        wg_local_start[lid] += add_a;
        wg_global_start[lid] += add_b;
        workgroupBarrier();
    }
    wg_local_start[lid] -= a;
    wg_global_start[lid] -= b;
}

@compute @workgroup_size(256)
fn radix_scatter(@builtin(local_invocation_index) lid: u32) {
    if lid == 0u {
        wg_uniform = atomicAdd(&sort_state[TICKETS + params.pass_index], 1u);
    }
    let tile = workgroupUniformLoad(&wg_uniform);
    if lid == 0u {
        wg_uniform = sort_count();
    }
    let n = workgroupUniformLoad(&wg_uniform);
    let first = tile * TILE;
    if first >= n {
        return;
    }
    let valid = min(TILE, n - first);
    atomicStore(&wg_count[lid], 0u);
    // The tile, read in order; past the keys, the largest key (which sorts to the end: every
    // split is stable and those come last).
    for (var e = 0u; e < PER_THREAD; e++) {
        let p = e * GROUP + lid;
        var key = 0xffffffffu;
        var val = 0u;
        if p < valid {
            key = keys_in[first + p];
            val = vals_in[first + p];
        }
        wg_keys[p] = key;
        wg_vals[p] = val;
    }
    workgroupBarrier();
    // The tile's count of each digit, while it is in order.
    for (var e = 0u; e < PER_THREAD; e++) {
        let p = e * GROUP + lid;
        if p < valid {
            atomicAdd(&wg_count[(wg_keys[p] >> params.shift) & 0xffu], 1u);
        }
    }
    split_tile(lid, 0u);
    split_tile(lid, 4u);
    let count = atomicLoad(&wg_count[lid]);
    let before = digit_prefix(tile, lid, count);
    let global = atomicLoad(&sort_state[params.pass_index * DIGITS + lid]);
    scan_digit_starts(lid, count, global);
    wg_global_start[lid] += before;
    workgroupBarrier();
    for (var e = 0u; e < PER_THREAD; e++) {
        let p = e * GROUP + lid;
        if p < valid {
            let key = wg_keys[p];
            let d = (key >> params.shift) & 0xffu;
            let out = wg_global_start[d] + p - wg_local_start[d];
            keys_out[out] = key;
            vals_out[out] = wg_vals[p];
        }
    }
}

// After an odd number of passes: the sorted pairs (in the other arrays, bound as the input)
// copied back into the sort's own arrays (bound as the output), a tile per workgroup.
@compute @workgroup_size(256)
fn radix_copy(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let n = sort_count();
    for (var e = 0u; e < PER_THREAD; e++) {
        let i = wid.x * TILE + e * GROUP + lid;
        if i < n {
            keys_out[i] = keys_in[i];
            vals_out[i] = vals_in[i];
        }
    }
}
