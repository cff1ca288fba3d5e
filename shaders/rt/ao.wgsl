// Ambient occlusion: cosine-weighted any-hit rays of bounded length from offset G-buffer
// positions; V = unoccluded fraction.
//
// A pixel's rays are shared by AO_LANES invocations (the pass runs over `partial`, twice the
// frame in each axis: texel (2x + i, 2y + j) is lane i + 2j of pixel (x, y)); lane k traces
// rays k, k + AO_LANES, ... (in rounds: the lanes of a subgroup trace together) and writes
// how much of them got through; `sum` (rt/ao_sum.wgsl) adds a pixel's lanes in order. Four
// times the invocations keep the GPU busy when few pixels have rays (a model covering a few
// percent of the frame): BENCHMARKS.md, "AO rays over four lanes".
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"
//#include "common/ray_blend.wgsl"
//#include "common/ao_params.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var partial: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(partial);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = id.xy / 2u;
    let lane = (id.x & 1u) | ((id.y & 1u) << 1u);
    let p = textureLoad(position, pixel, 0);
    if p.w == 0.0 {
        return; // the sky: `sum` writes 1 without reading the lanes
    }
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let origin = offset_ray_origin(p.xyz, n);
    let range = params.range + params.range_scale * frame.scene_sphere.w;
    let rotation = pixel_random2(pixel, params.seed);
    // With `per_frame`, every frame draws new samples: R2 goes on along its sequence, white
    // noise is seeded again.
    let frame_offset = select(0u, frame.frame_index, params.per_frame != 0u);
    var state = pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(params.seed + 0x9e3779b9u + frame_offset * 0x85ebca6bu)));
    // Each ray counts by how much of it gets through: 1 or 0, or the transmittance of the
    // BLEND surfaces it meets (common/ray_blend.wgsl).
    var open = 0.0;
    // Every lane runs the same number of rounds, so the lanes of a subgroup trace together.
    let rounds = (params.rays + AO_LANES - 1u) / AO_LANES;
    for (var round = 0u; round < rounds; round++) {
        let i = round * AO_LANES + lane;
        var u: vec2<f32>;
        if params.sampling == 0u {
            // One stream per pixel, drawn in ray order by every lane: each ray keeps its
            // numbers (lane k takes the k-th of each AO_LANES draws).
            for (var k = 0u; k < AO_LANES; k++) {
                let drawn = next_random2(&state);
                if k == lane {
                    u = drawn;
                }
            }
        } else {
            u = fract(r2_sample(i + frame_offset * params.rays) + rotation);
        }
        if i < params.rays {
            open += trace_transmittance(Ray(origin, 0.0, cosine_hemisphere(n, u), range));
        }
    }
    textureStore(partial, id.xy, vec4<f32>(open, 0.0, 0.0, 0.0));
    trace_flush_stats();
}
