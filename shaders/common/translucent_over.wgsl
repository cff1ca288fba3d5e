// How the forward layers put the translucent layer (forward/translucent.wgsl) over the opaque
// image: forward/shade.wgsl and forward/composite.wgsl.
//#include "common/scene_features.wgsl"

// The translucent layer (forward/translucent.wgsl) over `opaque`: its radiance plus what its
// transmittance lets through, the sky behind (alpha 0) by their mean, as the rt_blend layer
// composites it.
fn over_opaque(layer: vec4<f32>, absorbed: vec4<f32>, opaque: vec4<f32>) -> vec4<f32> {
    let transmittance = vec3<f32>(1.0) - absorbed.rgb;
    return vec4<f32>(layer.rgb + transmittance * opaque.rgb, 1.0 - dot(transmittance, vec3<f32>(1.0 / 3.0)) * (1.0 - opaque.a));
}

// The composite at pixel `q` of `opaque`: the opaque image itself in a scene without translucent
// materials (SCENE_BLEND: the layer is not read). Needs `translucent` and `translucent_filter`.
fn composite_translucent(q: vec2<u32>, opaque: vec4<f32>) -> vec4<f32> {
    if !SCENE_BLEND {
        return opaque;
    }
    return over_opaque(textureLoad(translucent, q, 0), textureLoad(translucent_filter, q, 0), opaque);
}
