// The specular lobes of a point of a material with its own (MATERIAL_LOBES): the factors of its
// `specular` and `clearcoat` words times its lobe textures' texels (layer 0, white, where it
// has none), read alike at ray hits (common/surface.wgsl) and by the rasterized fragments
// (common/raster_visibility.wgsl). Needs common/scene.wgsl and `scene_materials`.
//#include "common/lobes.wgsl"

// Whether material `m` has its own lobes (never in a scene without any: SCENE_LOBES).
fn material_has_lobes(m: u32) -> bool {
    return SCENE_LOBES && (scene_materials[m].flags & MATERIAL_LOBES) != 0u;
}

// The lobes of material `m` from the texels of its lobe slots: `specular` (specularTexture's
// alpha), `specular_color` (specularColorTexture's rgb), `coat` (clearcoatTexture's red),
// `coat_roughness` (clearcoatRoughnessTexture's green); `coat_normal`: the coat's normal.
// f0 = min(((ior - 1) / (ior + 1))^2 x specular colour, 1) x specular, f90 = specular
// (KHR_materials_specular).
fn lobes_from_texels(m: u32, specular: f32, specular_color: vec3<f32>, coat: f32, coat_roughness: f32, coat_normal: vec3<f32>) -> SurfaceLobes {
    let w = scene_materials[m].specular;
    let c = scene_materials[m].clearcoat;
    var l: SurfaceLobes;
    l.f90 = w.a * specular;
    l.f0 = min(w.rgb * specular_color, vec3<f32>(1.0)) * l.f90;
    l.clearcoat = c.x * coat;
    // Clamped as the base's roughness is (common/surface.wgsl): GGX's peak diverges at 0.
    l.clearcoat_roughness = clamp(c.y * coat_roughness, 0.02, 1.0);
    l.coat_normal = coat_normal;
    return l;
}
