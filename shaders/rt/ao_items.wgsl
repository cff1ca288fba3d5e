// Ambient occlusion over the list of pixels with rays (layers/rt_ao_compacted.ron): item i is
// lane i % AO_LANES of the pixel at list entry i / AO_LANES (rt/ao_list.wgsl), so the
// invocations of a workgroup all have rays to trace wherever the pixels lie; items past the
// list's end return at once. Each item traces what rt/ao.wgsl's lane does
// (common/ao_lane.wgsl) and writes the same texel of `partial`, so `sum` gives the same bits.
//#include "common/ao_lane.wgsl"
//#include "common/ao_list_item.wgsl"

// Group 0: common/ao_list_item.wgsl.

// One row of 64 invocations: the items of a workgroup are consecutive (16 listed pixels).
@compute @workgroup_size(64, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x {
        return;
    }
    let item = id.y * size.x + id.x;
    if item >= AO_LANES * listed[0] {
        return;
    }
    ao_trace_item(item);
    trace_flush_stats();
}
