// The compute back-end's arrays as four storage buffers (the AccelCache's buffers, bound by
// name) and their readers, included by trace/compute.wgsl. Devices with fewer storage buffers
// per stage than a trace pass with these needs get trace/compute_arrays_packed.wgsl instead.
// Every array is read in whole 16-byte words: the driver does not merge the loads of a
// struct's fields (PERF.md).
@group(2) @binding(0) var<storage, read> accel_tlas_nodes: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read> accel_instances: array<vec4<f32>>;
@group(2) @binding(2) var<storage, read> accel_blas_nodes: array<vec4<f32>>;
@group(2) @binding(3) var<storage, read> accel_triangles: array<vec4<f32>>;
@group(2) @binding(5) var<storage, read> accel_blas_quant: array<vec4<u32>>;

fn trace_tlas_node(i: u32) -> AccelNode {
    let a = accel_tlas_nodes[2u * i];
    let b = accel_tlas_nodes[2u * i + 1u];
    return AccelNode(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w));
}

fn trace_instance(i: u32) -> AccelInstance {
    let ids = bitcast<vec4<u32>>(accel_instances[7u * i + 6u]);
    return AccelInstance(accel_instances[7u * i], accel_instances[7u * i + 1u], accel_instances[7u * i + 2u], ids.x, ids.y, ids.z, ids.w);
}

fn trace_blas_node(i: u32) -> AccelNode {
    let a = accel_blas_nodes[2u * i];
    let b = accel_blas_nodes[2u * i + 1u];
    return AccelNode(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w));
}

fn trace_tri(i: u32) -> AccelTriangle {
    let a = accel_triangles[3u * i];
    let b = accel_triangles[3u * i + 1u];
    let c = accel_triangles[3u * i + 2u];
    return AccelTriangle(a.xyz, bitcast<u32>(a.w), b.xyz, bitcast<u32>(b.w), c.xyz, bitcast<u32>(c.w));
}

// The grid entry at a BLAS's root in blas_quant (src/accel/quantised.rs).
fn trace_blas_grid(root: u32) -> QuantGrid {
    let a = accel_blas_quant[2u * root];
    let b = accel_blas_quant[2u * root + 1u];
    return QuantGrid(bitcast<vec3<f32>>(a.xyz), bitcast<vec3<f32>>(b.xyz), a.w == QUANT_GRID_VALID);
}

// The child pair whose first child is node `first`, with 16-bit boxes.
fn trace_blas_pair(first: u32) -> QuantPair {
    return QuantPair(accel_blas_quant[2u * first], accel_blas_quant[2u * first + 1u]);
}
