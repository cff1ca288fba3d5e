// The G-buffer's material.a (common/gbuffer_store_material.wgsl, deferred/deferred.wgsl): 0 for
// an unlit surface (KHR_materials_unlit), 0.5 for a lit one whose material has its own
// specular lobes (MATERIAL_LOBES: the G-buffer's `lobes` channel holds them,
// common/gbuffer_lobes.wgsl), 1 for a lit one of glTF's core material.
//#include "common/scene_features.wgsl"

fn gbuffer_material_word(unlit: bool, flags: u32) -> f32 {
    return select(select(1.0, 0.5, SCENE_LOBES && (flags & 2048u) != 0u), 0.0, unlit);
}

fn gbuffer_unlit(word: f32) -> bool {
    return SCENE_UNLIT && word < 0.25;
}

fn gbuffer_has_lobes(word: f32) -> bool {
    return word > 0.25 && word < 0.75;
}
