// Hard shadows: any-hit rays from the offset G-buffer position to each light.
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "trace/trace.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var position: texture_2d<f32>;
@group(0) @binding(2) var geo_normal: texture_2d<f32>;
@group(0) @binding(3) var shadow: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shadow);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(shadow, id.xy, vec4<f32>(1.0));
        return;
    }
    let n = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    let origin = offset_ray_origin(p.xyz, n);
    var sun = 0.0;
    let l = frame.light_dir.xyz;
    if dot(n, l) > 0.0 && !trace_any(Ray(origin, 0.0, l, 3.0e38)) {
        sun = 1.0;
    }
    var point = 0.0;
    if frame.point_light.w > 0.0 {
        let to_light = frame.point_light.xyz - origin;
        let dist = length(to_light);
        let dir = to_light / dist;
        // Stop just short of the light: nothing behind it can shadow.
        if dot(n, dir) > 0.0 && !trace_any(Ray(origin, 0.0, dir, dist * 0.9999)) {
            point = 1.0;
        }
    }
    textureStore(shadow, id.xy, vec4<f32>(sun, point, 0.0, 1.0));
    trace_flush_stats();
}
