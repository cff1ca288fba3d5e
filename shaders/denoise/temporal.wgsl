// Temporal accumulation (layers/temporal.ron): reprojected history blended with this frame's
// signal as a running mean, restarted at disocclusions, optionally clamped to the current
// neighbourhood's statistics.
//#include "common/frame.wgsl"

struct Params {
    max_history: u32,
    variance_clamp: u32,
    clamp_sigma: f32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var signal: texture_2d<f32>;
@group(0) @binding(3) var motion: texture_2d<f32>;
@group(0) @binding(4) var mean_previous: texture_2d<f32>;
@group(0) @binding(5) var moments_previous: texture_2d<f32>;
@group(0) @binding(6) var mean: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var accumulated: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var moments: texture_storage_2d<rgba32float, write>;

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// `t` bilinearly at pixel position `at` (pixel centres at +0.5), clamped to the frame.
fn bilinear(t: texture_2d<f32>, at: vec2<f32>) -> vec4<f32> {
    let base = at - 0.5;
    let f = fract(base);
    let i0 = vec2<i32>(floor(base));
    let last = vec2<i32>(textureDimensions(t)) - 1;
    let a = textureLoad(t, clamp(i0, vec2<i32>(0), last), 0);
    let b = textureLoad(t, clamp(i0 + vec2<i32>(1, 0), vec2<i32>(0), last), 0);
    let c = textureLoad(t, clamp(i0 + vec2<i32>(0, 1), vec2<i32>(0), last), 0);
    let d = textureLoad(t, clamp(i0 + vec2<i32>(1, 1), vec2<i32>(0), last), 0);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(accumulated);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let now = textureLoad(signal, id.xy, 0);
    let l = luminance(now.rgb);
    let m = textureLoad(motion, id.xy, 0);
    if m.z != 0.0 {
        // No history here: start again.
        textureStore(mean, id.xy, now);
        textureStore(accumulated, id.xy, now);
        textureStore(moments, id.xy, vec4<f32>(l, l * l, 1.0, 0.0));
        return;
    }
    // Motion under a hundredth of a pixel is the rounding of the reprojection (a still camera
    // gives up to 1e-3 px): the history is read at the pixel itself, so that a long
    // accumulation does not drift by the bilinear weights of that rounding.
    let still = all(abs(m.xy) < vec2<f32>(0.01));
    let before = vec2<f32>(id.xy) + 0.5 - select(m.xy, vec2<f32>(0.0), still);
    var history = bilinear(mean_previous, before);
    let history_moments = bilinear(moments_previous, before);
    if params.variance_clamp != 0u {
        var sum = vec4<f32>(0.0);
        var sum2 = vec4<f32>(0.0);
        let last = vec2<i32>(size) - 1;
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let v = textureLoad(signal, clamp(vec2<i32>(id.xy) + vec2<i32>(dx, dy), vec2<i32>(0), last), 0);
                sum += v;
                sum2 += v * v;
            }
        }
        let local_mean = sum / 9.0;
        // The window: this frame's 3x3 deviation widened by the pixel's own deviation over
        // time (from the moments). A signal of one or two rays a pixel is heavy-tailed (most
        // GI rays return nothing): nine dark neighbours have no deviation at all, and a window
        // of theirs alone would clamp a correct history to black (measured: 1-ray GI on the
        // atrium came out at 7x the relMSE of no clamp after 32 frames).
        let over_time = sqrt(max(history_moments.y - history_moments.x * history_moments.x, 0.0));
        let sigma = sqrt(max(sum2 / 9.0 - local_mean * local_mean, vec4<f32>(0.0))) + over_time;
        history = clamp(history, local_mean - params.clamp_sigma * sigma, local_mean + params.clamp_sigma * sigma);
    }
    let n = min(floor(history_moments.z + 0.5) + 1.0, f32(params.max_history));
    let alpha = 1.0 / n;
    let blended = mix(history, now, alpha);
    textureStore(mean, id.xy, blended);
    textureStore(accumulated, id.xy, blended);
    textureStore(moments, id.xy, vec4<f32>(mix(history_moments.xy, vec2<f32>(l, l * l), alpha), n, 0.0));
}
