// Lambert under the directional light (times the shadow mask) plus sky ambient (times AO).
//#include "common/frame.wgsl"
//#include "common/fullscreen.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var albedo: texture_2d<f32>;
@group(0) @binding(2) var normal: texture_2d<f32>;
@group(0) @binding(3) var visibility: texture_2d<f32>;

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4<f32> {
    let texel = vec2<u32>(in.position.xy);
    let a = textureLoad(albedo, texel, 0);
    if a.a == 0.0 {
        return vec4<f32>(0.0);
    }
    let n = normalize(textureLoad(normal, texel, 0).xyz);
    let vis = textureLoad(visibility, texel, 0);
    let l = frame.light_dir.xyz;
    let direct = max(dot(n, l), 0.0) * frame.light_dir.w * frame.light_color.rgb * vis.g;
    let sky = mix(vec3<f32>(0.35, 0.3, 0.25), vec3<f32>(0.6, 0.75, 1.0), 0.5 + 0.5 * n.y);
    let ambient = frame.light_color.a * sky * vis.r;
    return vec4<f32>(a.rgb * (direct + ambient), 1.0);
}
