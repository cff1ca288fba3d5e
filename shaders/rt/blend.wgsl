// The rt_blend layer: the BLEND surfaces in front of each pixel's G-buffer surface composited
// front to back over the resolved image (common/hit_lighting.wgsl's composite_blend). The
// pixel's ray is the primary ray of common/primary_rays.wgsl (the rasterizer's sample
// position), cut just short of the G-buffer surface; textures are read at the mip level of the
// pixel's ray cone. The image is premultiplied (the sky, a = 0, shows through what the surfaces
// leave uncovered). Without BLEND materials (SCENE_BLEND false) the image is copied through.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_bindings.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/sampling.wgsl"
//#include "common/lighting.wgsl"
//#include "trace/trace.wgsl"
//#include "common/surface.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/hit_lighting.wgsl"

// Bindings 0 to 6: the frame and the scene (common/scene_bindings.wgsl).
@group(0) @binding(7) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(8) var position: texture_2d<f32>;
@group(0) @binding(9) var hdr: texture_2d<f32>;
@group(0) @binding(10) var color: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    var c = textureLoad(hdr, id.xy, 0);
    if SCENE_BLEND {
        let origin = camera_origin(id.xy);
        let dir = camera_dir(id.xy);
        // Up to the G-buffer's surface (w = 0: the sky, no end), stopping 1e-4 of the way
        // short of it so that the surface itself is not met.
        let p = textureLoad(position, id.xy, 0);
        let t_max = select(3.0e38, dot(p.xyz - origin, dir) * 0.9999, p.w != 0.0);
        if t_max > 0.0 {
            let cone = camera_cone_width(id.xy, 0.0);
            let layers = composite_blend(Ray(origin, 0.0, dir, t_max), cone, camera_cone_width(id.xy, 1.0) - cone);
            // Premultiplied: alpha is how much of the pixel is covered (the tone-map pass
            // shows the sky through the rest).
            let through = dot(layers.transmittance, vec3<f32>(1.0 / 3.0));
            c = vec4<f32>(layers.radiance + layers.transmittance * c.rgb, 1.0 - through * (1.0 - c.a));
        }
    }
    textureStore(color, id.xy, c);
    trace_flush_stats();
}
