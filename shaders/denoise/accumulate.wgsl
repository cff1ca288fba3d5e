// Progressive accumulation (layers/accumulate.ron): the running mean of the signal over every
// frame since the camera last changed, restarted where the executor has no history or the
// view-projection moved, and after `max_frames` frames where it is above 0.
//#include "common/frame.wgsl"

struct Params {
    max_frames: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(7) var<uniform> params: Params;
@group(0) @binding(1) var signal: texture_2d<f32>;
@group(0) @binding(2) var mean_previous: texture_2d<f32>;
@group(0) @binding(3) var count_previous: texture_2d<f32>;
@group(0) @binding(4) var mean: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var color: texture_storage_2d<rgba16float, write>;
@group(0) @binding(6) var count: texture_storage_2d<r32float, write>;

// Whether the camera is where it was on the previous frame (and that frame's history is kept).
fn camera_still() -> bool {
    if frame.history_valid == 0u {
        return false;
    }
    for (var c = 0; c < 4; c++) {
        if any(frame.view_proj[c] != frame.prev_view_proj[c]) {
            return false;
        }
    }
    return true;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(mean);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let x = textureLoad(signal, id.xy, 0);
    var n = 0.0;
    var m = vec4<f32>(0.0);
    if camera_still() {
        n = textureLoad(count_previous, id.xy, 0).r;
        m = textureLoad(mean_previous, id.xy, 0);
        if params.max_frames > 0u && n >= f32(params.max_frames) {
            n = 0.0;
        }
    }
    let next = m + (x - m) / (n + 1.0);
    textureStore(mean, id.xy, next);
    textureStore(color, id.xy, next);
    textureStore(count, id.xy, vec4<f32>(n + 1.0, 0.0, 0.0, 0.0));
}
