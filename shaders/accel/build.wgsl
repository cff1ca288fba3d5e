// The GPU BLAS builder (src/accel/gpu_build.rs): PLOC (Meister and Bittner 2018) over the
// triangles' Morton order, collapsed by the surface-area heuristic into leaves of at most four
// triangles and written out in the layout the `compute` back-end traverses (src/accel/layout.rs:
// the children of an interior node side by side, every box widened outwards).
//
// Nodes while building: the n triangles are leaves 0..n-1 (their input order), the n - 1
// clusters made by merging are n..2n-2, in the order they are made (so the root is 2n - 2).
// Every node carries its box, its triangle count and its SAH cost (the cheaper of a leaf and
// of its split), computed when it is made from its children's, which earlier dispatches wrote.
//
// Entry points, in the order the builder records them:
//   prim_boxes       the leaves' boxes and costs; the centroid bounds (atomics)
//   morton           30-bit (or 24-bit) Morton codes of the centroids (padded to a power of two for the
//                    bitonic sort); then shaders/accel/radix_sort.wgsl sorts them, or:
//   sort_block       bitonic sort of each block of 4096 keys in workgroup memory
//   sort_step_pair   two global compare-exchange steps (k, j and j / 2) of the network
//   sort_step        one global step (k, j), where a stage has an odd number of them
//   sort_block_merge the steps j < 4096 of stage k in workgroup memory
//   ploc_local       the first rounds within segments of 1024 leaves in Morton order, in
//                    workgroup memory; the survivors compacted in order
//   ploc_round       one round: nearest neighbours, merges and the survivors compacted in
//                    order into the other cluster array; or, in two dispatches:
//   ploc_nearest     each cluster's nearest neighbour among params.radius on either side
//   ploc_merge       mutual nearest neighbours merge into a new node; the survivors move, in
//                    order, to the other cluster array
//   ploc_finish      the last rounds in one workgroup
//   layout_offsets   per triangle, for itself and the nodes it is the leftmost triangle of:
//                    first triangle in depth-first order, depth, inside a leaf?
//   layout_write     the traversal's node pairs and the triangles in leaf order; per traversal
//                    node its parent, per triangle its input index (the GPU refit's inputs)
//
// `params.n` and the state's counts are written by the CPU, or copied on the GPU from a count
// only the GPU knows (the records kernel's), before the first dispatch.
//#include "common/lookback.wgsl"

struct Params {
    // Triangles.
    n: u32,
    // Bitonic stage and step; the PLOC round's parity (which count and dispatch slots it reads).
    k: u32,
    j: u32,
    parity: u32,
    // Clusters at or below which the rounds stop and `ploc_finish` completes the tree in one
    // workgroup.
    finish: u32,
    // Neighbours searched on either side (at most RADIUS, the window's margin).
    radius: u32,
    // Cells of the Morton grid along each axis (1024 for 30-bit codes, 256 for 24-bit ones).
    morton_cells: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Three 16-byte words per triangle: v0 and its primitive, v1 and its instance, v2 and flags.
@group(0) @binding(1) var<storage, read> tris_in: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> keys: array<u32>;
@group(0) @binding(3) var<storage, read_write> vals: array<u32>;
// See the STATE_* indices.
@group(0) @binding(4) var<storage, read_write> state: array<atomic<u32>>;
// Two words per node: (min, bitcast count), (max, SAH cost).
@group(0) @binding(5) var<storage, read_write> node_box: array<vec4<f32>>;
// Per node: left, right, parent (NONE where there is none), 1 where a leaf is cheaper.
@group(0) @binding(6) var<storage, read_write> node_link: array<vec4<u32>>;
@group(0) @binding(7) var<storage, read_write> clusters_in: array<u32>;
@group(0) @binding(8) var<storage, read_write> clusters_out: array<u32>;
@group(0) @binding(9) var<storage, read_write> nearest: array<u32>;
// Per workgroup (tile) of a merge: its survivors, flagged TILE_AGGREGATE, or the survivors of
// all tiles up to it, flagged TILE_PREFIX; 0 while neither is known.
@group(0) @binding(10) var<storage, read_write> tile_status: array<atomic<u32>>;
// Per node: first triangle in depth-first order; bit 31 set if a proper ancestor is a leaf.
@group(0) @binding(11) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(12) var<storage, read_write> out_nodes: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read_write> out_tris: array<vec4<f32>>;
// Per traversal node: its parent's index + 1; 0 for the root and for unused slots.
@group(0) @binding(14) var<storage, read_write> out_parents: array<u32>;
// Per triangle in leaf order: its index in tris_in.
@group(0) @binding(15) var<storage, read_write> out_order: array<u32>;
// The workgroups (x, y, z) of the next round's indirect dispatch, which has the other parity
// (each parity binds the other's): enough for its clusters, none when the finish takes them.
@group(0) @binding(16) var<storage, read_write> next_groups: array<u32>;

const NONE: u32 = 0xffffffffu;
const GROUP: u32 = 256u;
const RADIUS: u32 = 16u;
const MAX_LEAF: u32 = 4u;
// src/accel/bvh.rs's TRAVERSAL_COST and INTERSECTION_COST.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECTION_COST: f32 = 1.0;
// src/accel/layout.rs's BOX_PAD_ABS.
const BOX_PAD_ABS: f32 = 1e-20;

// state: centroid bounds as order-preserving integers (0..2 min, 3..5 max); the clusters left
// (6); the merge's next tile ticket (7); the next new node (8); the deepest leaf (9); rounds
// that merged (10); the parity whose input array holds the clusters (11); the finished root's
// SAH cost (12) and box area (13), as f32 bits; the fused rounds' second ticket (14); the
// triangles, n (15, read back by the CPU).
const STATE_COUNT: u32 = 6u;
const STATE_TICKET: u32 = 7u;
const STATE_NEXT_NODE: u32 = 8u;
const STATE_DEPTH: u32 = 9u;
const STATE_ROUNDS: u32 = 10u;
const STATE_HOLDER: u32 = 11u;
const STATE_ROOT_COST: u32 = 12u;
const STATE_ROOT_AREA: u32 = 13u;
const STATE_TICKET_B: u32 = 14u;

fn float_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn key_float(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
}

fn area(lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    let d = max(hi - lo, vec3<f32>(0.0));
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

fn tri_box(i: u32) -> array<vec3<f32>, 2> {
    let a = tris_in[3u * i].xyz;
    let b = tris_in[3u * i + 1u].xyz;
    let c = tris_in[3u * i + 2u].xyz;
    return array<vec3<f32>, 2>(min(a, min(b, c)), max(a, max(b, c)));
}

var<workgroup> wg_lo: array<vec3<f32>, 256>;
var<workgroup> wg_hi: array<vec3<f32>, 256>;

@compute @workgroup_size(256)
fn prim_boxes(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = gid.x;
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    if i < params.n {
        let b = tri_box(i);
        let c = 0.5 * (b[0] + b[1]);
        lo = c;
        hi = c;
        node_box[2u * i] = vec4<f32>(b[0], bitcast<f32>(1u));
        node_box[2u * i + 1u] = vec4<f32>(b[1], INTERSECTION_COST * area(b[0], b[1]));
        node_link[i] = vec4<u32>(NONE, NONE, NONE, 1u);
    }
    // `ploc_local`'s segments start their look-back afresh.
    if i < arrayLength(&tile_status) {
        atomicStore(&tile_status[i], 0u);
    }
    wg_lo[lid] = lo;
    wg_hi[lid] = hi;
    workgroupBarrier();
    for (var s = GROUP / 2u; s > 0u; s >>= 1u) {
        if lid < s {
            wg_lo[lid] = min(wg_lo[lid], wg_lo[lid + s]);
            wg_hi[lid] = max(wg_hi[lid], wg_hi[lid + s]);
        }
        workgroupBarrier();
    }
    if lid == 0u {
        for (var a = 0u; a < 3u; a++) {
            atomicMin(&state[a], float_key(wg_lo[0][a]));
            atomicMax(&state[3u + a], float_key(wg_hi[0][a]));
        }
    }
}

fn spread_bits(x: u32) -> u32 {
    var v = x & 0x3ffu;
    v = (v | (v << 16u)) & 0x030000ffu;
    v = (v | (v << 8u)) & 0x0300f00fu;
    v = (v | (v << 4u)) & 0x030c30c3u;
    v = (v | (v << 2u)) & 0x09249249u;
    return v;
}

@compute @workgroup_size(256)
fn morton(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.y * groups.x * GROUP;
    if i >= arrayLength(&keys) {
        return;
    }
    if i >= params.n {
        keys[i] = NONE;
        vals[i] = NONE;
        return;
    }
    let lo = vec3<f32>(key_float(atomicLoad(&state[0])), key_float(atomicLoad(&state[1])), key_float(atomicLoad(&state[2])));
    let hi = vec3<f32>(key_float(atomicLoad(&state[3])), key_float(atomicLoad(&state[4])), key_float(atomicLoad(&state[5])));
    let b = tri_box(i);
    let c = 0.5 * (b[0] + b[1]);
    let extent = max(hi - lo, vec3<f32>(1e-30));
    let cells = f32(params.morton_cells);
    let q = vec3<u32>(clamp((c - lo) / extent * cells, vec3<f32>(0.0), vec3<f32>(cells - 1.0)));
    keys[i] = (spread_bits(q.x) << 2u) | (spread_bits(q.y) << 1u) | spread_bits(q.z);
    vals[i] = i;
}

// Keys compare with their values as tie-break (the values are distinct), so the order is
// total and the sort's result does not depend on how the network is scheduled.
fn sort_less(ka: u32, va: u32, kb: u32, vb: u32) -> bool {
    return ka < kb || (ka == kb && va < vb);
}

// Blocks of SORT_BLOCK keys and values (32 KiB) are sorted in workgroup memory by
// SORT_BLOCK / 4 invocations, each doing two compare-exchanges per step.
const SORT_BLOCK: u32 = 4096u;
var<workgroup> wg_keys: array<u32, 4096>;
var<workgroup> wg_vals: array<u32, 4096>;

fn sort_block_steps(base: u32, lid: u32, k: u32, j_start: u32) {
    for (var j = j_start; j > 0u; j >>= 1u) {
        for (var h = 0u; h < 2u; h++) {
            let t = lid + h * (SORT_BLOCK / 4u);
            let a = (t / j) * 2u * j + (t % j);
            let b = a + j;
            let ascending = ((base + a) & k) == 0u;
            let ka = wg_keys[a];
            let kb = wg_keys[b];
            let va = wg_vals[a];
            let vb = wg_vals[b];
            if sort_less(kb, vb, ka, va) == ascending {
                wg_keys[a] = kb;
                wg_keys[b] = ka;
                wg_vals[a] = vb;
                wg_vals[b] = va;
            }
        }
        workgroupBarrier();
    }
}

fn block_base(wid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return (wid.x + wid.y * groups.x) * SORT_BLOCK;
}

fn sort_load(base: u32, lid: u32) {
    for (var h = 0u; h < 4u; h++) {
        let e = lid + h * (SORT_BLOCK / 4u);
        wg_keys[e] = keys[base + e];
        wg_vals[e] = vals[base + e];
    }
    workgroupBarrier();
}

fn sort_store(base: u32, lid: u32) {
    for (var h = 0u; h < 4u; h++) {
        let e = lid + h * (SORT_BLOCK / 4u);
        keys[base + e] = wg_keys[e];
        vals[base + e] = wg_vals[e];
    }
}

@compute @workgroup_size(1024)
fn sort_block(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let base = block_base(wid, groups);
    sort_load(base, lid);
    for (var k = 2u; k <= SORT_BLOCK; k <<= 1u) {
        sort_block_steps(base, lid, k, k >> 1u);
    }
    sort_store(base, lid);
}

@compute @workgroup_size(1024)
fn sort_block_merge(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let base = block_base(wid, groups);
    sort_load(base, lid);
    sort_block_steps(base, lid, params.k, SORT_BLOCK / 2u);
    sort_store(base, lid);
}

@compute @workgroup_size(256)
fn sort_step(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = gid.x + gid.y * groups.x * GROUP;
    let j = params.j;
    let a = (t / j) * 2u * j + (t % j);
    let b = a + j;
    if b >= arrayLength(&keys) {
        return;
    }
    let ascending = (a & params.k) == 0u;
    let ka = keys[a];
    let kb = keys[b];
    let va = vals[a];
    let vb = vals[b];
    if sort_less(kb, vb, ka, va) == ascending {
        keys[a] = kb;
        keys[b] = ka;
        vals[a] = vb;
        vals[b] = va;
    }
}

fn sort_exchange(a: u32, b: u32, ascending: bool) {
    let ka = keys[a];
    let kb = keys[b];
    let va = vals[a];
    let vb = vals[b];
    if sort_less(kb, vb, ka, va) == ascending {
        keys[a] = kb;
        keys[b] = ka;
        vals[a] = vb;
        vals[b] = va;
    }
}

// Two global steps of stage k at once, j = params.j and j / 2: each invocation owns the four
// keys a, a + h, a + 2h, a + 3h (h = j / 2), which both steps exchange only among themselves,
// all in the same direction (they differ in bits below k). Half the dispatches of `sort_step`.
@compute @workgroup_size(256)
fn sort_step_pair(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let g = gid.x + gid.y * groups.x * GROUP;
    let h = params.j / 2u;
    let a = (g / h) * 4u * h + (g % h);
    if a + 3u * h >= arrayLength(&keys) {
        return;
    }
    let ascending = (a & params.k) == 0u;
    sort_exchange(a, a + 2u * h, ascending);
    sort_exchange(a + h, a + 3u * h, ascending);
    sort_exchange(a, a + h, ascending);
    sort_exchange(a + 2u * h, a + 3u * h, ascending);
}

fn box_lo(node: u32) -> vec3<f32> {
    return node_box[2u * node].xyz;
}

fn box_hi(node: u32) -> vec3<f32> {
    return node_box[2u * node + 1u].xyz;
}

// Whether neighbour c of cluster i, whose union with i has area a, beats the best so far.
// Ties go to the neighbour whose index differs from i in the lowest bits, the same from both
// sides: equal boxes pair up as (2m, 2m + 1) and halve each round instead of chaining onto
// the lowest index.
fn nearer(i: u32, c: u32, a: f32, best: u32, best_area: f32) -> bool {
    return a < best_area || (a == best_area && (c ^ i) < (best ^ i));
}

var<workgroup> wg_uniform: u32;
var<workgroup> wg_prefix: u32;

// The clusters left if this round is to run: its parity holds them and there are more than
// the finish takes; 0 otherwise (a round recorded past the last one does nothing). Rounds are
// dispatched for all n clusters (indirect dispatches sized by the previous round measured
// slower on the H100); the workgroups past the clusters left return at once.
fn round_count(lid: u32) -> u32 {
    if lid == 0u {
        let count = atomicLoad(&state[STATE_COUNT]);
        let mine = atomicLoad(&state[STATE_HOLDER]) == params.parity;
        wg_uniform = select(0u, count, mine && count > params.finish);
    }
    return workgroupUniformLoad(&wg_uniform);
}

var<workgroup> win_lo: array<vec3<f32>, 288>;
var<workgroup> win_hi: array<vec3<f32>, 288>;

@compute @workgroup_size(256)
fn ploc_nearest(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let count = round_count(lid);
    if count == 0u {
        return;
    }
    let group = wid.x + wid.y * groups.x;
    if group * GROUP >= count {
        return;
    }
    // The merge that follows starts its tiles afresh.
    if lid == 0u {
        atomicStore(&tile_status[group], 0u);
        if group == 0u {
            atomicStore(&state[STATE_TICKET], 0u);
        }
    }
    let base = group * GROUP;
    // The window: clusters base - RADIUS .. base + GROUP + RADIUS.
    for (var w = lid; w < GROUP + 2u * RADIUS; w += GROUP) {
        let c = i32(base + w) - i32(RADIUS);
        if c >= 0 && u32(c) < count {
            let node = clusters_in[u32(c)];
            win_lo[w] = box_lo(node);
            win_hi[w] = box_hi(node);
        }
    }
    workgroupBarrier();
    let i = base + lid;
    if i >= count {
        return;
    }
    let lo = win_lo[lid + RADIUS];
    let hi = win_hi[lid + RADIUS];
    var best = i;
    var best_area = 3.0e38;
    let first = max(i32(i) - i32(params.radius), 0);
    let last = min(i + params.radius, count - 1u);
    for (var c = u32(first); c <= last; c++) {
        if c == i {
            continue;
        }
        let w = c + RADIUS - base;
        let a = area(min(lo, win_lo[w]), max(hi, win_hi[w]));
        if nearer(i, c, a, best, best_area) {
            best_area = a;
            best = c;
        }
    }
    nearest[i] = best;
}

var<workgroup> wg_sums: array<u32, 256>;

// Inclusive sum over the workgroup of each invocation's `value`, left in wg_sums (call from
// uniform control flow).
fn workgroup_inclusive_sum(lid: u32, value: u32) -> u32 {
    wg_sums[lid] = value;
    workgroupBarrier();
    for (var s = 1u; s < GROUP; s <<= 1u) {
        var add = 0u;
        if lid >= s {
            add = wg_sums[lid - s];
        }
        workgroupBarrier();
        wg_sums[lid] += add;
        workgroupBarrier();
    }
    return wg_sums[lid];
}

// Decoupled look-back over consecutive tiles' status words from `region` (lookback.wgsl).
fn tile_prefix(region: u32, tile: u32, total: u32) -> u32 {
    return tile_prefix_strided(region, 1u, tile, total);
}

// Mutual nearest neighbours merge into a new node, and the survivors move, in order, to the
// other cluster array: each workgroup (tile, in the order the tiles start) sums its
// survivors and finds how many the tiles before it keep by decoupled look-back (Merrill and
// Garland 2016: flag and value in one atomic word, so no other ordering is needed; a tile
// waits only on tiles that started before it). The last tile writes the next round's count.
@compute @workgroup_size(256)
fn ploc_merge(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let count = round_count(lid);
    // Workgroups past the clusters (a dispatch sized for more) take no tile.
    if count == 0u || (wid.x + wid.y * groups.x) * GROUP >= count {
        return;
    }
    if lid == 0u {
        wg_prefix = atomicAdd(&state[STATE_TICKET], 1u);
    }
    let tile = workgroupUniformLoad(&wg_prefix);
    let i = tile * GROUP + lid;
    var keep = 0u;
    var node = 0u;
    if i < count {
        let j = nearest[i];
        let mutual = j != i && nearest[j] == i;
        node = clusters_in[i];
        if mutual && i < j {
            let other = clusters_in[j];
            node = make_node(node, other, min(box_lo(node), box_lo(other)), max(box_hi(node), box_hi(other)));
        }
        keep = select(1u, 0u, mutual && j < i);
    }
    compact_survivors(lid, tile, count, 0u, keep, node);
}

// The survivors of a round's tile `tile` (per invocation: `keep` and its `node`) move, in
// order, to clusters_out, the tiles before it found by look-back over the tile status words
// from `region`; the last tile writes the next round's count (call from uniform control flow).
fn compact_survivors(lid: u32, tile: u32, count: u32, region: u32, keep: u32, node: u32) {
    let upto = workgroup_inclusive_sum(lid, keep);
    if lid == 0u {
        let total = wg_sums[GROUP - 1u];
        let before = tile_prefix(region, tile, total);
        wg_prefix = before;
        if tile == (count - 1u) / GROUP {
            write_next_groups(before + total);
            atomicStore(&state[STATE_COUNT], before + total);
            atomicStore(&state[STATE_HOLDER], 1u - params.parity);
            atomicAdd(&state[STATE_ROUNDS], 1u);
        }
    }
    let before = workgroupUniformLoad(&wg_prefix);
    if keep == 1u {
        clusters_out[before + upto - 1u] = node;
    }
}

// The next round's indirect dispatch for `count` clusters (see next_groups).
fn write_next_groups(count: u32) {
    next_groups[0] = select(0u, (count + GROUP - 1u) / GROUP, count > params.finish);
    next_groups[1] = 1u;
    next_groups[2] = 1u;
}

// The fused round's window in workgroup memory: the boxes of clusters base - 2 RADIUS ..
// base + GROUP + 2 RADIUS, and the nearest neighbours of base - RADIUS .. base + GROUP + RADIUS
// (every cluster a merge of the tile looks at).
var<workgroup> round_lo: array<vec3<f32>, 320>;
var<workgroup> round_hi: array<vec3<f32>, 320>;
var<workgroup> round_near: array<u32, 288>;

// The nearest neighbour of cluster i, whose box is at `w` in the fused round's window (of the
// tile starting at `base`), among params.radius on either side (as `ploc_nearest`).
fn window_nearest(i: u32, w: u32, count: u32) -> u32 {
    let lo = round_lo[w];
    let hi = round_hi[w];
    var best = i;
    var best_area = 3.0e38;
    let first = max(i32(i) - i32(params.radius), 0);
    let last = min(i + params.radius, count - 1u);
    for (var c = u32(first); c <= last; c++) {
        if c == i {
            continue;
        }
        let a = area(min(lo, round_lo[w + c - i]), max(hi, round_hi[w + c - i]));
        if nearer(i, c, a, best, best_area) {
            best_area = a;
            best = c;
        }
    }
    return best;
}

// The ticket of the fused rounds' set of tile status words `status_set`.
fn round_ticket(status_set: u32) -> u32 {
    return select(STATE_TICKET, STATE_TICKET_B, status_set == 1u);
}

// One whole round in one dispatch (`ploc_nearest` and `ploc_merge` together): each tile finds
// the nearest neighbours of its clusters and of RADIUS more on either side in workgroup
// memory, so it knows which pairs are mutual without another dispatch; merges, then compacts
// as `ploc_merge`. The rounds use two sets of tile status words and tickets by turns (set
// `parity`; `ploc_local` used set 0 and leaves the clusters for parity 1, so the first round
// uses the fresh set 1), each round clearing the set the next one uses.
@compute @workgroup_size(256)
fn ploc_round(@builtin(local_invocation_index) lid: u32) {
    let count = round_count(lid);
    if count == 0u {
        return;
    }
    let status_set = params.parity;
    let stride = arrayLength(&tile_status) / 2u;
    if lid == 0u {
        wg_prefix = atomicAdd(&state[round_ticket(status_set)], 1u);
    }
    let tile = workgroupUniformLoad(&wg_prefix);
    let base = tile * GROUP;
    if base >= count {
        return;
    }
    if lid == 0u {
        atomicStore(&tile_status[(1u - status_set) * stride + tile], 0u);
        if tile == 0u {
            atomicStore(&state[round_ticket(1u - status_set)], 0u);
        }
    }
    for (var w = lid; w < GROUP + 4u * RADIUS; w += GROUP) {
        let c = i32(base + w) - i32(2u * RADIUS);
        if c >= 0 && u32(c) < count {
            let node = clusters_in[u32(c)];
            round_lo[w] = box_lo(node);
            round_hi[w] = box_hi(node);
        }
    }
    workgroupBarrier();
    for (var q = lid; q < GROUP + 2u * RADIUS; q += GROUP) {
        let i = i32(base + q) - i32(RADIUS);
        if i >= 0 && u32(i) < count {
            round_near[q] = window_nearest(u32(i), q + RADIUS, count);
        }
    }
    workgroupBarrier();
    let i = base + lid;
    var keep = 0u;
    var node = 0u;
    if i < count {
        let j = round_near[lid + RADIUS];
        let mutual = j != i && round_near[j + RADIUS - base] == i;
        node = clusters_in[i];
        if mutual && i < j {
            let wi = lid + 2u * RADIUS;
            let wj = j + 2u * RADIUS - base;
            node = make_node(node, clusters_in[j], min(round_lo[wi], round_lo[wj]), max(round_hi[wi], round_hi[wj]));
        }
        keep = select(1u, 0u, mutual && j < i);
    }
    compact_survivors(lid, tile, count, status_set * stride, keep, node);
}

// Makes the new node of nodes a and b (their boxes' union lo, hi) and returns its id.
fn make_node(a: u32, b: u32, lo: vec3<f32>, hi: vec3<f32>) -> u32 {
    let counts = vec2<u32>(bitcast<u32>(node_box[2u * a].w), bitcast<u32>(node_box[2u * b].w));
    return make_node_from(a, b, counts, vec2<f32>(node_box[2u * a + 1u].w, node_box[2u * b + 1u].w), lo, hi);
}

// The same for children whose triangle counts and SAH costs the caller holds (H-PLOC's come
// from other workgroups of the same dispatch, through atomics, not from node_box).
fn make_node_from(a: u32, b: u32, counts: vec2<u32>, costs: vec2<f32>, lo: vec3<f32>, hi: vec3<f32>) -> u32 {
    let id = params.n + atomicAdd(&state[STATE_NEXT_NODE], 1u);
    let n = counts.x + counts.y;
    let area_ab = area(lo, hi);
    let split_cost = TRAVERSAL_COST * area_ab + costs.x + costs.y;
    let leaf_cost = select(3.0e38, INTERSECTION_COST * area_ab * f32(n), n <= MAX_LEAF);
    let leaf = leaf_cost <= split_cost;
    node_box[2u * id] = vec4<f32>(lo, bitcast<f32>(n));
    node_box[2u * id + 1u] = vec4<f32>(hi, min(leaf_cost, split_cost));
    node_link[id] = vec4<u32>(a, b, NONE, select(0u, 1u, leaf));
    node_link[a].z = id;
    node_link[b].z = id;
    return id;
}

// The finish's clusters (at most FINISH_CAPACITY): boxes (lo.xyz, hi.xyz), node ids, and a
// word per cluster for nearest neighbours and then the survivors' sum. 32 KiB, the most
// workgroup memory lavapipe offers (the H100 has 48).
const FINISH_CAPACITY: u32 = 1024u;
var<workgroup> fin_box: array<f32, 6144>;
var<workgroup> fin_node: array<u32, 1024>;
var<workgroup> fin_aux: array<u32, 1024>;

fn fin_lo(i: u32) -> vec3<f32> {
    return vec3<f32>(fin_box[6u * i], fin_box[6u * i + 1u], fin_box[6u * i + 2u]);
}

fn fin_hi(i: u32) -> vec3<f32> {
    return vec3<f32>(fin_box[6u * i + 3u], fin_box[6u * i + 4u], fin_box[6u * i + 5u]);
}

fn fin_set(i: u32, node: u32, lo: vec3<f32>, hi: vec3<f32>) {
    fin_node[i] = node;
    fin_box[6u * i] = lo.x;
    fin_box[6u * i + 1u] = lo.y;
    fin_box[6u * i + 2u] = lo.z;
    fin_box[6u * i + 3u] = hi.x;
    fin_box[6u * i + 4u] = hi.y;
    fin_box[6u * i + 5u] = hi.z;
}

// PLOC rounds on the `count` clusters in workgroup memory (one invocation each; call from
// uniform control flow) until at most `goal` are left: the same nearest neighbours (and
// tie-break), merges and in-order compaction as the dispatched rounds, with barriers instead
// of dispatches between the steps. Returns the clusters left and adds the rounds to `rounds`.
fn shared_rounds(i: u32, count_in: u32, goal: u32, rounds: ptr<function, u32>) -> u32 {
    var count = count_in;
    loop {
        workgroupBarrier();
        if count <= goal {
            break;
        }
        *rounds += 1u;
        var lo = vec3<f32>(0.0);
        var hi = vec3<f32>(0.0);
        if i < count {
            lo = fin_lo(i);
            hi = fin_hi(i);
            var best = i;
            var best_area = 3.0e38;
            for (var c = u32(max(i32(i) - i32(params.radius), 0)); c <= min(i + params.radius, count - 1u); c++) {
                if c == i {
                    continue;
                }
                let a = area(min(lo, fin_lo(c)), max(hi, fin_hi(c)));
                if nearer(i, c, a, best, best_area) {
                    best_area = a;
                    best = c;
                }
            }
            fin_aux[i] = best;
        }
        workgroupBarrier();
        var keep = 0u;
        var node = 0u;
        if i < count {
            let j = fin_aux[i];
            let mutual = j != i && fin_aux[j] == i;
            node = fin_node[i];
            if mutual && i < j {
                lo = min(lo, fin_lo(j));
                hi = max(hi, fin_hi(j));
                node = make_node(node, fin_node[j], lo, hi);
            }
            keep = select(1u, 0u, mutual && j < i);
        }
        workgroupBarrier();
        // Inclusive sum of the survivors, then each moves to its place.
        fin_aux[i] = keep;
        workgroupBarrier();
        for (var s = 1u; s < FINISH_CAPACITY; s <<= 1u) {
            var add = 0u;
            if i >= s {
                add = fin_aux[i - s];
            }
            workgroupBarrier();
            fin_aux[i] += add;
            workgroupBarrier();
        }
        if keep == 1u {
            fin_set(fin_aux[i] - 1u, node, lo, hi);
        }
        count = workgroupUniformLoad(&fin_aux[FINISH_CAPACITY - 1u]);
    }
    return count;
}

// The first rounds, per segment of FINISH_CAPACITY leaves in Morton order (one workgroup
// each, in the order the segments' tickets say), down to params.k clusters per segment, the
// neighbours searched within the segment only; then the survivors of all segments go, in
// order, to clusters_out (decoupled look-back over the segments, as in `ploc_merge`) and the
// last segment writes their count. Many global rounds become one dispatch.
@compute @workgroup_size(1024)
fn ploc_local(@builtin(local_invocation_index) i: u32) {
    if i == 0u {
        fin_aux[0] = atomicAdd(&state[STATE_TICKET], 1u);
    }
    let segment = workgroupUniformLoad(&fin_aux[0]);
    let first = segment * FINISH_CAPACITY;
    if first >= params.n {
        return;
    }
    let count = min(FINISH_CAPACITY, params.n - first);
    if i < count {
        let node = vals[first + i];
        fin_set(i, node, box_lo(node), box_hi(node));
    }
    var rounds = 0u;
    let left = shared_rounds(i, count, params.k, &rounds);
    if i == 0u {
        let before = tile_prefix(0u, segment, left);
        fin_aux[1023] = before;
        if segment == (params.n - 1u) / FINISH_CAPACITY {
            write_next_groups(before + left);
            atomicStore(&state[STATE_COUNT], before + left);
            atomicStore(&state[STATE_HOLDER], 1u);
        }
    }
    let before = workgroupUniformLoad(&fin_aux[1023]);
    if i < left {
        clusters_out[before + i] = fin_node[i];
    }
}

// The last rounds, from at most `finish` (<= FINISH_CAPACITY) clusters down to one, in one
// workgroup with one invocation per cluster and the clusters in workgroup memory. Does nothing
// while there are more clusters.
@compute @workgroup_size(1024)
fn ploc_finish(@builtin(local_invocation_index) i: u32) {
    if i == 0u {
        fin_aux[0] = atomicLoad(&state[STATE_COUNT]);
    }
    let count = workgroupUniformLoad(&fin_aux[0]);
    if count > min(params.finish, FINISH_CAPACITY) || count <= 1u {
        return;
    }
    // The clusters, wherever the last round left them.
    let holder = atomicLoad(&state[STATE_HOLDER]);
    if i < count {
        var node = clusters_in[i];
        if holder != params.parity {
            node = clusters_out[i];
        }
        fin_set(i, node, box_lo(node), box_hi(node));
    }
    var rounds = 0u;
    shared_rounds(i, count, 1u, &rounds);
    if i == 0u {
        atomicStore(&state[STATE_COUNT], 1u);
        atomicAdd(&state[STATE_ROUNDS], rounds);
    }
}

fn is_leaf(node: u32) -> bool {
    return node_link[node].w != 0u;
}

fn node_count(node: u32) -> u32 {
    return bitcast<u32>(node_box[2u * node].w);
}

// Whether the rounds and the finish have made the root (the layout is recorded with them and
// does nothing before; a build with no triangles has none).
fn tree_finished() -> bool {
    return atomicLoad(&state[STATE_COUNT]) == 1u;
}

// Every triangle walks up to the root: its place in depth-first order is the number of
// triangles in the left siblings of the subtrees it lies in the right side of. The ancestors it
// reaches from left children only (the nodes whose leftmost triangle it is: every node is one
// triangle's) have the same first triangle, and it writes theirs too, with whether each lies
// inside a leaf (an ancestor above it collapsed) and, for the leaves of the finished tree, their
// depth. A walk per triangle, not per node: half the walks of the tree's 2n - 1 nodes.
@compute @workgroup_size(256)
fn layout_offsets(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let x = gid.x + gid.y * groups.x * GROUP;
    if !tree_finished() || x >= params.n {
        return;
    }
    var offset = 0u;
    var depth = 0u;
    // Ancestors reached from left children only; the highest ancestor collapsed into a leaf
    // (1 the parent; 0: none).
    var leftmost_of = 0u;
    var highest_leaf = 0u;
    var child = x;
    var parent = node_link[x].z;
    loop {
        if parent == NONE {
            break;
        }
        let link = node_link[parent];
        depth++;
        if link.y == child {
            offset += node_count(link.x);
        } else if leftmost_of + 1u == depth {
            leftmost_of = depth;
        }
        if link.w != 0u {
            highest_leaf = depth;
        }
        child = parent;
        parent = link.z;
    }
    // A triangle goes to its place in depth-first order.
    out_tris[3u * offset] = tris_in[3u * x];
    out_tris[3u * offset + 1u] = tris_in[3u * x + 1u];
    out_tris[3u * offset + 2u] = tris_in[3u * x + 2u];
    out_order[offset] = x;
    // The triangle (level 0) and the ancestors whose leftmost triangle it is: the first
    // triangle, inside a leaf or not, and the depth of a leaf of the finished tree (the
    // traversal's stack holds at most the deepest).
    var deepest_leaf = 0u;
    var node = x;
    for (var level = 0u; level <= leftmost_of; level++) {
        let inside = highest_leaf > level;
        offsets[node] = offset | select(0u, 0x80000000u, inside);
        if !inside && node_link[node].w != 0u {
            deepest_leaf = max(deepest_leaf, depth - level);
        }
        node = node_link[node].z;
    }
    if deepest_leaf > 0u {
        atomicMax(&state[STATE_DEPTH], deepest_leaf);
    }
}

// `x` moved outwards past x -/+ BOX_PAD_ABS by one ulp (src/accel/layout.rs's widen_down and
// widen_up).
fn widen_down(v: vec3<f32>) -> vec3<f32> {
    let y = v - vec3<f32>(BOX_PAD_ABS);
    let b = bitcast<vec3<u32>>(y);
    let down = select(b + vec3<u32>(1u), b - vec3<u32>(1u), y > vec3<f32>(0.0));
    return select(bitcast<vec3<f32>>(down), vec3<f32>(bitcast<f32>(0x80000001u)), y == vec3<f32>(0.0));
}

fn widen_up(v: vec3<f32>) -> vec3<f32> {
    let y = v + vec3<f32>(BOX_PAD_ABS);
    let b = bitcast<vec3<u32>>(y);
    let up = select(b - vec3<u32>(1u), b + vec3<u32>(1u), y > vec3<f32>(0.0));
    return select(bitcast<vec3<f32>>(up), vec3<f32>(bitcast<f32>(1u)), y == vec3<f32>(0.0));
}

// Where interior node k (made by a merge, not inside a leaf) lies in the traversal's layout:
// 0 for the root, else beside its sibling in its parent's pair.
fn layout_index(k: u32) -> u32 {
    let parent = node_link[k].z;
    if parent == NONE {
        return 0u;
    }
    return 1u + 2u * (parent - params.n) + select(0u, 1u, node_link[parent].y == k);
}

// The traversal's entry for `node`: its widened box, and either its leaf (first triangle,
// count) or the index of its children's pair.
fn write_entry(e: u32, node: u32) {
    var first = 1u + 2u * (node - params.n);
    var count = 0u;
    if is_leaf(node) {
        first = offsets[node] & 0x7fffffffu;
        count = node_count(node);
    }
    out_nodes[2u * e] = vec4<f32>(widen_down(box_lo(node)), bitcast<f32>(first));
    out_nodes[2u * e + 1u] = vec4<f32>(widen_up(box_hi(node)), bitcast<f32>(count));
}

// Interior node k (not a leaf, not inside one) writes its children at 1 + 2 (k - n) and
// 2 + 2 (k - n); the root also writes itself at 0.
@compute @workgroup_size(256)
fn layout_write(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = gid.x + gid.y * groups.x * GROUP;
    let n = params.n;
    if !tree_finished() || t >= n {
        return;
    }
    if t == 0u {
        let root = select(2u * n - 2u, 0u, n == 1u);
        write_entry(0u, root);
        atomicStore(&state[STATE_ROOT_COST], bitcast<u32>(node_box[2u * root + 1u].w));
        atomicStore(&state[STATE_ROOT_AREA], bitcast<u32>(area(box_lo(root), box_hi(root))));
    }
    let k = n + t;
    if k > 2u * n - 2u || is_leaf(k) || (offsets[k] & 0x80000000u) != 0u {
        return;
    }
    let link = node_link[k];
    write_entry(1u + 2u * t, link.x);
    write_entry(2u + 2u * t, link.y);
    let parent = layout_index(k) + 1u;
    out_parents[1u + 2u * t] = parent;
    out_parents[2u + 2u * t] = parent;
}
