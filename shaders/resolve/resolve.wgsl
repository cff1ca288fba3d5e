// Resolve of the hybrid and full-RT modes, as a compute pass (on GPUs with few graphics units,
// such as the H100, a full-screen fragment pass is several times slower): the shading model of
// common/lighting.wgsl on the G-buffer, with the shadowed direct light of `rt_shadow` (or, when
// it is switched off, every light unshadowed), sky ambient x AO x material occlusion,
// reflections x Fresnel (the sky's where no reflection ray was traced) and emission; with an
// environment map, its irradiance x the visibility rt_shadow traced (AO where it traced none).
// Inputs that may be 1x1 fallbacks are read at a clamped texel.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/lighting.wgsl"
//#include "common/gbuffer_lobes.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var position: texture_2d<f32>;
@group(0) @binding(2) var normal: texture_2d<f32>;
@group(0) @binding(3) var albedo: texture_2d<f32>;
@group(0) @binding(4) var material: texture_2d<f32>;
@group(0) @binding(5) var direct: texture_2d<f32>;
@group(0) @binding(6) var ao: texture_2d<f32>;
@group(0) @binding(7) var reflection: texture_2d<f32>;
@group(0) @binding(8) var emissive: texture_2d<f32>;
@group(0) @binding(9) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(10) var hdr: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var gi: texture_2d<f32>;
@group(0) @binding(12) var lobes: texture_2d<u32>;

fn load(t: texture_2d<f32>, p: vec2<u32>) -> vec4<f32> {
    return textureLoad(t, min(p, textureDimensions(t) - vec2<u32>(1u)), 0);
}

// 16x16 workgroups: a pass over every pixel with little work each is not bound by its bytes;
// in 8x8 ones this pass took 11-21% longer, the tone map half as long again (PERF.md step 52).
@compute @workgroup_size(16, 16)
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
    let m = load(material, texel);
    let e = load(emissive, texel);
    var s: ShadingPoint;
    s.position = p.xyz;
    s.normal = normalize(load(normal, texel).xyz);
    s.view = camera_view_dir(p.xyz);
    s.albedo = load(albedo, texel).rgb;
    s.metallic = m.r;
    s.roughness = m.g;
    s.occlusion = e.a;
    s.emissive = e.rgb;
    s.unlit = gbuffer_unlit(m.a);
    shading_lobes(&s, gbuffer_lobes(m.a, textureLoad(lobes, texel, 0), s.normal));
    if s.unlit {
        return vec4<f32>(surface_radiance(s, vec3<f32>(0.0), 1.0), 1.0);
    }
    let d = load(direct, texel);
    var lit = d.rgb;
    if d.a == 0.0 {
        // No shadow pass: every light unshadowed.
        for (var i = 0u; i < frame.light_count; i++) {
            lit += light_radiance(s, light_sample(scene_lights[i], s.position));
        }
    }
    var occlusion = load(ao, texel).r;
    if has_environment() && d.a >= 2.0 {
        // The map's visibility, where rt_shadow traced it (a = 2 + visibility), shadows its
        // light instead.
        occlusion = d.a - 2.0;
    }
    var color = surface_radiance(s, lit, occlusion);
    // Diffuse global illumination (0 without an rt_gi node).
    color += s.albedo * (1.0 - s.metallic) * s.occlusion * load(gi, texel).rgb;
    // Where no reflection ray was traced (a = 0: switched off, or too rough), the sky.
    let r = load(reflection, texel);
    if r.a > 0.0 {
        color += reflected_radiance(s, r.rgb);
    } else {
        color += sky_specular(s);
    }
    return vec4<f32>(color, 1.0);
}
