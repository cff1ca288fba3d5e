// What the scene uses of the material and mesh features a pass can compile out, set by the
// executor from the scene's instances (src/runtime/exec/features.rs) on every pass whose module
// declares them: a scene without a feature runs passes with no trace of it. The defaults keep
// every feature, so a pipeline made without these constants is right for any scene.

// Some material is translucent (BLEND, or transmissive: MATERIAL_ALPHA_BLEND).
override SCENE_BLEND: bool = true;
// Some material has its own specular lobes (MATERIAL_LOBES).
override SCENE_LOBES: bool = true;
// Some material has a non-default sampler or a texture transform (MATERIAL_SAMPLERS,
// MATERIAL_UV_TRANSFORM).
override SCENE_CUSTOM_SAMPLING: bool = true;
// Some drawn mesh has COLOR_0 or TEXCOORD_1 (MeshRecord.extras).
override SCENE_VERTEX_EXTRAS: bool = true;
// Some material is unlit (MATERIAL_UNLIT, KHR_materials_unlit).
override SCENE_UNLIT: bool = true;
// An environment map lights the scene (`--env`; common/environment.wgsl). Read together with
// the bound map's size, so that the default is right without a map too.
override SCENE_ENVIRONMENT: bool = true;
