// Ambient occlusion, second pass: a pixel's AO_LANES partial sums (rt/ao.wgsl) added in lane
// order and divided by the ray count; 1 on the sky.
//#include "common/ao_params.wgsl"

@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var partial: texture_2d<f32>;
@group(0) @binding(4) var ao: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    if textureLoad(position, id.xy, 0).w == 0.0 {
        textureStore(ao, id.xy, vec4<f32>(1.0));
        return;
    }
    var open = 0.0;
    for (var lane = 0u; lane < AO_LANES; lane++) {
        open += textureLoad(partial, 2u * id.xy + vec2<u32>(lane & 1u, lane >> 1u), 0).r;
    }
    let v = open / f32(max(params.rays, 1u));
    textureStore(ao, id.xy, vec4<f32>(v, v, v, 1.0));
}
