// Ambient occlusion (layers/rt_ao.ron), the spread schedule: runs where the list's length gives
// more than four lanes a pixel (common/ao_spread.wgsl: under a quarter of the frame covered)
// and returns at once otherwise (rt/ao_dense.wgsl has the pixels then). The invocation at
// texel t of `spread` runs item `ao_spread_item` of the list of pixels with rays
// (rt/ao_list.wgsl), lane item % lanes of entry item / lanes, and writes at the item's texel;
// items past the list's end return at once. Each ray keeps its samples whatever the lane count
// (common/ao_lane.wgsl); only the order of the pixel's sum changes.
//#include "common/ao_lane.wgsl"
//#include "common/ao_spread.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var list: texture_2d<u32>;
@group(0) @binding(5) var<storage, read> listed: array<u32>;
@group(0) @binding(6) var spread: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(spread);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let count = listed[0];
    let image = textureDimensions(position);
    let lanes = ao_spread_lanes(count, image.x * image.y, params.rays);
    let item = ao_spread_item(id.xy, size);
    if lanes == AO_LANES || item >= lanes * count {
        return;
    }
    let entry = item / lanes;
    let width = textureDimensions(list).x;
    let packed = textureLoad(list, vec2<u32>(entry % width, entry / width), 0).r;
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let p = textureLoad(position, pixel, 0);
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open_of(pixel, item % lanes, lanes, p.xyz, n);
    textureStore(spread, ao_spread_texel(item, size.x), vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
