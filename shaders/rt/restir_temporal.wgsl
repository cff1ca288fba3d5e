// ReSTIR DI, temporal reuse (common/restir.wgsl): each pixel's reservoir combined with the one
// its surface had on the previous frame (through `motion`; none where it is disoccluded), whose
// candidate count is capped at `max_history` times this frame's. Without `temporal`, a copy.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/ray_offset.wgsl"
//#include "common/lighting.wgsl"
//#include "common/scene.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/sampling.wgsl"
//#include "common/emitters.wgsl"
//#include "common/restir_bindings.wgsl"
//#include "common/restir.wgsl"

@group(0) @binding(12) var candidates: texture_2d<u32>;
@group(0) @binding(13) var motion: texture_2d<f32>;
@group(0) @binding(14) var reservoirs_previous: texture_2d<u32>;
@group(0) @binding(15) var temporal: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(temporal);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let current = reservoir_unpack(textureLoad(candidates, id.xy, 0));
    let m = textureLoad(motion, id.xy, 0);
    let at = restir_surface(id.xy);
    let was = vec2<i32>(floor(vec2<f32>(id.xy) + 0.5 - m.xy));
    let inside = all(was >= vec2<i32>(0)) && all(was < vec2<i32>(size));
    if params.temporal == 0u || !at.valid || m.z != 0.0 || !inside {
        textureStore(temporal, id.xy, reservoir_pack(current));
        return;
    }
    var previous = reservoir_unpack(textureLoad(reservoirs_previous, was, 0));
    var state = pcg_hash(id.x ^ pcg_hash(id.y ^ pcg_hash(0x9e3779b9u ^ frame_seed(params.seed, frame.frame_index, params.per_frame))));
    var stream = restir_stream();
    restir_offer(&stream, current, restir_target(at, current.light, current.uv), current.count, next_random1(&state));
    let capped = min(previous.count, params.max_history * max(current.count, 1.0));
    restir_offer(&stream, previous, restir_target(at, previous.light, previous.uv), capped, next_random1(&state));
    textureStore(temporal, id.xy, reservoir_pack(restir_finish(stream)));
}
