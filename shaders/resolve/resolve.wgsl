// Resolve of the hybrid and full-RT modes, as a compute pass (on GPUs with few graphics units,
// such as the H100, a full-screen fragment pass is several times slower). Inputs that may be
// 1x1 fallbacks are read at a clamped texel.
//#include "common/frame.wgsl"
//#include "common/lighting.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var position: texture_2d<f32>;
@group(0) @binding(2) var normal: texture_2d<f32>;
@group(0) @binding(3) var albedo: texture_2d<f32>;
@group(0) @binding(4) var material: texture_2d<f32>;
@group(0) @binding(5) var shadow: texture_2d<f32>;
@group(0) @binding(6) var ao: texture_2d<f32>;
@group(0) @binding(7) var reflection: texture_2d<f32>;
@group(0) @binding(8) var hdr: texture_storage_2d<rgba16float, write>;

fn load(t: texture_2d<f32>, p: vec2<u32>) -> vec4<f32> {
    return textureLoad(t, min(p, textureDimensions(t) - vec2<u32>(1u)), 0);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = id.xy;
    if any(texel >= textureDimensions(hdr)) {
        return;
    }
    textureStore(hdr, texel, shade(texel));
}

fn shade(texel: vec2<u32>) -> vec4<f32> {
    let p = load(position, texel);
    if p.w == 0.0 {
        return vec4<f32>(0.0); // sky: the tone-map pass draws it
    }
    let n = normalize(load(normal, texel).xyz);
    let a = load(albedo, texel).rgb;
    let m = load(material, texel);
    let sh = load(shadow, texel);
    let occlusion = load(ao, texel).r;
    let refl = load(reflection, texel).rgb;
    let v = normalize(frame.camera_pos.xyz - p.xyz);
    var color = frame.light_color.a * sky_color(n) * a * (1.0 - m.r) * occlusion;
    color += sh.r * brdf_light(n, v, frame.light_dir.xyz, frame.light_color.rgb * frame.light_dir.w, a, m.r, m.g);
    if frame.point_light.w > 0.0 {
        let to_light = frame.point_light.xyz - p.xyz;
        let d2 = max(dot(to_light, to_light), 1e-8);
        color += sh.g * brdf_light(n, v, to_light * inverseSqrt(d2), frame.point_color.rgb * frame.point_light.w / d2, a, m.r, m.g);
    }
    color += fresnel_schlick(dot(n, v), specular_f0(a, m.r)) * refl;
    color += vec3<f32>(m.b * 16.0) * a;
    return vec4<f32>(color, 1.0);
}
