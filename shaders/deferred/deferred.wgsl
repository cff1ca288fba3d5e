// G-buffer: world position, shading normal (normal-mapped, common/material_inputs.wgsl, with
// the tangent frame from screen-space derivatives), geometric normal (from derivatives of the
// object-space position, transformed), albedo, material, emission and occlusion. Normals face
// the camera. The rasterizer culls back faces of single-sided materials (`cull_back_faces`);
// those of double-sided ones (glTF `doubleSided`) get reversed normals, as primary rays do
// (common/primary_rays.wgsl).
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/material_inputs.wgsl"
//#include "common/gbuffer_lobes.wgsl"
//#include "common/scene_fragment.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;

struct GBuffer {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) geo_normal: vec4<f32>,
    @location(3) albedo: vec4<f32>,
    @location(4) material: vec4<f32>,
    @location(5) emissive: vec4<f32>,
    // Written where material.a says the material has its own lobes (common/gbuffer_lobes.wgsl).
    @location(6) lobes: vec4<u32>,
}

// The fragment's G-buffer channels (discarded fragments never return).
fn gbuffer_of(in: VertexOut, front_facing: bool) -> GBuffer {
    let inst = scene_instances[in.instance];
    let s = scene_fragment_surface(in, inst, front_facing);
    var out: GBuffer;
    // w: the instance + 1 (0 is the sky), as common/gbuffer_store.wgsl writes it.
    out.position = vec4<f32>(in.world, f32(in.instance + 1u));
    out.normal = vec4<f32>(s.normal, 0.0);
    out.geo_normal = vec4<f32>(s.geo_normal, 0.0);
    out.albedo = vec4<f32>(s.albedo, 1.0);
    let e = dot(s.emissive, vec3<f32>(0.2126, 0.7152, 0.0722));
    // a: 1 for a lit surface, 0 for an unlit one (KHR_materials_unlit), 0.5 for a lit one with
    // its own specular lobes, as common/gbuffer_store_material.wgsl writes it.
    let word = gbuffer_material_word(s.unlit, scene_materials[inst.material].flags);
    out.material = vec4<f32>(s.metallic, s.roughness, min(e / 16.0, 1.0), word);
    out.emissive = vec4<f32>(s.emissive, s.occlusion);
    out.lobes = pack_gbuffer_lobes(s.lobes);
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front_facing: bool) -> GBuffer {
    if !scene_fragment_kept(in) {
        discard;
    }
    return gbuffer_of(in, front_facing);
}

// The G-buffer in three draws, for devices whose colour attachments take fewer than the 72
// bytes per sample of all seven (WebGPU's default is 32; layers/deferred_split.ron): the surface
// half (32 bytes), the material half (24 bytes as WebGPU counts them), then the lobes (16).
struct GBufferSurface {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) geo_normal: vec4<f32>,
}

struct GBufferMaterial {
    @location(0) albedo: vec4<f32>,
    @location(1) material: vec4<f32>,
    @location(2) emissive: vec4<f32>,
}

@fragment
fn fs_surface(in: VertexOut, @builtin(front_facing) front_facing: bool) -> GBufferSurface {
    if !scene_fragment_kept(in) {
        discard;
    }
    let g = gbuffer_of(in, front_facing);
    return GBufferSurface(g.position, g.normal, g.geo_normal);
}

@fragment
fn fs_material(in: VertexOut, @builtin(front_facing) front_facing: bool) -> GBufferMaterial {
    if !scene_fragment_kept(in) {
        discard;
    }
    let g = gbuffer_of(in, front_facing);
    return GBufferMaterial(g.albedo, g.material, g.emissive);
}

@fragment
fn fs_lobes(in: VertexOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<u32> {
    if !scene_fragment_kept(in) {
        discard;
    }
    return gbuffer_of(in, front_facing).lobes;
}
