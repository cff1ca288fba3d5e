// Ambient occlusion over the list of pixels with rays by persistent invocations
// (layers/rt_ao_persistent.ron): a fixed dispatch about the size of what the GPU holds at
// once, each invocation taking the next (pixel, lane) item (common/ao_list_item.wgsl) off the
// counter `taken` until the list's items are all taken. Item for item the same work and
// texels as rt/ao_items.wgsl; only who runs it differs.
//#include "common/ao_lane.wgsl"
//#include "common/ao_list_item.wgsl"

// Group 0, bindings 0-6: common/ao_list_item.wgsl.
// [0]: items taken so far (zeroed by the graph before the pass).
@group(0) @binding(7) var<storage, read_write> taken: array<atomic<u32>>;

@compute @workgroup_size(64, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let items = AO_LANES * listed[0];
    loop {
        let item = atomicAdd(&taken[0], 1u);
        if item >= items {
            break;
        }
        ao_trace_item(item);
    }
    trace_flush_stats();
}
