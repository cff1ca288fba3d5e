// Ambient occlusion (cosine-weighted, stratified by a per-pixel rotated R2 sequence) and a hard
// shadow towards the directional light, both any-hit rays from offset G-buffer positions.
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"

struct Params {
    ao_rays: u32,
    ao_range: f32,
    shadows: u32,
    seed: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var visibility: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(visibility);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(visibility, id.xy, vec4<f32>(1.0, 1.0, 0.0, 0.0));
        return;
    }
    let n = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    let origin = offset_ray_origin(p.xyz, n);

    var lit = 1.0;
    if params.shadows != 0u {
        let l = frame.light_dir.xyz;
        if dot(n, l) <= 0.0 {
            lit = 0.0;
        } else if trace_any(Ray(origin, 0.0, l, 1e30)) {
            lit = 0.0;
        }
    }

    var open = 0u;
    let rotation = pixel_random2(id.xy, params.seed);
    for (var i = 0u; i < params.ao_rays; i++) {
        let dir = cosine_hemisphere(n, fract(r2_sample(i) + rotation));
        if !trace_any(Ray(origin, 0.0, dir, params.ao_range)) {
            open++;
        }
    }
    let ao = select(f32(open) / f32(params.ao_rays), 1.0, params.ao_rays == 0u);
    textureStore(visibility, id.xy, vec4<f32>(ao, lit, 0.0, 1.0));
    trace_flush_stats();
}
