// Ambient occlusion: cosine-weighted any-hit rays of bounded length from offset G-buffer
// positions; V = unoccluded fraction.
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/blend.wgsl"

struct Params {
    rays: u32,
    range: f32,
    range_scale: f32,
    sampling: u32,
    seed: u32,
    per_frame: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var ao: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(ao, id.xy, vec4<f32>(1.0));
        return;
    }
    let n = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    let origin = offset_ray_origin(p.xyz, n);
    let range = params.range + params.range_scale * frame.scene_sphere.w;
    let rotation = pixel_random2(id.xy, params.seed);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    var state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(params.seed + 0x9e3779b9u + frame_offset * 0x85ebca6bu)));
    // Each ray counts by how much of it gets through: 1 or 0, or the transmittance of the
    // BLEND surfaces it meets (common/blend.wgsl).
    var open = 0.0;
    for (var i = 0u; i < params.rays; i++) {
        var u: vec2<f32>;
        if params.sampling == 0u {
            u = next_random2(&state);
        } else {
            u = fract(r2_sample(i + frame_offset * params.rays) + rotation);
        }
        open += trace_transmittance(Ray(origin, 0.0, cosine_hemisphere(n, u), range));
    }
    let v = open / f32(max(params.rays, 1u));
    textureStore(ao, id.xy, vec4<f32>(v, v, v, 1.0));
    trace_flush_stats();
}
