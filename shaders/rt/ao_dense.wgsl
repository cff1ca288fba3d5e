// Ambient occlusion (layers/rt_ao.ron), the four-lane schedule over the frame: runs where the
// list's length gives four lanes a pixel (common/ao_spread.wgsl: a frame at least a quarter
// covered) and returns at once otherwise, leaving the pixels to rt/ao_spread.wgsl. The same
// code as rt/ao.wgsl (common/ao_four_lanes.wgsl), so the same bits.
//#include "common/ao_four_lanes.wgsl"
//#include "common/ao_spread.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> listed: array<u32>;
@group(0) @binding(5) var partial: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let image = textureDimensions(position);
    if ao_spread_lanes(listed[0], image.x * image.y, params.rays) != AO_LANES {
        return;
    }
    ao_four_lanes_texel(id.xy);
    trace_flush_stats();
}
