// The compute back-end's arrays packed into one storage buffer, for devices with few storage
// buffers per stage (a browser's WebGPU: 8 by default): the include substitution of
// trace/compute_arrays.wgsl (and trace/alpha_words.wgsl) the device selects
// (runtime::gpu::include_aliases). The AccelCache copies its four arrays and the alpha words
// into `accel_packed` after every update (AccelCache::record_packing). Word 0 holds where each
// array starts, in 16-byte words: (instances, BLAS nodes, triangles, alpha words); the TLAS
// nodes start at word 1. The readers are those of trace/compute_arrays.wgsl with those bases.
@group(2) @binding(0) var<storage, read> accel_packed: array<vec4<f32>>;

const ACCEL_TLAS_BASE: u32 = 1u;

fn accel_bases() -> vec4<u32> {
    return bitcast<vec4<u32>>(accel_packed[0]);
}

fn trace_tlas_node(i: u32) -> AccelNode {
    let a = accel_packed[ACCEL_TLAS_BASE + 2u * i];
    let b = accel_packed[ACCEL_TLAS_BASE + 2u * i + 1u];
    return AccelNode(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w));
}

fn trace_instance(i: u32) -> AccelInstance {
    let base = accel_bases().x + 7u * i;
    let ids = bitcast<vec4<u32>>(accel_packed[base + 6u]);
    return AccelInstance(accel_packed[base], accel_packed[base + 1u], accel_packed[base + 2u], ids.x, ids.y, ids.z, ids.w);
}

fn trace_blas_node(i: u32) -> AccelNode {
    let base = accel_bases().y + 2u * i;
    let a = accel_packed[base];
    let b = accel_packed[base + 1u];
    return AccelNode(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w));
}

fn trace_tri(i: u32) -> AccelTriangle {
    let base = accel_bases().z + 3u * i;
    let a = accel_packed[base];
    let b = accel_packed[base + 1u];
    let c = accel_packed[base + 2u];
    return AccelTriangle(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w), c.xyz, bitcast<u32>(c.w));
}
