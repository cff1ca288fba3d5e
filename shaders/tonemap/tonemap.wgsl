// Tone map: exposure, then the ACES filmic fit (Narkowicz 2015), into an sRGB target.
// Texels with alpha 0 (nothing drawn) show a sky gradient.
//#include "common/fullscreen.wgsl"

struct Params {
    exposure: f32,
    sky: u32,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: Params;

fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let c = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4<f32> {
    let size = textureDimensions(hdr);
    let texel = min(vec2<u32>(in.position.xy), size - vec2<u32>(1u));
    let c = textureLoad(hdr, texel, 0);
    var color = c.rgb;
    if (c.a == 0.0 && params.sky != 0u) {
        color = mix(vec3<f32>(0.9, 0.85, 0.8), vec3<f32>(0.35, 0.55, 0.9), in.uv.y * -1.0 + 1.0);
    }
    return vec4<f32>(aces(color * params.exposure), 1.0);
}
