// The GPU builder's input records made on the GPU (`src/accel/gpu_records.rs`): every usable
// instance's triangles moved to world space, classified as the CPU classifies the merged mesh
// (`classify_mesh_triangle`: indices in range, finite vertices, a non-zero f32 cross product),
// and the survivors compacted in input order (instance, then triangle). Three dispatches:
// `records_count` (survivors per workgroup), `records_scan` (one workgroup: the workgroups'
// offsets and the total), `records_write` (each survivor's record and its object-space
// vertices at its offset). The world position is the CPU's f64 `m * v + t` rounded once to
// f32; here it is carried in two f32s (error-free products and sums), whose rounding to f32
// agrees with the f64 result except within about 2^-44 relative of a rounding boundary (or
// where a product or 4097 times a coordinate overflows f32, past 1e34).

struct Params {
    // Input slots: the usable instances' triangles, one after another.
    slots: u32,
    // Usable instances (records of `instances`).
    instances: u32,
    // 1.0 (see `opaque`).
    one: f32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Per instance, 5 words of vec4<u32>: object-to-world rows 0..2 (f32 bits); (first vertex,
// first triangle in `indices`, first input slot, scene instance); (triangle flags, 0, 0, 0).
@group(0) @binding(1) var<storage, read> instances: array<vec4<u32>>;
// Every mesh's object-space positions (xyz), one mesh after another.
@group(0) @binding(2) var<storage, read> vertices: array<vec4<f32>>;
// Every mesh's index triples; a triangle with an index out of its mesh's range has
// 0xffffffff as its first index (checked on the CPU when the mesh changes).
@group(0) @binding(3) var<storage, read> indices: array<u32>;
// Survivors per workgroup, turned into each workgroup's first output slot by `records_scan`.
@group(0) @binding(4) var<storage, read_write> group_offsets: array<u32>;
// [0]: survivors in all.
@group(0) @binding(5) var<storage, read_write> total: array<u32>;
// The builder's input records: v0, prim, v1, instance, v2, flags (`GpuTriangle`).
@group(0) @binding(6) var<storage, read_write> records: array<vec4<u32>>;
// Per record, its three object-space vertices (the tree refit's input), each with its index
// into `vertices` in w (where shaders/accel/gather_positions.wgsl gathers deformed positions from).
@group(0) @binding(7) var<storage, read_write> object_vertices: array<vec4<u32>>;

const GROUP: u32 = 256u;
const BAD_INDEX: u32 = 0xffffffffu;

var<workgroup> scan: array<u32, 256>;

fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

// `x`, hidden from the shader compiler's algebra (`params.one` is 1.0): a driver may simplify
// float expressions it can see through (Mesa's inexact NIR rules turn (a + b) - a into b)
// and fuse a product into a following sum. A value passed through here is an exact
// multiplication it cannot undo, and fusing it into a sum rounds the same.
fn opaque(x: f32) -> f32 {
    return x * params.one;
}

// a + b as an f32 and its rounding error (Knuth's two-sum).
fn two_sum(a: f32, b: f32) -> vec2<f32> {
    let s = opaque(a + b);
    let bb = opaque(s - a);
    return vec2<f32>(s, (a - opaque(s - bb)) + (b - bb));
}

// `a` as a high part of at most 12 significant bits and the rest (Veltkamp's split).
fn split(a: f32) -> vec2<f32> {
    let c = opaque(4097.0 * a);
    let hi = opaque(c - opaque(c - a));
    return vec2<f32>(hi, a - hi);
}

// a * b as an f32 and its rounding error (Dekker's product: no `fma`, which a driver may
// compute as a multiplication and an addition).
fn two_prod(a: f32, b: f32) -> vec2<f32> {
    let p = opaque(a * b);
    let x = split(a);
    let y = split(b);
    var e = opaque(opaque(x.x * y.x) - p);
    e = opaque(e + opaque(x.x * y.y));
    e = opaque(e + opaque(x.y * y.x));
    return vec2<f32>(p, e + opaque(x.y * y.y));
}

// The sum of two (high, low) pairs, renormalised.
fn pair_add(x: vec2<f32>, y: vec2<f32>) -> vec2<f32> {
    let s = two_sum(x.x, y.x);
    let t = two_sum(x.y, y.y);
    let u = two_sum(s.x, s.y + t.x);
    return two_sum(u.x, u.y + t.y);
}

// Row `r` of the instance's transform applied to `v`, in the CPU's order:
// ((m0 vx + m1 vy) + m2 vz) + t, rounded once.
fn transform_row(row: vec4<f32>, v: vec3<f32>) -> f32 {
    var acc = two_prod(row.x, v.x);
    acc = pair_add(acc, two_prod(row.y, v.y));
    acc = pair_add(acc, two_prod(row.z, v.z));
    acc = pair_add(acc, vec2<f32>(row.w, 0.0));
    return acc.x + acc.y;
}

fn to_world(inst: u32, v: vec3<f32>) -> vec3<f32> {
    let base = 5u * inst;
    return vec3<f32>(
        transform_row(bitcast<vec4<f32>>(instances[base]), v),
        transform_row(bitcast<vec4<f32>>(instances[base + 1u]), v),
        transform_row(bitcast<vec4<f32>>(instances[base + 2u]), v),
    );
}

// Whether (b - a) x (c - a) in f32 is zero or not finite. A component is zero exactly when
// its two rounded products are equal, and overflows exactly when half their difference (exact
// halves) doubled does: neither test lets a fused multiply-add change the answer.
fn degenerate(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> bool {
    let e1 = b - a;
    let e2 = c - a;
    let p = vec3<f32>(e1.y * e2.z, e1.z * e2.x, e1.x * e2.y);
    let q = vec3<f32>(e1.z * e2.y, e1.x * e2.z, e1.y * e2.x);
    if !finite3(p) || !finite3(q) {
        return true;
    }
    let doubled = (p * 0.5 - q * 0.5) * 2.0;
    return all(p == q) || !finite3(doubled);
}

// The usable instance whose slots hold `slot` (binary search over the first slots).
fn instance_of(slot: u32) -> u32 {
    var lo = 0u;
    var hi = params.instances;
    while hi - lo > 1u {
        let mid = (lo + hi) / 2u;
        if instances[5u * mid + 3u].z <= slot {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

struct Triangle {
    keep: bool,
    inst: u32,
    prim: u32,
    // Object-space and world-space vertices.
    o0: vec3<f32>,
    o1: vec3<f32>,
    o2: vec3<f32>,
    w0: vec3<f32>,
    w1: vec3<f32>,
    w2: vec3<f32>,
    // The vertices' indices into `vertices`.
    ids: vec3<u32>,
}

fn classify(slot: u32) -> Triangle {
    var t: Triangle;
    t.keep = false;
    if slot >= params.slots {
        return t;
    }
    t.inst = instance_of(slot);
    let head = instances[5u * t.inst + 3u];
    t.prim = slot - head.z;
    let first = 3u * (head.y + t.prim);
    if indices[first] == BAD_INDEX {
        return t;
    }
    t.ids = head.x + vec3<u32>(indices[first], indices[first + 1u], indices[first + 2u]);
    t.o0 = vertices[t.ids.x].xyz;
    t.o1 = vertices[t.ids.y].xyz;
    t.o2 = vertices[t.ids.z].xyz;
    t.w0 = to_world(t.inst, t.o0);
    t.w1 = to_world(t.inst, t.o1);
    t.w2 = to_world(t.inst, t.o2);
    let finite_all = finite3(t.o0) && finite3(t.o1) && finite3(t.o2) && finite3(t.w0) && finite3(t.w1) && finite3(t.w2);
    t.keep = finite_all && !degenerate(t.w0, t.w1, t.w2);
    return t;
}

fn group_index(wid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return wid.y * groups.x + wid.x;
}

@compute @workgroup_size(256)
fn records_count(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = group_index(wid, groups);
    scan[lid] = u32(classify(g * GROUP + lid).keep);
    workgroupBarrier();
    for (var s = GROUP / 2u; s > 0u; s /= 2u) {
        if lid < s {
            scan[lid] += scan[lid + s];
        }
        workgroupBarrier();
    }
    if lid == 0u {
        group_offsets[g] = scan[0];
    }
}

// One workgroup: each invocation sums a run of workgroup counts, the runs are scanned in
// workgroup memory, then each run is written back as exclusive offsets.
@compute @workgroup_size(256)
fn records_scan(@builtin(local_invocation_index) lid: u32) {
    let n = arrayLength(&group_offsets);
    let run = (n + GROUP - 1u) / GROUP;
    let first = min(lid * run, n);
    let end = min(first + run, n);
    var sum = 0u;
    for (var i = first; i < end; i++) {
        sum += group_offsets[i];
    }
    scan[lid] = sum;
    scan_inclusive(lid);
    var offset = scan[lid] - sum;
    for (var i = first; i < end; i++) {
        let c = group_offsets[i];
        group_offsets[i] = offset;
        offset += c;
    }
    if lid == GROUP - 1u {
        total[0] = scan[lid];
    }
}

// `scan` made inclusive prefix sums of itself across the workgroup (Hillis-Steele); called by
// every invocation, in uniform control flow, after each has written its own entry.
fn scan_inclusive(lid: u32) {
    workgroupBarrier();
    for (var s = 1u; s < GROUP; s *= 2u) {
        let add = select(0u, scan[max(lid, s) - s], lid >= s);
        workgroupBarrier();
        scan[lid] += add;
        workgroupBarrier();
    }
}

@compute @workgroup_size(256)
fn records_write(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = group_index(wid, groups);
    let t = classify(g * GROUP + lid);
    let keep = u32(t.keep);
    scan[lid] = keep;
    scan_inclusive(lid);
    if !t.keep {
        return;
    }
    let out = group_offsets[g] + scan[lid] - keep;
    let flags = instances[5u * t.inst + 4u].x;
    let scene_instance = instances[5u * t.inst + 3u].w;
    records[3u * out] = vec4<u32>(bitcast<vec3<u32>>(t.w0), t.prim);
    records[3u * out + 1u] = vec4<u32>(bitcast<vec3<u32>>(t.w1), scene_instance);
    records[3u * out + 2u] = vec4<u32>(bitcast<vec3<u32>>(t.w2), flags);
    object_vertices[3u * out] = vec4<u32>(bitcast<vec3<u32>>(t.o0), t.ids.x);
    object_vertices[3u * out + 1u] = vec4<u32>(bitcast<vec3<u32>>(t.o1), t.ids.y);
    object_vertices[3u * out + 2u] = vec4<u32>(bitcast<vec3<u32>>(t.o2), t.ids.z);
}
