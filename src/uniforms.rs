//! CPU-side mirrors of the uniform structs shared with WGSL (`shaders/common/*.wgsl`).

use bytemuck::{Pod, Zeroable};

/// Shadow-map slots of directional and spot lights in the raster mode (`shadow_map` layer: one
/// 2048² depth texture each): slots 0 to 3.
pub(crate) const SHADOW_MAP_SLOTS: usize = 4;
/// Point lights with a cube shadow map in the raster mode, the most powerful (`shadow_map`
/// layer's `cube`: six 1024² layers each). Cube map k has slots `SHADOW_MAP_SLOTS + 6k ..`, one per face in the
/// order +x, -x, +y, -y, +z, -z.
pub(crate) const CUBE_SHADOW_MAPS: usize = 2;
/// Every raster shadow slot: the maps', then the cube maps' faces.
pub(crate) const SHADOW_SLOTS: usize = SHADOW_MAP_SLOTS + 6 * CUBE_SHADOW_MAPS;

/// Mirrors `struct Frame` in `shaders/common/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct FrameUniforms {
    /// World to clip space.
    pub(crate) view_proj: [[f32; 4]; 4],
    /// Clip to world space.
    pub(crate) inv_view_proj: [[f32; 4]; 4],
    /// xyz camera position; w 1 for a perspective camera, 0 for an orthographic one.
    pub(crate) camera_pos: [f32; 4],
    /// width, height, 1/width, 1/height.
    pub(crate) resolution: [f32; 4],
    /// xyz scene bounds centre, w half diagonal (ray lengths and offsets scale with it).
    pub(crate) scene_sphere: [f32; 4],
    /// View-projection of each raster shadow-map slot (see [`LightUniforms::shadow_map`]).
    pub(crate) shadow_view_proj: [[[f32; 4]; 4]; SHADOW_SLOTS],
    /// Intensity of the sky's ambient light (`Scene::light.ambient`).
    pub(crate) ambient: f32,
    /// Number of records in `scene_lights`.
    pub(crate) light_count: u32,
    /// The shadow slots in use: bit `slot` set where a light has it.
    pub(crate) shadow_slots: u32,
    /// Frame counter (seeds the per-frame sample sequences).
    pub(crate) frame_index: u32,
    /// 1 when history resources hold the previous frame, 0 on the first frame of an executor
    /// and on a camera cut (`runtime::exec::history`).
    pub(crate) history_valid: u32,
    pub(crate) _pad: [u32; 3],
    /// The previous frame's world to clip space (this frame's on a frame without history).
    pub(crate) prev_view_proj: [[f32; 4]; 4],
}

/// Light kinds of [`LightUniforms::kind`].
pub(crate) const LIGHT_DIRECTIONAL: u32 = 0;
/// A point light (position, range).
pub(crate) const LIGHT_POINT: u32 = 1;
/// A spot light (position, direction, cones).
pub(crate) const LIGHT_SPOT: u32 = 2;

/// Mirrors `struct Light` in `shaders/common/lighting.wgsl`: one record of `scene_lights`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct LightUniforms {
    /// World position (point and spot lights).
    pub(crate) position: [f32; 3],
    /// [`LIGHT_DIRECTIONAL`], [`LIGHT_POINT`] or [`LIGHT_SPOT`].
    pub(crate) kind: u32,
    /// Unit direction the light shines in (from the light towards the scene).
    pub(crate) direction: [f32; 3],
    /// Distance where the light's influence ends; 0: infinite.
    pub(crate) range: f32,
    /// Linear colour times intensity (glTF lux or candela, used as a linear scale).
    pub(crate) radiance: [f32; 3],
    /// Cosine of the spot cone's inner angle (full intensity inside).
    pub(crate) cos_inner: f32,
    /// Cosine of the spot cone's outer angle (no light outside).
    pub(crate) cos_outer: f32,
    /// Raster shadow slot (index into `Frame::shadow_view_proj`), -1: none. A point light's is
    /// its cube map's first face (`CUBE_SHADOW_MAPS`).
    pub(crate) shadow_map: i32,
    /// World length of the shadow map's depth range (far - near), so a depth bias given as a
    /// fraction of it is a world distance.
    pub(crate) shadow_depth_range: f32,
    /// Padding to the WGSL struct's size.
    pub(crate) _pad: u32,
}

/// Mirrors `struct Instance` in `shaders/common/scene.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct InstanceUniforms {
    /// Object to world space.
    pub(crate) model: [[f32; 4]; 4],
    /// Inverse-transpose of the model matrix (for normals).
    pub(crate) normal_matrix: [[f32; 4]; 4],
    /// Index into `scene_materials`.
    pub(crate) material: u32,
    /// Index of the mesh in the scene.
    pub(crate) mesh: u32,
    /// Padding to the WGSL struct's size.
    pub(crate) _pad: [u32; 2],
}

/// Mirrors `struct Material` in `shaders/common/scene.wgsl`. Texture fields are layers of
/// `scene_textures`: layer 0 is plain white, and 0 in `normal_texture` means "no normal map".
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct MaterialUniforms {
    /// Linear base colour and alpha.
    pub(crate) base_color: [f32; 4],
    /// Linear emitted radiance (factor times strength).
    pub(crate) emissive: [f32; 3],
    /// Metalness, 0..1.
    pub(crate) metallic: f32,
    /// Perceptual roughness, 0..1.
    pub(crate) roughness: f32,
    /// Scale of the normal map's xy.
    pub(crate) normal_scale: f32,
    /// Alpha-mask cutoff (0 unless the material is alpha-tested).
    pub(crate) alpha_cutoff: f32,
    /// [`MATERIAL_DOUBLE_SIDED`] | [`MATERIAL_ALPHA_MASK`] | [`MATERIAL_ALPHA_BLEND`] |
    /// [`MATERIAL_UNLIT`] | [`MATERIAL_UV_TRANSFORM`] |
    /// [`MATERIAL_SAMPLERS`] | [`MATERIAL_LOBES`] | [`MATERIAL_TRANSMISSION`].
    pub(crate) flags: u32,
    /// Layer of the base colour texture.
    pub(crate) base_texture: u32,
    /// Layer of the metallic-roughness texture (glTF: roughness in g, metalness in b).
    pub(crate) metallic_roughness_texture: u32,
    /// Layer of the normal map (0: none).
    pub(crate) normal_texture: u32,
    /// Layer of the emissive texture.
    pub(crate) emissive_texture: u32,
    /// Layer of the occlusion texture (0: none, occlusion 1).
    pub(crate) occlusion_texture: u32,
    /// How much the occlusion texture darkens ambient light, 0..1.
    pub(crate) occlusion_strength: f32,
    /// Each texture slot's sampler, 8 bits a slot ([`crate::scene::SlotSampling::sampler_bits`]):
    /// slots 0-3 in the first word, 4-7 in the second (8-10 in `slot_words[2]`).
    pub(crate) samplers: [u32; 2],
    /// Layers of the lobe extensions' textures of slots 5-8 (specular, specular colour,
    /// clearcoat, clearcoat roughness; 0: none).
    pub(crate) lobe_layers: [u32; 4],
    /// The layers of slots 9 (clearcoat normal, 0: none) and 10 (transmission), the sampler
    /// bits of slots 8-10, and the uv-set bits (bit `slot`: the slot reads `TEXCOORD_1`).
    pub(crate) slot_words: [u32; 4],
    /// Each slot's uv transform (`KHR_texture_transform`), rows `2 slot` and `2 slot + 1` (xyz);
    /// read only with [`MATERIAL_UV_TRANSFORM`].
    pub(crate) uv_transforms: [[f32; 4]; 2 * MATERIAL_TEXTURE_SLOTS],
    /// ((ior - 1) / (ior + 1))² x the specular colour factor (rgb) and the specular factor (a),
    /// which the shaders make the dielectric reflectance with the lobe textures
    /// (`shaders/common/surface_lobes.wgsl`: min(that, 1) x the specular factor x the
    /// textures' texels); read only with [`MATERIAL_LOBES`].
    pub(crate) specular: [f32; 4],
    /// The clear coat's weight and perceptual roughness, the transmission factor and the
    /// coverage factor of a transmissive material ([`crate::scene::Material::coverage_factor`]);
    /// read only with [`MATERIAL_LOBES`].
    pub(crate) clearcoat: [f32; 4],
    /// The scale of the coat's normal map (x); y-w padding.
    pub(crate) coat: [f32; 4],
}

/// A material's texture slots (`crate::scene::TEXTURE_SLOTS`): glTF's five and the lobe
/// extensions' six.
pub(crate) const MATERIAL_TEXTURE_SLOTS: usize = 11;

/// Material flag: both faces are lit and never culled.
pub(crate) const MATERIAL_DOUBLE_SIDED: u32 = 1;
/// Material flag: alpha-tested against `alpha_cutoff`.
pub(crate) const MATERIAL_ALPHA_MASK: u32 = 2;
/// Material flag: alpha-blended (glTF `BLEND`).
pub(crate) const MATERIAL_ALPHA_BLEND: u32 = 4;
/// Material flag: unlit (glTF `KHR_materials_unlit`).
pub(crate) const MATERIAL_UNLIT: u32 = 8;
/// Material flag: a texture slot has a uv transform (`uv_transforms` is read).
pub(crate) const MATERIAL_UV_TRANSFORM: u32 = 16;
/// Material flag: a texture slot's sampler is not glTF's default (`samplers` is read).
pub(crate) const MATERIAL_SAMPLERS: u32 = 1024;
/// Material flag: its specular lobes are not glTF's core material's (`specular` and
/// `clearcoat` are read; KHR_materials_ior, KHR_materials_specular, KHR_materials_clearcoat).
pub(crate) const MATERIAL_LOBES: u32 = 2048;
/// Material flag: transmissive (`KHR_materials_transmission`; translucent, with
/// MATERIAL_ALPHA_BLEND: its coverage factor is `clearcoat[3]`).
pub(crate) const MATERIAL_TRANSMISSION: u32 = 4096;
/// Material flag: its transmission texture is drawn ([`crate::scene::Material::transmission_texture_drawn`]):
/// the coverage is `base_color.a` x (1 - transmission x (1 - metallic) x the texel).
pub(crate) const MATERIAL_TRANSMISSION_TEXTURE: u32 = 8192;

/// Mirrors `EnvironmentParams` in shaders/common/environment.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct EnvironmentUniforms {
    pub(crate) intensity: f32,
    pub(crate) rotation_cos: f32,
    pub(crate) rotation_sin: f32,
    /// Mip levels of the radiance texture (its prefiltered roughness steps + 1).
    pub(crate) levels: f32,
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// 1 where the sampler's table holds the map (0: a black map, nothing to sample).
    pub(crate) sampled: u32,
    pub(crate) _pad: u32,
}
