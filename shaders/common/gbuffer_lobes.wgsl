// The G-buffer's `lobes` channel (Rgba32Uint): the specular lobes of a surface whose material
// has its own (material.a 0.5, common/gbuffer_material_word.wgsl), written by the G-buffer
// producers (common/gbuffer_store_material.wgsl, deferred/deferred.wgsl) only there, and read
// by the passes that shade from the G-buffer (resolve/resolve.wgsl, rt/shadow.wgsl), 16 bits a
// value: x f0.r and f0.g, y f0.b and f90, z the coat's weight and roughness (unorm); w the
// coat's normal (octahedral, snorm).
//#include "common/lobes.wgsl"
//#include "common/scene_features.wgsl"
//#include "common/gbuffer_material_word.wgsl"

// A unit vector's octahedral coordinates in [-1, 1]^2.
fn octahedral_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z >= 0.0 {
        return p;
    }
    return (vec2<f32>(1.0) - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn octahedral_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if n.z < 0.0 {
        n = vec3<f32>((vec2<f32>(1.0) - abs(n.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), n.xy >= vec2<f32>(0.0)), n.z);
    }
    return normalize(n);
}

fn pack_gbuffer_lobes(l: SurfaceLobes) -> vec4<u32> {
    return vec4<u32>(
        pack2x16unorm(l.f0.rg),
        pack2x16unorm(vec2<f32>(l.f0.b, l.f90)),
        pack2x16unorm(vec2<f32>(l.clearcoat, l.clearcoat_roughness)),
        pack2x16snorm(octahedral_encode(l.coat_normal)),
    );
}

fn unpack_gbuffer_lobes(texel: vec4<u32>) -> SurfaceLobes {
    let rg = unpack2x16unorm(texel.x);
    let b_f90 = unpack2x16unorm(texel.y);
    let coat = unpack2x16unorm(texel.z);
    return SurfaceLobes(vec3<f32>(rg, b_f90.x), b_f90.y, coat.x, coat.y, octahedral_decode(unpack2x16snorm(texel.w)));
}

// The lobes of a G-buffer texel from its material word `word` and lobes texel `texel`; glTF's
// core material's (coat normal `normal`) where the word says so.
fn gbuffer_lobes(word: f32, texel: vec4<u32>, normal: vec3<f32>) -> SurfaceLobes {
    if SCENE_LOBES && gbuffer_has_lobes(word) {
        return unpack_gbuffer_lobes(texel);
    }
    return core_lobes(normal);
}
