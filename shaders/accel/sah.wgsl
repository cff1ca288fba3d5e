// The SAH cost of a tree in the traversal's layout (src/accel/deform.rs's SAH probe): per
// workgroup, the sum over its nodes of area x cost (1 per interior node, the triangle count
// per leaf, as src/accel/bvh.rs's `sah_cost`); the root's area goes after the partial sums,
// and the CPU adds them up in f64 and divides.

// Node i: [2i] = (min.xyz, left_or_first), [2i + 1] = (max.xyz, count).
@group(0) @binding(0) var<storage, read> nodes: array<vec4<f32>>;
// Per workgroup its sum, then the root's area.
@group(0) @binding(1) var<storage, read_write> partials: array<f32>;

struct SahParams {
    node_count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}
@group(0) @binding(2) var<uniform> sah_params: SahParams;

var<workgroup> sums: array<f32, 256>;

fn area(i: u32) -> f32 {
    let d = max(nodes[2u * i + 1u].xyz - nodes[2u * i].xyz, vec3<f32>(0.0));
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

@compute @workgroup_size(256)
fn sah_partials(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = wid.y * groups.x + wid.x;
    let i = g * 256u + lid;
    var cost = 0.0;
    if i < sah_params.node_count {
        let count = bitcast<u32>(nodes[2u * i + 1u].w);
        cost = area(i) * select(1.0, f32(count), count > 0u);
    }
    sums[lid] = cost;
    workgroupBarrier();
    for (var s = 128u; s > 0u; s /= 2u) {
        if lid < s {
            sums[lid] += sums[lid + s];
        }
        workgroupBarrier();
    }
    if lid == 0u {
        partials[g] = sums[0];
        if g == 0u {
            partials[groups.x * groups.y] = area(0u);
        }
    }
}
