// The viewer's pass inspector: a copy of a graph texture (any float colour format) drawn into
// the viewer's display texture, `value * scale + bias` per channel (one channel as grey, two
// as red and green), clamped to [0, 1] and sRGB-encoded when the values are linear (egui draws
// gamma-encoded rgba8unorm textures). Non-finite texels show magenta.

struct Visualize {
    scale: vec4<f32>,
    bias: vec4<f32>,
    // 1: grey from r; 2: r and g; 3 or 4: rgb
    channels: u32,
    // 1: linear values, sRGB-encode them; 0: already display-encoded (the graph's output)
    encode_srgb: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var display: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(2) var<uniform> vis: Visualize;

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

fn finite(v: vec4<f32>) -> bool {
    // NaN fails every comparison; infinities exceed the largest f32.
    return all(abs(v) <= vec4<f32>(3.4e38));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(display);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let src = textureDimensions(source);
    let p = min(id.xy * src / size, src - vec2<u32>(1u));
    let raw = textureLoad(source, p, 0);
    if (!finite(raw)) {
        textureStore(display, id.xy, vec4<f32>(1.0, 0.0, 1.0, 1.0));
        return;
    }
    var v = raw * vis.scale + vis.bias;
    if (vis.channels == 1u) {
        v = vec4<f32>(v.r, v.r, v.r, 1.0);
    } else if (vis.channels == 2u) {
        v = vec4<f32>(v.r, v.g, 0.0, 1.0);
    }
    var rgb = clamp(v.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    if (vis.encode_srgb == 1u) {
        rgb = srgb_encode(rgb);
    }
    textureStore(display, id.xy, vec4<f32>(rgb, 1.0));
}
