// The spread AO schedule's second pass (layers/rt_ao_spread.ron): invocation (x, y) writes 1
// on pixel (x, y) if it is the sky, and, if list entry y * width + x exists (the list is as
// wide as the image: that entry's texel is (x, y)), adds that pixel's lanes in lane order
// (rt/ao_spread.wgsl) and writes their mean over the rays.
//#include "common/ao_spread.wgsl"

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
    if textureLoad(position, id.xy, 0).w == 0.0 {
        textureStore(ao, id.xy, vec4<f32>(1.0));
    }
    let entry = id.y * size.x + id.x;
    let count = listed[0];
    if entry >= count {
        return;
    }
    let lanes = ao_spread_lanes(count, size.x * size.y, params.rays);
    let packed = textureLoad(list, id.xy, 0).r;
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let width = textureDimensions(partial).x;
    var open = 0.0;
    for (var lane = 0u; lane < lanes; lane++) {
        open += textureLoad(partial, ao_spread_texel(entry * lanes + lane, width), 0).r;
    }
    let v = open / f32(max(params.rays, 1u));
    textureStore(ao, pixel, vec4<f32>(v, v, v, 1.0));
}
