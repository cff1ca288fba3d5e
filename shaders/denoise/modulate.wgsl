// A ratio put back on its base (layers/modulate.ron): rgb = factor x base, alpha base's.

@group(0) @binding(0) var factor: texture_2d<f32>;
@group(0) @binding(1) var base: texture_2d<f32>;
@group(0) @binding(2) var product: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(product);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let b = textureLoad(base, id.xy, 0);
    textureStore(product, id.xy, vec4<f32>(textureLoad(factor, id.xy, 0).rgb * b.rgb, b.a));
}
