// The material half of the G-buffer (common/gbuffer_store.wgsl): `material`, `emissive` and
// `lobes` (common/gbuffer_lobes.wgsl; written only for a material with its own lobes), storage
// textures the main shader declares.
//#include "common/gbuffer_material_word.wgsl"
//#include "common/gbuffer_lobes.wgsl"

fn store_gbuffer_material(p: vec2<u32>, s: Surface) {
    let e = dot(s.emissive, vec3<f32>(0.2126, 0.7152, 0.0722));
    // a: 1 for a lit surface, 0 for an unlit one (KHR_materials_unlit), 0.5 for a lit one with
    // its own specular lobes (common/lighting.wgsl's gbuffer_material_word).
    let word = gbuffer_material_word(s.unlit, scene_materials[s.material].flags);
    textureStore(material, p, vec4<f32>(s.metallic, s.roughness, min(e / 16.0, 1.0), word));
    textureStore(emissive, p, vec4<f32>(s.emissive, s.occlusion));
    if gbuffer_has_lobes(word) {
        textureStore(lobes, p, pack_gbuffer_lobes(s.lobes));
    }
}

fn store_gbuffer_material_miss(p: vec2<u32>) {
    textureStore(material, p, vec4<f32>(0.0));
    textureStore(emissive, p, vec4<f32>(0.0));
}
