// Ambient occlusion with four lanes a pixel over the frame (layers/rt_ao_four_lanes.ron; the
// default layer, rt_ao, runs it after a frame at least an eighth covered and spreads the rays
// over more lanes after the others: rt/ao_spread.wgsl): cosine-weighted any-hit rays of bounded
// length from offset G-buffer positions; V = unoccluded fraction.
//
// A pixel's rays are shared by AO_LANES invocations (the pass runs over `partial`, twice the
// frame in each axis: texel (2x + i, 2y + j) is lane i + 2j of pixel (x, y)); lane k traces
// rays k, k + AO_LANES, ... (common/ao_lane.wgsl) and writes how much of them got through; `sum`
// (rt/ao_sum.wgsl) adds a pixel's lanes in order. Four times the invocations keep the GPU busy
// when few pixels have rays (a model covering a few percent of the frame): BENCHMARKS.md, "AO
// rays over four lanes". The lanes of sky pixels return at once; layers/rt_ao_compacted.ron
// and layers/rt_ao_persistent.ron run over a list of the pixels with rays instead.
//#include "common/ao_lane.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var partial: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = id.xy / 2u;
    let lane = (id.x & 1u) | ((id.y & 1u) << 1u);
    let p = textureLoad(position, pixel, 0);
    if p.w == 0.0 {
        return; // the sky: `sum` writes 1 without reading the lanes
    }
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open(pixel, lane, p.xyz, n);
    textureStore(partial, id.xy, vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
