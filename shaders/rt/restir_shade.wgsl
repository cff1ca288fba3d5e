// ReSTIR DI, shading (common/restir.wgsl): the light of the sample each pixel's reservoir keeps
// (after spatial reuse, rt/restir_spatial.wgsl), times its W and its shadow ray's visibility:
// the pixel's direct light.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/lighting.wgsl"
//#include "common/scene.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/sampling.wgsl"
//#include "common/emitters.wgsl"
//#include "trace/trace.wgsl"
//#include "common/shadow_ray.wgsl"
//#include "common/restir_bindings.wgsl"
//#include "common/restir.wgsl"
//#include "common/restir_visibility.wgsl"

@group(0) @binding(12) var kept: texture_2d<u32>;
@group(0) @binding(13) var direct: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(direct);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let at = restir_surface(id.xy);
    if !at.valid {
        textureStore(direct, id.xy, vec4<f32>(0.0));
        return;
    }
    let r = reservoir_unpack(textureLoad(kept, id.xy, 0));
    var light = vec3<f32>(0.0);
    if r.light != RESTIR_NONE {
        let toward = restir_light(at, r.light, r.uv);
        light = toward.radiance * r.weight * restir_visibility(at, r.light, toward);
    }
    // a = 1: the direct light was computed here (the resolve's fallback has a = 0); 2 where the
    // environment map is among the samples (a = 2 + its visibility, as rt_shadow writes it: 0,
    // for the resolve adds no light of the map's own, which is in `light`).
    textureStore(direct, id.xy, vec4<f32>(light, select(1.0, 2.0, restir_environment())));
    trace_flush_stats();
}
