// Ambient occlusion: cosine-weighted any-hit rays of bounded length from offset G-buffer
// positions; V = unoccluded fraction. A pixel's rays are shared out over its workgroup's lanes
// (trace/pixel_rays.wgsl), each ray the one the pixel would trace itself.
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/blend.wgsl"
//#include "trace/pixel_rays.wgsl"

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

// What a pixel's AO rays start from (trace/pixel_rays.wgsl).
struct PixelRays {
    origin: vec3<f32>,
    range: f32,
    normal: vec3<f32>,
    // The pixel's stream (white noise) and frame offset into the sequence (R2).
    key: u32,
    rotation: vec2<f32>,
    frame_offset: u32,
}

// AO ray `i` of `pixel`: how much of it gets through, 1 or 0, or the transmittance of the
// BLEND surfaces it meets (common/blend.wgsl).
fn pixel_ray(pixel: PixelRays, i: u32) -> f32 {
    var u: vec2<f32>;
    if params.sampling == 0u {
        u = indexed_random2(pixel.key, i);
    } else {
        u = fract(r2_sample(i + pixel.frame_offset * params.rays) + pixel.rotation);
    }
    return trace_transmittance(Ray(pixel.origin, 0.0, cosine_hemisphere(pixel.normal, u), pixel.range));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    let inside = id.x < size.x && id.y < size.y;
    // Every lane goes on to `pixel_rays_sum`, which shares the rays out over the workgroup.
    let p = select(vec4<f32>(0.0), textureLoad(position, min(id.xy, size - 1u), 0), inside);
    let n = normalize(textureLoad(geo_normal, min(id.xy, size - 1u), 0).xyz);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    var pixel: PixelRays;
    pixel.origin = offset_ray_origin(p.xyz, n);
    pixel.range = params.range + params.range_scale * frame.scene_sphere.w;
    pixel.normal = n;
    pixel.key = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(params.seed + 0x9e3779b9u + frame_offset * 0x85ebca6bu)));
    pixel.rotation = pixel_random2(id.xy, params.seed);
    pixel.frame_offset = frame_offset;
    let rays = max(params.rays, 1u);
    let open = pixel_rays_sum(id.xy, pixel, inside && p.w != 0.0, rays);
    if inside {
        // The sky is open.
        let v = select(open / f32(rays), 1.0, p.w == 0.0);
        textureStore(ao, id.xy, vec4<f32>(v, v, v, 1.0));
    }
    trace_flush_stats();
}
