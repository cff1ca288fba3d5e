// Ambient occlusion, last pass (layers/rt_ao.ron): a pixel's lanes added in lane order and
// divided by the ray count; 1 on the sky. In a frame that ran the four lanes (`ao`, rt/ao.wgsl:
// the list did not run, and `listed` was zeroed), invocation (x, y) adds the 2x2 texels of
// `partial` over its pixel, as rt/ao_sum.wgsl. In a frame that ran `ao_spread` (a list of
// pixels with rays; an empty list is all sky), invocation (x, y) adds list entry y * width + x's
// lanes from `spread` (the list is as wide as the image: that entry's texel is (x, y)) and
// writes that pixel. Either way it counts the pixels with rays of a sample of the frame into
// `covered`: the 16x16 tiles of even column and row (a quarter of the frame), their pixels
// with rays in word 0 and their pixels in word 1; the next frame's `runs_when` picks the
// schedule from them. One global atomic add per counted tile: adding every tile's count to one
// counter (57,600 adds at 2560x1440 with 8x8 workgroups) doubled the pass's 0.043 ms on the
// GPU machine (BENCHMARKS.md, "Two AO schedules, picked from the frame before").
//#include "common/ao_lane_count.wgsl"
//#include "common/ao_four_lanes_sum.wgsl"

@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var list: texture_2d<u32>;
@group(0) @binding(4) var<storage, read> listed: array<u32>;
@group(0) @binding(5) var partial: texture_2d<f32>;
@group(0) @binding(6) var spread: texture_2d<f32>;
@group(0) @binding(7) var ao: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var<storage, read_write> covered: array<atomic<u32>>;

var<workgroup> group_covered: atomic<u32>;

@compute @workgroup_size(16, 16)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    let size = textureDimensions(ao);
    let inside = id.x < size.x && id.y < size.y;
    var sky = true;
    if inside {
        sky = textureLoad(position, id.xy, 0).w == 0.0;
        sum_lanes(id.xy, size, sky);
    }
    // Uniform in the workgroup: whether its tile is in the sample.
    let counted = (group.x & 1u) == 0u && (group.y & 1u) == 0u;
    if counted && !sky {
        atomicAdd(&group_covered, 1u);
    }
    workgroupBarrier();
    if counted && local == 0u {
        atomicAdd(&covered[0], atomicLoad(&group_covered));
        if all(group.xy == vec2<u32>(0u)) {
            atomicStore(&covered[1], sampled_pixels(size.x) * sampled_pixels(size.y));
        }
    }
}

// How many pixels of an axis of `n` the tiles of even index hold: 16 of every 32, and of the
// last 32 or fewer, up to 16.
fn sampled_pixels(n: u32) -> u32 {
    return (n / 32u) * 16u + min(n % 32u, 16u);
}

// Writes the AO of pixel `id` (four lanes) or of list entry `id` (spread); 1 where `id` is sky.
fn sum_lanes(id: vec2<u32>, size: vec2<u32>, sky: bool) {
    if sky {
        textureStore(ao, id, vec4<f32>(1.0));
    }
    let count = listed[0];
    if count == 0u {
        if !sky {
            store_open(id, ao_four_lanes_open(partial, id));
        }
        return;
    }
    let entry = id.y * size.x + id.x;
    if entry >= count {
        return;
    }
    let lanes = ao_spread_lanes(count, size.x * size.y, params.rays);
    let packed = textureLoad(list, id, 0).r;
    let width = textureDimensions(spread).x;
    var open = 0.0;
    for (var lane = 0u; lane < lanes; lane++) {
        open += textureLoad(spread, ao_spread_texel(entry * lanes + lane, width), 0).r;
    }
    store_open(vec2<u32>(packed & 0xffffu, packed >> 16u), open);
}

fn store_open(pixel: vec2<u32>, open: f32) {
    let v = open / f32(max(params.rays, 1u));
    textureStore(ao, pixel, vec4<f32>(v, v, v, 1.0));
}
