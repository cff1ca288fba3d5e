// The à-trous steps of layers/atrous.ron: `source` filtered into `result` with taps 1, 2, 4 or
// 8 pixels apart (one entry point per step; common/atrous_step.wgsl).
//#include "common/frame.wgsl"
//#include "common/atrous_step.wgsl"

//#include "common/atrous_params.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var position: texture_2d<f32>;
@group(0) @binding(4) var normal: texture_2d<f32>;
@group(0) @binding(5) var result: texture_storage_2d<rgba16float, write>;

// The last step writes alpha 1 where the filtered signal is there, instead of the variance,
// and 0 where the signal had none (a negative variance, see denoise/variance.wgsl).
fn filter_pixel(id: vec2<u32>, step: i32, last: bool) {
    let size = textureDimensions(result);
    if id.x < size.x && id.y < size.y {
        let v = atrous_step(source, vec2<i32>(id), step);
        textureStore(result, id, select(v, vec4<f32>(v.rgb, select(1.0, 0.0, v.a < 0.0)), last));
    }
}

@compute @workgroup_size(8, 8)
fn step_1(@builtin(global_invocation_id) id: vec3<u32>) {
    filter_pixel(id.xy, 1, false);
}

@compute @workgroup_size(8, 8)
fn step_2(@builtin(global_invocation_id) id: vec3<u32>) {
    filter_pixel(id.xy, 2, false);
}

@compute @workgroup_size(8, 8)
fn step_4(@builtin(global_invocation_id) id: vec3<u32>) {
    filter_pixel(id.xy, 4, false);
}

@compute @workgroup_size(8, 8)
fn step_8(@builtin(global_invocation_id) id: vec3<u32>) {
    filter_pixel(id.xy, 8, true);
}
