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
    pub base_color: [f32; 4],
    /// Layer in `scene_textures`; layer 0 is plain white.
    pub texture: u32,
    pub _pad: [u32; 3],
}
