// Ambient occlusion (layers/rt_ao.ron), over `partial` (twice the image in each axis), with the
// lane count of common/ao_lane_count.wgsl. Four lanes (a frame at least a quarter covered): texel
// (2x + i, 2y + j) is lane i + 2j of pixel (x, y), as in rt/ao.wgsl, bit for bit. More lanes:
// the invocation runs item `ao_spread_item` of the list of pixels with rays (rt/ao_list.wgsl),
// lane item % lanes of entry item / lanes, and items past the list's end return at once. Each
// ray keeps its samples whatever the lane count (common/ao_lane.wgsl).
//#include "common/ao_lane.wgsl"
//#include "common/ao_lane_count.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var list: texture_2d<u32>;
@group(0) @binding(5) var<storage, read> listed: array<u32>;
@group(0) @binding(6) var partial: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let count = listed[0];
    let image = textureDimensions(position);
    let lanes = ao_spread_lanes(count, image.x * image.y, params.rays);
    var pixel = id.xy / 2u;
    var lane = (id.x & 1u) | ((id.y & 1u) << 1u);
    var texel = id.xy;
    if lanes != AO_LANES {
        let item = ao_spread_item(id.xy, size);
        if item >= lanes * count {
            return;
        }
        let entry = item / lanes;
        let width = textureDimensions(list).x;
        let packed = textureLoad(list, vec2<u32>(entry % width, entry / width), 0).r;
        pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
        lane = item % lanes;
        texel = ao_spread_texel(item, size.x);
    }
    let p = textureLoad(position, pixel, 0);
    if p.w == 0.0 {
        return; // the sky: `sum` writes 1 without reading the lanes
    }
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open_of(pixel, lane, lanes, p.xyz, n);
    textureStore(partial, texel, vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
