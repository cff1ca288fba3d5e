// Temporal accumulation (layers/temporal.ron): reprojected history blended with this frame's
// signal as a running mean, restarted at disocclusions, optionally clamped to the current
// neighbourhood's statistics.
//#include "common/frame.wgsl"

struct Params {
    max_history: u32,
    variance_clamp: u32,
    clamp_sigma: f32,
    history_taps: u32,
}

// `history_taps`' choices.
const HISTORY_TAPS_CONSISTENT: u32 = 0u;
const HISTORY_TAPS_BILINEAR: u32 = 1u;

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

// The history read at pixel position `at` (pixel centres at +0.5, clamped to the frame): the
// running mean and the moments, bilinearly from the four texels around it; with
// `history_taps` "consistent", less those whose mean is farther from this frame's luminance
// `now` than `clamp_sigma` times that texel's own deviation over time plus a rounding margin.
// A noise-free texel across a shadow's or an object's edge is left out (bilinear weights alone
// smear the edge, and a long history keeps the smear for many frames); a noisy one stays. If
// no texel is consistent, all four are used: an outlier sample of a noisy signal; but where
// every texel is noise-free too (no deviation over 4 frames or more), the history is stale (a
// mirror's image moves otherwise than its surface) and `stale` says so.
struct History {
    mean: vec4<f32>,
    moments: vec4<f32>,
    stale: bool,
}

fn reprojected_history(at: vec2<f32>, now: f32) -> History {
    let base = at - 0.5;
    let f = fract(base);
    let i0 = vec2<i32>(floor(base));
    let last = vec2<i32>(textureDimensions(mean_previous)) - 1;
    var weights = array<f32, 4>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    var means: array<vec4<f32>, 4>;
    var moments: array<vec4<f32>, 4>;
    var consistent = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    var consistent_weight = 0.0;
    var noise_free = true;
    for (var k = 0; k < 4; k++) {
        let texel = clamp(i0 + vec2<i32>(k & 1, k >> 1u), vec2<i32>(0), last);
        means[k] = textureLoad(mean_previous, texel, 0);
        moments[k] = textureLoad(moments_previous, texel, 0);
        let deviation = sqrt(max(moments[k].y - moments[k].x * moments[k].x, 0.0));
        let rounding = 0.01 * max(abs(now), abs(moments[k].x)) + 1e-4;
        let margin = params.clamp_sigma * deviation + rounding;
        // Noise-free means a deviation of 0 over 4 frames or more (one frame has none).
        noise_free = noise_free && (weights[k] == 0.0 || (moments[k].z >= 4.0 && deviation <= rounding));
        if params.history_taps == HISTORY_TAPS_BILINEAR || abs(luminance(means[k].rgb) - now) <= margin {
            consistent[k] = 1.0;
            consistent_weight += weights[k];
        }
    }
    var h: History;
    let use_consistent = consistent_weight > 1e-6;
    let total = select(1.0, consistent_weight, use_consistent);
    for (var k = 0; k < 4; k++) {
        let w = select(weights[k], weights[k] * consistent[k], use_consistent) / total;
        h.mean += w * means[k];
        h.moments += w * moments[k];
    }
    h.stale = !use_consistent && noise_free && params.history_taps == HISTORY_TAPS_CONSISTENT;
    return h;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(accumulated);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let now = textureLoad(signal, id.xy, 0);
    let l = luminance(now.rgb);
    let restarted = vec4<f32>(l, l * l, 1.0, 0.0);
    let m = textureLoad(motion, id.xy, 0);
    if m.z != 0.0 {
        // No history here: start again.
        store_accumulation(id.xy, now, restarted);
        return;
    }
    // Motion under a hundredth of a pixel is the rounding of the reprojection (a still camera
    // gives up to 1e-3 px): the history is read at the pixel itself, so that a long
    // accumulation does not drift by the bilinear weights of that rounding.
    let still = all(abs(m.xy) < vec2<f32>(0.01));
    let before = vec2<f32>(id.xy) + 0.5 - select(m.xy, vec2<f32>(0.0), still);
    let reprojected = reprojected_history(before, l);
    if reprojected.stale && !still {
        // Only a stale history, on a moving pixel: start again as at a disocclusion.
        store_accumulation(id.xy, now, restarted);
        return;
    }
    var history = reprojected.mean;
    let history_moments = reprojected.moments;
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
    store_accumulation(id.xy, mix(history, now, alpha), vec4<f32>(mix(history_moments.xy, vec2<f32>(l, l * l), alpha), n, 0.0));
}

// The running mean (kept, and the readers' copy) and the moments of pixel `id`.
fn store_accumulation(id: vec2<u32>, value: vec4<f32>, stats: vec4<f32>) {
    textureStore(mean, id, value);
    textureStore(accumulated, id, value);
    textureStore(moments, id, stats);
}
