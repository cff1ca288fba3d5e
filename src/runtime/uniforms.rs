//! CPU-side mirrors of the uniform structs shared with WGSL (`shaders/common/*.wgsl`).

use bytemuck::{Pod, Zeroable};

/// Mirrors `struct Frame` in `shaders/common/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    /// xyz camera position, w unused.
    pub camera_pos: [f32; 4],
    /// xyz unit direction towards the light, w intensity.
    pub light_dir: [f32; 4],
    /// rgb light colour, a ambient intensity.
    pub light_color: [f32; 4],
    /// width, height, 1/width, 1/height.
    pub resolution: [f32; 4],
    /// Orthographic view-projection of the directional light, covering the scene (shadow maps).
    pub light_view_proj: [[f32; 4]; 4],
    /// xyz position, w intensity (0: no point light).
    pub point_light: [f32; 4],
    /// rgb colour, a unused.
    pub point_color: [f32; 4],
    /// xyz scene bounds centre, w half diagonal (ray lengths and offsets scale with it).
    pub scene_sphere: [f32; 4],
    pub frame_index: u32,
    pub _pad: [u32; 3],
}

/// Mirrors `struct Instance` in `shaders/common/scene.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct InstanceUniforms {
    pub model: [[f32; 4]; 4],
    /// Inverse-transpose of the model matrix (for normals).
    pub normal_matrix: [[f32; 4]; 4],
    /// Index into `scene_materials`.
    pub material: u32,
    /// Index of the mesh in the scene.
    pub mesh: u32,
    pub _pad: [u32; 2],
}

/// Mirrors `struct Material` in `shaders/common/scene.wgsl`. Texture fields are layers of
/// `scene_textures`: layer 0 is plain white, and 0 in `normal_texture` means "no normal map".
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MaterialUniforms {
    pub base_color: [f32; 4],
    pub emissive: [f32; 3],
    pub metallic: f32,
    pub roughness: f32,
    pub normal_scale: f32,
    /// Alpha-mask cutoff (0 unless the material is alpha-tested).
    pub alpha_cutoff: f32,
    /// [`MATERIAL_DOUBLE_SIDED`] | [`MATERIAL_ALPHA_MASK`] | [`MATERIAL_ALPHA_BLEND`].
    pub flags: u32,
    pub base_texture: u32,
    pub metallic_roughness_texture: u32,
    pub normal_texture: u32,
    pub emissive_texture: u32,
    /// Layer of the occlusion texture (0: none, occlusion 1).
    pub occlusion_texture: u32,
    pub occlusion_strength: f32,
    pub _pad: [u32; 2],
}

pub const MATERIAL_DOUBLE_SIDED: u32 = 1;
pub const MATERIAL_ALPHA_MASK: u32 = 2;
pub const MATERIAL_ALPHA_BLEND: u32 = 4;
