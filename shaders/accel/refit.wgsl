// GPU refit of the merged layout (src/accel/refit.rs): after instances move, every triangle is
// moved to world space again from its object-space vertices and its instance's transform, and
// every node box is recomputed bottom-up. The topology stays; boxes are widened outward exactly
// as src/accel/layout.rs widens them (1e-20, then one ulp), so they stay conservative.
//
// The tree is cut into treelets: subtrees of at most a few hundred nodes, and the top part
// above them. One workgroup refits one treelet, level by level from its deepest, with a
// storage barrier between levels (a workgroup sees its own writes after it). The first
// dispatch refits every subtree treelet, the second the top one.
//
// A tree built on the GPU (src/accel/gpu_build.rs) is refitted without a plan, from its
// parents: `refit_leaves` moves every leaf's triangles, writes the leaf's box and carries it up
// to the root by atomic max on order-preserving keys of the boxes (per node and axis), stopping
// once an ancestor already holds a key as large in every word (whoever set it carries it on up);
// `refit_interior` turns the keys into the interior nodes' boxes and clears them for the next
// refit. Every cross-workgroup exchange is an atomic on one word, then a dispatch boundary.

struct Params {
    // This dispatch refits treelets[first_treelet + workgroup index].
    first_treelet: u32,
    // 1 for the dispatch that ends with the root (node 0): the TLAS's one node (a leaf over the
    // merged instance) then gets the root's box too.
    writes_root: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Node i: [2i] = (min.xyz, left_or_first), [2i + 1] = (max.xyz, count); as in compute.wgsl.
@group(0) @binding(1) var<storage, read_write> nodes: array<vec4<f32>>;
// Triangle i: [3i] = (v0, prim), [3i + 1] = (v1, instance), [3i + 2] = (v2, flags).
@group(0) @binding(2) var<storage, read_write> triangles: array<vec4<f32>>;
// Triangle i's object-space vertices: [3i], [3i + 1], [3i + 2] (w: the vertex's index, for
// shaders/accel/gather_positions.wgsl).
@group(0) @binding(3) var<storage, read> object_vertices: array<vec4<f32>>;
// Scene instance j's object-to-world rows: [3j], [3j + 1], [3j + 2].
@group(0) @binding(4) var<storage, read> transforms: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> level_nodes: array<u32>;
@group(0) @binding(6) var<storage, read_write> tlas_nodes: array<vec4<f32>>;
// Per treelet level (deepest first): (first, count) into level_nodes.
@group(0) @binding(7) var<storage, read> level_ranges: array<vec2<u32>>;
// Per treelet: (first level, level count) into level_ranges.
@group(0) @binding(8) var<storage, read> treelets: array<vec2<u32>>;

const NO_PRIM: u32 = 0xffffffffu;
const BOX_PAD_ABS: f32 = 1e-20;

// One ulp towards -inf (x finite), as Rust's f32::next_down.
fn next_down(x: f32) -> f32 {
    let b = bitcast<u32>(x);
    if (b & 0x7fffffffu) == 0u {
        return -bitcast<f32>(1u);
    }
    return bitcast<f32>(select(b - 1u, b + 1u, x < 0.0));
}

fn widen_down(x: vec3<f32>) -> vec3<f32> {
    let y = x - BOX_PAD_ABS;
    return vec3<f32>(next_down(y.x), next_down(y.y), next_down(y.z));
}

fn widen_up(x: vec3<f32>) -> vec3<f32> {
    let y = -(x + BOX_PAD_ABS);
    return -vec3<f32>(next_down(y.x), next_down(y.y), next_down(y.z));
}

fn to_world(j: u32, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(transforms[3u * j], h), dot(transforms[3u * j + 1u], h), dot(transforms[3u * j + 2u], h));
}

// Recomputes node `node`'s box (and, for a leaf, moves its triangles).
fn refit_node(node: u32) {
    let a = nodes[2u * node];
    let b = nodes[2u * node + 1u];
    let first = bitcast<u32>(a.w);
    let count = bitcast<u32>(b.w);
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    if count > 0u {
        for (var i = first; i < first + count; i++) {
            let t0 = triangles[3u * i];
            let t1 = triangles[3u * i + 1u];
            let t2 = triangles[3u * i + 2u];
            if bitcast<u32>(t0.w) == NO_PRIM {
                continue;
            }
            let j = bitcast<u32>(t1.w);
            let v0 = to_world(j, object_vertices[3u * i].xyz);
            let v1 = to_world(j, object_vertices[3u * i + 1u].xyz);
            let v2 = to_world(j, object_vertices[3u * i + 2u].xyz);
            triangles[3u * i] = vec4<f32>(v0, t0.w);
            triangles[3u * i + 1u] = vec4<f32>(v1, t1.w);
            triangles[3u * i + 2u] = vec4<f32>(v2, t2.w);
            lo = min(lo, min(v0, min(v1, v2)));
            hi = max(hi, max(v0, max(v1, v2)));
        }
        if lo.x > hi.x {
            return; // padding only: the box stays the never-entered placeholder
        }
        lo = widen_down(lo);
        hi = widen_up(hi);
    } else {
        // The children's boxes are widened already; their union is the widened union.
        lo = min(nodes[2u * first].xyz, nodes[2u * first + 2u].xyz);
        hi = max(nodes[2u * first + 1u].xyz, nodes[2u * first + 3u].xyz);
    }
    nodes[2u * node] = vec4<f32>(lo, a.w);
    nodes[2u * node + 1u] = vec4<f32>(hi, b.w);
}

fn copy_root_to_tlas() {
    tlas_nodes[0] = vec4<f32>(nodes[0].xyz, tlas_nodes[0].w);
    tlas_nodes[1] = vec4<f32>(nodes[1].xyz, tlas_nodes[1].w);
}

const GROUP: u32 = 256u;

@compute @workgroup_size(256)
fn refit_treelets(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let treelet = treelets[params.first_treelet + group.x];
    for (var l = 0u; l < treelet.y; l++) {
        let range = level_ranges[treelet.x + l];
        for (var k = lane; k < range.y; k += GROUP) {
            refit_node(level_nodes[range.x + k]);
        }
        storageBarrier();
    }
    if params.writes_root == 1u && lane == 0u {
        copy_root_to_tlas();
    }
}

// The GPU-built tree's refit (no treelet plan): node i's parent index + 1, 0 for the root and
// for unused slots.
@group(0) @binding(9) var<storage, read> parents: array<u32>;
// Triangle i (leaf order) is input triangle leaf_order[i], whose object-space vertices are
// object_vertices[3 leaf_order[i] + 0..2].
@group(0) @binding(10) var<storage, read> leaf_order: array<u32>;
// Per node, six keys: (~key(min.xyz), key(max.xyz)); 0 is below every key (nothing yet).
@group(0) @binding(11) var<storage, read_write> box_keys: array<atomic<u32>>;

// Order-preserving unsigned key of a float (larger float, larger key).
fn float_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn key_float(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
}

// Whether slot `node` holds a node of the tree (unused slots inside leaves have no parent).
fn in_tree(node: u32) -> bool {
    return node == 0u || parents[node] != 0u;
}

// Moves the triangles first..first + count of a leaf and returns its widened box (lo > hi if it has none).
fn refit_leaf(first: u32, count: u32) -> array<vec3<f32>, 2> {
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    for (var i = first; i < first + count; i++) {
        let t0 = triangles[3u * i];
        let t1 = triangles[3u * i + 1u];
        let t2 = triangles[3u * i + 2u];
        let j = bitcast<u32>(t1.w);
        let source = 3u * leaf_order[i];
        let v0 = to_world(j, object_vertices[source].xyz);
        let v1 = to_world(j, object_vertices[source + 1u].xyz);
        let v2 = to_world(j, object_vertices[source + 2u].xyz);
        triangles[3u * i] = vec4<f32>(v0, t0.w);
        triangles[3u * i + 1u] = vec4<f32>(v1, t1.w);
        triangles[3u * i + 2u] = vec4<f32>(v2, t2.w);
        lo = min(lo, min(v0, min(v1, v2)));
        hi = max(hi, max(v0, max(v1, v2)));
    }
    if lo.x <= hi.x {
        lo = widen_down(lo);
        hi = widen_up(hi);
    }
    return array<vec3<f32>, 2>(lo, hi);
}

@compute @workgroup_size(256)
fn refit_leaves(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let node = gid.x + gid.y * groups.x * GROUP;
    if node >= arrayLength(&parents) || !in_tree(node) {
        return;
    }
    let a = nodes[2u * node];
    let b = nodes[2u * node + 1u];
    let count = bitcast<u32>(b.w);
    if count == 0u {
        return;
    }
    let bounds = refit_leaf(bitcast<u32>(a.w), count);
    if bounds[0].x > bounds[1].x {
        return;
    }
    nodes[2u * node] = vec4<f32>(bounds[0], a.w);
    nodes[2u * node + 1u] = vec4<f32>(bounds[1], b.w);
    var keys: array<u32, 6>;
    for (var c = 0u; c < 3u; c++) {
        keys[c] = ~float_key(bounds[0][c]);
        keys[3u + c] = float_key(bounds[1][c]);
    }
    var parent = parents[node];
    loop {
        if parent == 0u {
            break;
        }
        let p = parent - 1u;
        var raised = false;
        for (var c = 0u; c < 6u; c++) {
            let before = atomicMax(&box_keys[6u * p + c], keys[c]);
            raised = raised || before < keys[c];
        }
        if !raised {
            break;
        }
        parent = parents[p];
    }
}

@compute @workgroup_size(256)
fn refit_interior(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let node = gid.x + gid.y * groups.x * GROUP;
    if node >= arrayLength(&parents) || !in_tree(node) {
        return;
    }
    let a = nodes[2u * node];
    let b = nodes[2u * node + 1u];
    if bitcast<u32>(b.w) == 0u {
        var lo: vec3<f32>;
        var hi: vec3<f32>;
        for (var c = 0u; c < 3u; c++) {
            lo[c] = key_float(~atomicExchange(&box_keys[6u * node + c], 0u));
            hi[c] = key_float(atomicExchange(&box_keys[6u * node + 3u + c], 0u));
        }
        nodes[2u * node] = vec4<f32>(lo, a.w);
        nodes[2u * node + 1u] = vec4<f32>(hi, b.w);
    }
    if node == 0u {
        copy_root_to_tlas();
    }
}
