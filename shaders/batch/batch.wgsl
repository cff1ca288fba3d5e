// Traces a buffer of rays through the trace interface and writes one result per ray: the
// back-end test harness (src/runtime/batch.rs). `mode` 0: closest hit, 1: any hit; `flags`: the
// trace interface's per-ray flags for every ray.
//#include "trace/trace.wgsl"

struct BatchParams {
    count: u32,
    mode: u32,
    flags: u32,
    // Invocations per row of the dispatch (rays are numbered row by row).
    row: u32,
}

struct BatchResult {
    t: f32,
    instance: u32,
    primitive: u32,
    // bit 0: hit, bit 1: front face
    flags: u32,
    bary: vec2<f32>,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> batch: BatchParams;
@group(0) @binding(1) var<storage, read> batch_rays: array<Ray>;
@group(0) @binding(2) var<storage, read_write> batch_results: array<BatchResult>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * batch.row;
    if i >= batch.count {
        return;
    }
    let ray = batch_rays[i];
    var r = BatchResult(-1.0, NO_HIT, 0u, 0u, vec2<f32>(0.0), 0u, 0u);
    if batch.mode == 0u {
        let h = trace_closest_flags(ray, batch.flags);
        if h.instance != NO_HIT {
            r = BatchResult(h.t, h.instance, h.primitive, 1u | select(0u, 2u, h.front_face), h.bary, 0u, 0u);
        }
    } else if trace_any_flags(ray, batch.flags) {
        r.flags = 1u;
    }
    batch_results[i] = r;
    trace_flush_stats();
}
