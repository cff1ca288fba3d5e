// Ambient occlusion over the list of pixels with rays, each pixel's rays spread over as many
// lanes as fill one invocation an image pixel (layers/rt_ao_spread.ron; the lane count:
// common/ao_spread.wgsl). Item i is lane i % lanes of the pixel at list entry i / lanes
// (rt/ao_list.wgsl); items past the list's end return at once. With four lanes an item traces
// what rt/ao.wgsl's lane does, bit for bit; with more, each ray keeps its samples and only the
// order of the sum changes.
//#include "common/ao_lane.wgsl"
//#include "common/ao_spread.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var list: texture_2d<u32>;
@group(0) @binding(5) var<storage, read> listed: array<u32>;
@group(0) @binding(6) var partial: texture_storage_2d<r32float, write>;

// One row of 64 invocations: a workgroup's items are consecutive, a pixel's lanes side by side.
@compute @workgroup_size(64, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let item = id.y * size.x + id.x;
    let count = listed[0];
    let image = textureDimensions(position);
    let lanes = ao_spread_lanes(count, image.x * image.y, params.rays);
    if item >= lanes * count {
        return;
    }
    let entry = item / lanes;
    let width = textureDimensions(list).x;
    let packed = textureLoad(list, vec2<u32>(entry % width, entry / width), 0).r;
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let p = textureLoad(position, pixel, 0);
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open_of(pixel, item % lanes, lanes, p.xyz, n);
    textureStore(partial, id.xy, vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
