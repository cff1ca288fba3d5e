// Scene records. `Instance` (bound as `scene_instances`) mirrors InstanceUniforms and
// `Material` (bound as `scene_materials`) mirrors MaterialUniforms in src/uniforms.rs.
// Texture fields are layers of `scene_textures` (0 = white; `normal_texture` 0 = none).
//#include "common/scene_features.wgsl"
struct Instance {
    model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
    material: u32,
    mesh: u32,
    _pad0: u32,
    _pad1: u32,
}

const MATERIAL_DOUBLE_SIDED: u32 = 1u;
const MATERIAL_ALPHA_MASK: u32 = 2u;
const MATERIAL_ALPHA_BLEND: u32 = 4u;
const MATERIAL_UNLIT: u32 = 8u;
const MATERIAL_UV_TRANSFORM: u32 = 16u;
// A texture slot's sampler is not glTF's default (samplers_low/high are read).
const MATERIAL_SAMPLERS: u32 = 1024u;
// The specular lobes are not glTF's core material's (`specular` and `clearcoat` are read).
const MATERIAL_LOBES: u32 = 2048u;
// Transmissive (KHR_materials_transmission; with MATERIAL_ALPHA_BLEND): its coverage factor is
// clearcoat.w, and what it lets through is tinted by its base colour.
const MATERIAL_TRANSMISSION: u32 = 4096u;
// Its transmission texture is drawn (src/scene/mod.rs Material::transmission_texture_drawn):
// the coverage is base_color.a x (1 - transmission x (1 - metallic) x the texel's red).
const MATERIAL_TRANSMISSION_TEXTURE: u32 = 8192u;

struct Material {
    base_color: vec4<f32>,
    emissive: vec3<f32>,
    metallic: f32,
    roughness: f32,
    normal_scale: f32,
    alpha_cutoff: f32,
    flags: u32,
    base_texture: u32,
    metallic_roughness_texture: u32,
    normal_texture: u32,
    emissive_texture: u32,
    // 0: no occlusion texture (occlusion 1).
    occlusion_texture: u32,
    occlusion_strength: f32,
    // Each texture slot's sampler, 8 bits a slot (common/texture_sampling.wgsl): slots 0-3,
    // then 4-7 (8-10 in slot_words.z).
    samplers_low: u32,
    samplers_high: u32,
    // Layers of the lobe extensions' textures of slots 5-8: specular, specular colour,
    // clearcoat, clearcoat roughness (0: white).
    lobe_layers: vec4<u32>,
    // x, y: the layers of slots 9 (clearcoat normal; 0: none) and 10 (transmission); z: the
    // sampler bits of slots 8-10; w: bit `slot` set where the slot reads TEXCOORD_1.
    slot_words: vec4<u32>,
    // Each slot's uv transform (KHR_texture_transform): rows 2 slot and 2 slot + 1 (xyz), read
    // only with MATERIAL_UV_TRANSFORM.
    uv_transforms: array<vec4<f32>, 22>,
    // KHR_materials_ior / _specular: ((ior - 1) / (ior + 1))^2 x specularColorFactor (rgb) and
    // specularFactor (a); KHR_materials_clearcoat: weight, roughness; then
    // KHR_materials_transmission's factor and the coverage factor base_color.a x (1 -
    // transmission x (1 - metallic)). Read only with MATERIAL_LOBES (common/surface_lobes.wgsl)
    // and MATERIAL_TRANSMISSION.
    specular: vec4<f32>,
    clearcoat: vec4<f32>,
    // x: the scale of the coat's normal map.
    coat: vec4<f32>,
}

// Geometry for shading hits (`scene_vertices`, `scene_indices`, `scene_meshes`): a vertex is
// 8 floats (position, normal, uv) as in src/scene/mod.rs `Vertex`; a mesh record gives its
// first index, base vertex and index count.
struct SceneVertex {
    px: f32,
    py: f32,
    pz: f32,
    nx: f32,
    ny: f32,
    nz: f32,
    u: f32,
    v: f32,
}

// `extras`: where the mesh's colours and second uvs start in `scene_vertices` (one record a
// vertex, laid out as `VertexExtra` in src/scene/vertex.rs: u1, v1, then rgba in the places of
// pz..nz), or MESH_NO_EXTRAS.
struct MeshRecord {
    first_index: u32,
    base_vertex: u32,
    index_count: u32,
    extras: u32,
}

const MESH_NO_EXTRAS: u32 = 0xffffffffu;
