// The translucent layer (forward/translucent.wgsl) over the opaque image of the fragment-stage
// forward layer (common/translucent_over.wgsl); a copy of the opaque image in a scene without
// translucent materials.
//#include "common/translucent_over.wgsl"

@group(0) @binding(0) var opaque: texture_2d<f32>;
@group(0) @binding(1) var translucent: texture_2d<f32>;
@group(0) @binding(2) var translucent_filter: texture_2d<f32>;
@group(0) @binding(3) var color: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    textureStore(color, id.xy, composite_translucent(id.xy, textureLoad(opaque, id.xy, 0)));
}
