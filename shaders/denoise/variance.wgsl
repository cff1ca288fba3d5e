// The signal packed with its luminance variance for the à-trous filter (layers/atrous.ron;
// -1 where the signal's alpha says there is none):
// from the temporal moments where 4 or more frames were accumulated (divided by their number:
// the variance of the accumulated mean), else from the 3x3
// neighbourhood of this frame (Schied et al. 2017, section 4.2), or 0 with `short_history`
// "unfiltered" (layers/atrous.ron).
//#include "common/atrous_params.wgsl"

@group(0) @binding(3) var<uniform> params: Params;
@group(0) @binding(0) var signal: texture_2d<f32>;
@group(0) @binding(1) var moments: texture_2d<f32>;
@group(0) @binding(2) var packed: texture_storage_2d<rgba16float, write>;

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(packed);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let s = textureLoad(signal, id.xy, 0);
    // A 1x1 `moments` is the layer's fallback (no temporal moments: z = 0).
    let m = textureLoad(moments, min(id.xy, textureDimensions(moments) - 1u), 0);
    // The moments give the variance of one frame's value over time; the signal is the mean of
    // m.z frames, whose variance is that over m.z. (The spatial estimate below is taken from
    // the signal itself.)
    var variance = max(m.y - m.x * m.x, 0.0) / max(m.z, 1.0);
    if m.z < 4.0 && params.short_history == SHORT_HISTORY_UNFILTERED {
        variance = 0.0;
    } else if m.z < 4.0 {
        var sum = 0.0;
        var sum2 = 0.0;
        let last = vec2<i32>(size) - 1;
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let l = luminance(textureLoad(signal, clamp(vec2<i32>(id.xy) + vec2<i32>(dx, dy), vec2<i32>(0), last), 0).rgb);
                sum += l;
                sum2 += l * l;
            }
        }
        variance = max(sum2 / 9.0 - (sum / 9.0) * (sum / 9.0), 0.0);
    }
    // A pixel without a signal (alpha 0: no reflection traced there) is marked by a negative
    // variance: the steps leave it out and keep its alpha 0.
    textureStore(packed, id.xy, vec4<f32>(s.rgb, select(variance, -1.0, s.a <= 0.0)));
}
