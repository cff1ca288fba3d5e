// ReSTIR DI's parameters (layers/restir_di.ron) and the bindings its four passes share
// (rt/restir_initial.wgsl, restir_temporal.wgsl, restir_spatial.wgsl, restir_shade.wgsl): the
// frame, the G-buffer and the scene's lights, instances, materials and emitters. Each pass
// binds its own textures from 12 on.

struct Params {
    candidates: u32,
    visibility_reuse: u32,
    temporal: u32,
    max_history: f32,
    spatial_samples: u32,
    spatial_radius: f32,
    per_frame: u32,
    seed: u32,
    reflection_roughness: f32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var normal: texture_2d<f32>;
@group(0) @binding(5) var albedo: texture_2d<f32>;
@group(0) @binding(6) var material: texture_2d<f32>;
@group(0) @binding(7) var lobes: texture_2d<u32>;
@group(0) @binding(8) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(9) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(10) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(11) var<storage, read> scene_emitters: array<u32>;
