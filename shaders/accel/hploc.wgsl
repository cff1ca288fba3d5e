// H-PLOC (Benthin, Meister, Barczak, Mehalwal, Tsakok, Kensler, "H-PLOC: Hierarchical Parallel
// Locally-Ordered Clustering for Bounding Volume Hierarchy Construction", HPG 2024): the whole
// tree from the sorted leaves in one dispatch (`hploc`), in place of `ploc_local`, the rounds
// and the finish of shaders/accel/build.wgsl, whose bindings and `make_node_from` it uses.
//
// Each invocation starts at a leaf of the Morton order and climbs the radix tree of the codes
// bottom-up (Apetrei 2014): the leaves [l, r] are the left child of split r when the codes at
// r, r + 1 differ less than those at l - 1, l (`hploc_closer`), else the right child of split
// l - 1. At a split the first child to arrive leaves its boundary and cluster count there and
// stops; the second takes the whole range on. A range keeps at most HPLOC_KEEP clusters: when
// one of more leaves than that is formed, its team loads the two children's clusters (at
// most 2 HPLOC_KEEP, one invocation each) and runs PLOC rounds on them (each cluster's nearest
// neighbour among params.radius on either side, mutual pairs merge, survivors kept in order)
// until HPLOC_KEEP are left, or one at the root. No workgroup waits on another.
//
// tile_status holds, while `hploc` runs: per split p < n - 1 the first arrival's word
// (boundary << 5 | clusters; 0 until then: prim_boxes cleared it), then from word n each
// range's clusters as HPLOC_RECORD-word records at its first leaves. A range's records reach
// the invocation that takes it on through atomics, stored before a device-scope storage
// barrier that comes before the exchange handing them on.
//#include "accel/build.wgsl"

// A team of HPLOC_TEAM invocations starts at as many leaves and merges one range's clusters
// at a time; a workgroup holds HPLOC_TEAMS teams, which step together.
const HPLOC_TEAM: u32 = 32u;
// One team a workgroup: on the H200 the atrium's hploc kernel took 0.331-0.350 ms with one, 0.409
// with four teams and 0.556 with eight (docs/experiments/hploc/run.sh; src/accel/gpu_build.rs's
// HPLOC_GROUP must match).
const HPLOC_TEAMS: u32 = 1u;
const HPLOC_GROUP: u32 = HPLOC_TEAM * HPLOC_TEAMS;
// Clusters a range keeps: two children's fit a team.
const HPLOC_KEEP: u32 = 16u;
// A cluster's record: node, box lo, box hi, triangles, SAH cost (f32 bits).
const HPLOC_RECORD: u32 = 9u;

// The clusters of each team's task at hand, one per invocation (team t at 32 t ..).
var<workgroup> hp_lo: array<vec3<f32>, HPLOC_GROUP>;
var<workgroup> hp_hi: array<vec3<f32>, HPLOC_GROUP>;
var<workgroup> hp_node: array<u32, HPLOC_GROUP>;
var<workgroup> hp_count: array<u32, HPLOC_GROUP>;
var<workgroup> hp_cost: array<f32, HPLOC_GROUP>;
// Each cluster's nearest neighbour (its index in these arrays).
var<workgroup> hp_near: array<u32, HPLOC_GROUP>;
// Each team's tasks of the step, at 32 t ..: (first leaf, split, last leaf, left clusters |
// right clusters << 8 | owner << 16); their number; the survivors of a round, one bit each.
var<workgroup> hp_task: array<vec4<u32>, HPLOC_GROUP>;
var<workgroup> hp_tasks: array<atomic<u32>, HPLOC_TEAMS>;
var<workgroup> hp_keep: array<atomic<u32>, HPLOC_TEAMS>;
// The step: the most tasks of a team << 8, | 1 if any invocation still climbs.
var<workgroup> hp_step: atomic<u32>;
// Teams with merging left after a round.
var<workgroup> hp_more: atomic<u32>;

fn hploc_record(pos: u32) -> u32 {
    return params.n + HPLOC_RECORD * pos;
}

fn hploc_store(pos: u32, node: u32, lo: vec3<f32>, hi: vec3<f32>, count: u32, cost: f32) {
    let r = hploc_record(pos);
    let l = bitcast<vec3<u32>>(lo);
    let h = bitcast<vec3<u32>>(hi);
    atomicStore(&tile_status[r], node);
    atomicStore(&tile_status[r + 1u], l.x);
    atomicStore(&tile_status[r + 2u], l.y);
    atomicStore(&tile_status[r + 3u], l.z);
    atomicStore(&tile_status[r + 4u], h.x);
    atomicStore(&tile_status[r + 5u], h.y);
    atomicStore(&tile_status[r + 6u], h.z);
    atomicStore(&tile_status[r + 7u], count);
    atomicStore(&tile_status[r + 8u], bitcast<u32>(cost));
}

// The record at `pos` into cluster k of the arrays.
fn hploc_load(pos: u32, k: u32) {
    let r = hploc_record(pos);
    hp_node[k] = atomicLoad(&tile_status[r]);
    let l = vec3<u32>(atomicLoad(&tile_status[r + 1u]), atomicLoad(&tile_status[r + 2u]), atomicLoad(&tile_status[r + 3u]));
    let h = vec3<u32>(atomicLoad(&tile_status[r + 4u]), atomicLoad(&tile_status[r + 5u]), atomicLoad(&tile_status[r + 6u]));
    hp_lo[k] = bitcast<vec3<f32>>(l);
    hp_hi[k] = bitcast<vec3<f32>>(h);
    hp_count[k] = atomicLoad(&tile_status[r + 7u]);
    hp_cost[k] = bitcast<f32>(atomicLoad(&tile_status[r + 8u]));
}

// Whether the neighbours a, a + 1 of the Morton order differ less than b, b + 1: in their
// codes (the highest differing bit first), then in their positions' bits (Karras 2012's
// tie-break, which halves a run of equal codes), then by position.
fn hploc_closer(a: u32, b: u32) -> bool {
    let da = keys[a] ^ keys[a + 1u];
    let db = keys[b] ^ keys[b + 1u];
    if da != db {
        return da < db;
    }
    let pa = a ^ (a + 1u);
    let pb = b ^ (b + 1u);
    if pa != pb {
        return pa < pb;
    }
    return a < b;
}

// One step up for the leaves [range.x, range.y] held as range.z clusters: the parent's range
// (first leaf, split, last leaf, left clusters | right clusters << 8), or x = NONE where the
// sibling has not arrived yet (this invocation stops) or the range is the whole tree.
fn hploc_climb(range: vec3<u32>) -> vec4<u32> {
    let l = range.x;
    let r = range.y;
    let last = params.n - 1u;
    if l == 0u && r == last {
        return vec4<u32>(NONE);
    }
    if l == 0u || (r != last && hploc_closer(r, l - 1u)) {
        let other = atomicExchange(&tile_status[r], (l << 5u) | range.z);
        if other == 0u {
            return vec4<u32>(NONE);
        }
        return vec4<u32>(l, r, other >> 5u, range.z | ((other & 31u) << 8u));
    }
    let other = atomicExchange(&tile_status[l - 1u], (r << 5u) | range.z);
    if other == 0u {
        return vec4<u32>(NONE);
    }
    return vec4<u32>(other >> 5u, l - 1u, r, (other & 31u) | (range.z << 8u));
}

// The nearest neighbour of a team's cluster `lane` (of `count`, from `base` in the arrays)
// among params.radius on either side; its index in the arrays.
fn hploc_nearest(lane: u32, count: u32, base: u32) -> u32 {
    let lo = hp_lo[base + lane];
    let hi = hp_hi[base + lane];
    var best = lane;
    var best_area = 3.0e38;
    for (var c = u32(max(i32(lane) - i32(params.radius), 0)); c <= min(lane + params.radius, count - 1u); c++) {
        if c == lane {
            continue;
        }
        let a = area(min(lo, hp_lo[base + c]), max(hi, hp_hi[base + c]));
        if nearer(lane, c, a, best, best_area) {
            best_area = a;
            best = c;
        }
    }
    return base + best;
}

// Cluster i of the arrays after a round's merges: merged with its nearest neighbour j when
// they are mutual and i < j; `keep` 0 when it went into j's.
struct HplocCluster {
    node: u32,
    lo: vec3<f32>,
    hi: vec3<f32>,
    count: u32,
    cost: f32,
    keep: u32,
}

fn hploc_merged(i: u32) -> HplocCluster {
    var c = HplocCluster(hp_node[i], hp_lo[i], hp_hi[i], hp_count[i], hp_cost[i], 1u);
    let j = hp_near[i];
    let mutual = j != i && hp_near[j] == i;
    if mutual && i < j {
        c.lo = min(c.lo, hp_lo[j]);
        c.hi = max(c.hi, hp_hi[j]);
        c.node = make_node_from(c.node, hp_node[j], vec2<u32>(c.count, hp_count[j]), vec2<f32>(c.cost, hp_cost[j]), c.lo, c.hi);
        c.count += hp_count[j];
        c.cost = node_box[2u * c.node + 1u].w;
    }
    c.keep = select(1u, 0u, mutual && j < i);
    return c;
}

// PLOC rounds on each team's `count` clusters (call from uniform control flow; the teams'
// counts and goals differ) until at most `goal` are left; returns how many, and adds the
// team's rounds to `rounds`. Survivors keep their order: each finds its place by counting the
// survivor bits below its own.
fn hploc_rounds(i: u32, count_in: u32, goal: u32, rounds: ptr<function, u32>) -> u32 {
    let team = i / HPLOC_TEAM;
    let lane = i % HPLOC_TEAM;
    var count = count_in;
    if lane == 0u && count > goal {
        atomicAdd(&hp_more, 1u);
    }
    loop {
        if workgroupUniformLoad(&hp_more) == 0u {
            break;
        }
        let merging = count > goal;
        if i == 0u {
            atomicStore(&hp_more, 0u);
        }
        if lane == 0u {
            atomicStore(&hp_keep[team], 0u);
        }
        if merging && lane < count {
            hp_near[i] = hploc_nearest(lane, count, i - lane);
        }
        workgroupBarrier();
        var c = HplocCluster(0u, vec3<f32>(0.0), vec3<f32>(0.0), 0u, 0.0, 0u);
        if merging && lane < count {
            c = hploc_merged(i);
            atomicOr(&hp_keep[team], c.keep << lane);
        }
        workgroupBarrier();
        if merging {
            *rounds += 1u;
            let kept = atomicLoad(&hp_keep[team]);
            if c.keep == 1u {
                let k = i - lane + countOneBits(kept & ((1u << lane) - 1u));
                hp_node[k] = c.node;
                hp_lo[k] = c.lo;
                hp_hi[k] = c.hi;
                hp_count[k] = c.count;
                hp_cost[k] = c.cost;
            }
            count = countOneBits(kept);
            if lane == 0u && count > goal {
                atomicAdd(&hp_more, 1u);
            }
        }
    }
    return count;
}

// Task t of each team's tasks of the step (a team with fewer does nothing), by the whole
// team: the two children's clusters loaded, merged down to HPLOC_KEEP (one at the root) and
// stored at the range's first leaves. Returns the clusters left and the invocation that owns
// the range (NONE for a team without a task t).
fn hploc_task(i: u32, t: u32, rounds: ptr<function, u32>) -> vec2<u32> {
    let team = i / HPLOC_TEAM;
    let lane = i % HPLOC_TEAM;
    let has = t < atomicLoad(&hp_tasks[team]);
    var task = vec4<u32>(0u);
    if has {
        task = hp_task[team * HPLOC_TEAM + t];
    }
    let left = task.w & 255u;
    let count = left + ((task.w >> 8u) & 255u);
    if lane < count {
        hploc_load(select(task.y + 1u + lane - left, task.x + lane, lane < left), i);
    }
    let root = has && task.x == 0u && task.z == params.n - 1u;
    let kept = hploc_rounds(i, count, select(HPLOC_KEEP, 1u, root), rounds);
    if lane < kept {
        hploc_store(task.x + lane, hp_node[i], hp_lo[i], hp_hi[i], hp_count[i], hp_cost[i]);
    }
    if root && lane == 0u {
        atomicStore(&state[STATE_COUNT], 1u);
    }
    workgroupBarrier();
    return vec2<u32>(kept, select(NONE, task.w >> 16u, has));
}

// A climbing invocation climbs one step; where its new range needs merging it queues it as a
// task of its team. Returns the range the invocation holds now and whether it still climbs (w).
fn hploc_step_up(i: u32, range_in: vec3<u32>) -> vec4<u32> {
    let up = hploc_climb(range_in);
    if up.x == NONE {
        return vec4<u32>(range_in, 0u);
    }
    let range = vec3<u32>(up.x, up.z, (up.w & 255u) + ((up.w >> 8u) & 255u));
    var step = 1u;
    if up.z - up.x + 1u > HPLOC_KEEP || (up.x == 0u && up.z == params.n - 1u) {
        let team = i / HPLOC_TEAM;
        let k = atomicAdd(&hp_tasks[team], 1u);
        hp_task[team * HPLOC_TEAM + k] = vec4<u32>(up.xyz, up.w | (i << 16u));
        step |= (k + 1u) << 8u;
    }
    atomicMax(&hp_step, step);
    return vec4<u32>(range, 1u);
}

@compute @workgroup_size(HPLOC_GROUP)
fn hploc(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) i: u32) {
    let first = (wid.x + wid.y * groups.x) * HPLOC_GROUP;
    if first >= params.n {
        return;
    }
    if params.n == 1u {
        atomicStore(&state[STATE_COUNT], 1u);
        return;
    }
    // (first leaf, last leaf, clusters): the invocation's leaf, its record at its position.
    var range = vec3<u32>(first + i, first + i, 1u);
    var climbing = first + i < params.n;
    if climbing {
        let leaf = vals[first + i];
        hploc_store(first + i, leaf, box_lo(leaf), box_hi(leaf), 1u, node_box[2u * leaf + 1u].w);
    }
    var rounds = 0u;
    var stored = true;
    loop {
        // What this workgroup stored is visible before it hands it on.
        if stored {
            storageBarrier();
        }
        if i == 0u {
            atomicStore(&hp_step, 0u);
        }
        if i % HPLOC_TEAM == 0u {
            atomicStore(&hp_tasks[i / HPLOC_TEAM], 0u);
        }
        workgroupBarrier();
        if climbing {
            let up = hploc_step_up(i, range);
            range = up.xyz;
            climbing = up.w == 1u;
        }
        let step = workgroupUniformLoad(&hp_step);
        let most = step >> 8u;
        stored = most > 0u;
        if stored {
            // What the siblings' workgroups stored before their exchanges is visible.
            storageBarrier();
        }
        for (var t = 0u; t < most; t++) {
            let done = hploc_task(i, t, &rounds);
            if done.y == i {
                range.z = done.x;
            }
        }
        if step == 0u {
            break;
        }
    }
    if i % HPLOC_TEAM == 0u {
        atomicAdd(&state[STATE_ROUNDS], rounds);
    }
}
