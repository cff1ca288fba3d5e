// Bindings 0 to 6 of the compute passes that read the scene's surfaces at a pixel's ray
// (common/surface.wgsl): the frame, the scene's instances, materials, meshes, indices and
// vertices, and the linear sampler. The main shader declares its own bindings from 7.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(4) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(6) var linear_sampler: sampler;
