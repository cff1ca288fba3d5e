// Tone map: exposure, then the ACES filmic fit (Narkowicz 2015), encoded as sRGB into an 8-bit
// target (a compute pass: storage textures cannot be sRGB, so the encoding is done here).
// The image is premultiplied by alpha: the sky gradient shows through 1 - alpha of each texel
// (all of it where nothing was drawn, a = 0; part of it behind translucent surfaces); with an
// environment map (`--env`), the map along each pixel's camera ray.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/environment.wgsl"

struct Params {
    exposure: f32,
    sky: u32,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(3) var<uniform> frame: Frame;

fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let c = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}

// The sRGB transfer function (IEC 61966-2-1), what an sRGB render target applies on store.
fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, 12.92 * c, c <= vec3<f32>(0.0031308));
}

// 16x16 workgroups: a pass over every pixel with little work each is not bound by its bytes;
// in 8x8 ones this pass took half as long again (PERF.md step 52).
@compute @workgroup_size(16, 16)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if any(id.xy >= size) {
        return;
    }
    let c = textureLoad(hdr, min(id.xy, textureDimensions(hdr) - vec2<u32>(1u)), 0);
    var linear = c.rgb;
    if (c.a < 1.0 && params.sky != 0u) {
        // Pixel centres, as the fragment stage saw them: v = 0 at the top, 1 at the bottom.
        let v = (f32(id.y) + 0.5) / f32(size.y);
        var backdrop = mix(vec3<f32>(0.9, 0.85, 0.8), vec3<f32>(0.35, 0.55, 0.9), 1.0 - v);
        if has_environment() {
            backdrop = environment_radiance_level(camera_dir(id.xy), 0.0);
        }
        linear += (1.0 - max(c.a, 0.0)) * backdrop;
    }
    textureStore(color, id.xy, vec4<f32>(srgb_encode(aces(linear * params.exposure)), 1.0));
}
