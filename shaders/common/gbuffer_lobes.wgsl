// The specular lobes of a G-buffer texel's surface, for the passes that shade from the
// G-buffer (resolve/resolve.wgsl, rt/shadow.wgsl): glTF's core material's, unless the texel's
// material.a says its material has its own (common/lighting.wgsl's gbuffer_material_word), which
// are then read from the material of the instance in position.w (the instance + 1). Needs
// `scene_instances` and `scene_materials` declared by the main shader.
//#include "common/scene.wgsl"

fn gbuffer_lobes(s: ptr<function, ShadingPoint>, word: f32, instance_plus_one: f32) {
    if gbuffer_has_lobes(word) && instance_plus_one >= 1.0 {
        let m = scene_materials[scene_instances[u32(instance_plus_one) - 1u].material];
        shading_lobes(s, m.flags, m.specular, m.clearcoat);
    } else {
        shading_lobes(s, 0u, vec4<f32>(0.0), vec4<f32>(0.0));
    }
}
