// The specular lobes of a surface point (KHR_materials_ior, _specular, _clearcoat): its
// material's factors times its lobe textures where it has them (common/surface_lobes.wgsl),
// glTF's core material's otherwise (`core_lobes`). Self-contained: included by
// common/lighting.wgsl and by the passes that read or write them.

struct SurfaceLobes {
    // The dielectric part's reflectance at normal incidence (0.04: glTF's core material) and
    // at grazing angles (1).
    f0: vec3<f32>,
    f90: f32,
    // The clear coat's weight (0: none) and perceptual roughness.
    clearcoat: f32,
    clearcoat_roughness: f32,
    // The coat's normal (world space, on the viewer's side): the surface's normal before the
    // base's normal map, or its own normal map's.
    coat_normal: vec3<f32>,
}

// glTF's core material at a point whose normal before normal mapping is `normal`.
fn core_lobes(normal: vec3<f32>) -> SurfaceLobes {
    return SurfaceLobes(vec3<f32>(0.04), 1.0, 0.0, 0.0, normal);
}
