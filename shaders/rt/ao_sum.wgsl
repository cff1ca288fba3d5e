// Ambient occlusion, second pass: a pixel's AO_LANES partial sums (rt/ao.wgsl) added in lane
// order and divided by the ray count; 1 on the sky.
//#include "common/ao_four_lanes_sum.wgsl"

@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var partial: texture_2d<f32>;
@group(0) @binding(4) var ao: texture_storage_2d<rgba16float, write>;

// 16x16 workgroups, as the other passes over every pixel (PERF.md steps 52-53: this one took
// as long in 8x8 ones, the tone map half as long again).
@compute @workgroup_size(16, 16)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    if textureLoad(position, id.xy, 0).w == 0.0 {
        textureStore(ao, id.xy, vec4<f32>(1.0));
        return;
    }
    let v = ao_four_lanes_open(partial, id.xy) / f32(max(params.rays, 1u));
    textureStore(ao, id.xy, vec4<f32>(v, v, v, 1.0));
}
