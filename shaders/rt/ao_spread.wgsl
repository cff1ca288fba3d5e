// Ambient occlusion spread over lanes (layers/rt_ao.ron's `ao_spread`, run in frames where
// fewer than an eighth of the pixels had AO rays the frame before): each pixel of the list
// (rt/ao_list.wgsl) gets the lane count of common/ao_lane_count.wgsl, 4 to 16, and the pass runs
// one invocation per (listed pixel, lane) item: the invocation at texel t of `spread` runs item
// `ao_spread_item(t)`, lane item % lanes of entry item / lanes, and items past the list's end
// return at once. Each ray keeps its samples whatever the lane count (common/ao_lane.wgsl).
//#include "common/ao_lane.wgsl"
//#include "common/ao_lane_count.wgsl"

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
    if item >= lanes * count {
        return;
    }
    let entry = item / lanes;
    let width = textureDimensions(list).x;
    let packed = textureLoad(list, vec2<u32>(entry % width, entry / width), 0).r;
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let lane = item % lanes;
    let p = textureLoad(position, pixel, 0);
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open_of(pixel, lane, lanes, p.xyz, n);
    textureStore(spread, ao_spread_texel(item, size.x), vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
