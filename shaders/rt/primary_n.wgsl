// N closest-hit primary rays per pixel through R2-stratified points of the pixel; the output
// is the fraction that hit (no shading). Perspective cameras only: `bench rays` gives it no
// other (src/bench/rays.rs).
//#include "common/frame.wgsl"
//#include "common/sampling.wgsl"
//#include "trace/trace.wgsl"

struct Params {
    rays: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_storage_2d<rgba8unorm, write>;

// 8x4: the Miss and Stress tests ran 2-8% faster on the H100 than in 8x8 workgroups (PERF.md).
@compute @workgroup_size(8, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let origin = frame.camera_pos.xyz;
    var hits = 0u;
    for (var i = 0u; i < params.rays; i++) {
        let s = r2_sample(i);
        let ndc = vec2<f32>((f32(id.x) + s.x) * frame.resolution.z * 2.0 - 1.0, 1.0 - (f32(id.y) + s.y) * frame.resolution.w * 2.0);
        let far = frame.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
        let dir = normalize(far.xyz / far.w - origin);
        if trace_closest(Ray(origin, 0.0, dir, 3.0e38)).instance != NO_HIT {
            hits++;
        }
    }
    let f = f32(hits) / f32(max(params.rays, 1u));
    textureStore(color, id.xy, vec4<f32>(f, f, f, 1.0));
    trace_flush_stats();
}
