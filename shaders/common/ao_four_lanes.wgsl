// The four-lane AO schedule's invocation at texel `texel` of `partial` (twice the image in
// each axis): lane i + 2j of pixel (x, y) at texel (2x + i, 2y + j) traces its rays
// (common/ao_lane.wgsl) and writes how much of them got through. Run by rt/ao.wgsl
// (layers/rt_ao_four_lanes.ron) and rt/ao_dense.wgsl (layers/rt_ao.ron on a frame mostly
// covered). The includer declares `position`, `geo_normal` and `partial`.
//#include "common/ao_lane.wgsl"

fn ao_four_lanes_texel(texel: vec2<u32>) {
    let pixel = texel / 2u;
    let lane = (texel.x & 1u) | ((texel.y & 1u) << 1u);
    let p = textureLoad(position, pixel, 0);
    if p.w == 0.0 {
        return; // the sky: `sum` writes 1 without reading the lanes
    }
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open(pixel, lane, p.xyz, n);
    textureStore(partial, texel, vec4<f32>(open, 0.0, 0.0, 0.0));
}
