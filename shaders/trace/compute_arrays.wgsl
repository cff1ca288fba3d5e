// The compute back-end's arrays as four storage buffers (the AccelCache's buffers, bound by
// name) and their readers, included by trace/compute.wgsl. Devices with fewer storage buffers
// per stage than a trace pass with these needs get trace/compute_arrays_packed.wgsl instead.
// Every array is read in whole 16-byte words: the driver does not merge the loads of a
// struct's fields (PERF.md).
@group(2) @binding(0) var<storage, read> accel_tlas_nodes: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read> accel_instances: array<vec4<f32>>;
@group(2) @binding(2) var<storage, read> accel_blas_nodes: array<vec4<f32>>;
@group(2) @binding(3) var<storage, read> accel_triangles: array<vec4<f32>>;

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
