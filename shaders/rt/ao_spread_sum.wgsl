// Ambient occlusion, second pass (layers/rt_ao.ron): a pixel's lanes (rt/ao_spread.wgsl) added
// in lane order and divided by the ray count; 1 on the sky. Four lanes: invocation (x, y) adds
// the 2x2 texels over its pixel, as rt/ao_sum.wgsl. More lanes: invocation (x, y) writes 1 on
// its pixel if it is the sky, and, if list entry y * width + x exists (the list is as wide as
// the image: that entry's texel is (x, y)), adds that entry's lanes and writes that pixel.
//#include "common/ao_lane_count.wgsl"
//#include "common/ao_four_lanes_sum.wgsl"

@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var list: texture_2d<u32>;
@group(0) @binding(4) var<storage, read> listed: array<u32>;
@group(0) @binding(5) var partial: texture_2d<f32>;
@group(0) @binding(6) var ao: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let sky = textureLoad(position, id.xy, 0).w == 0.0;
    if sky {
        textureStore(ao, id.xy, vec4<f32>(1.0));
    }
    let count = listed[0];
    let lanes = ao_spread_lanes(count, size.x * size.y, params.rays);
    if lanes == AO_LANES {
        if !sky {
            store_open(id.xy, ao_four_lanes_open(partial, id.xy));
        }
        return;
    }
    let entry = id.y * size.x + id.x;
    if entry >= count {
        return;
    }
    let packed = textureLoad(list, id.xy, 0).r;
    let width = textureDimensions(partial).x;
    var open = 0.0;
    for (var lane = 0u; lane < lanes; lane++) {
        open += textureLoad(partial, ao_spread_texel(entry * lanes + lane, width), 0).r;
    }
    store_open(vec2<u32>(packed & 0xffffu, packed >> 16u), open);
}

fn store_open(pixel: vec2<u32>, open: f32) {
    let v = open / f32(max(params.rays, 1u));
    textureStore(ao, pixel, vec4<f32>(v, v, v, 1.0));
}
