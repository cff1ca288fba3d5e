//! The vertex layout every mesh shares (its own file: the animation data holds rest vertices
//! without depending on the scene that holds the animation).

use bytemuck::{Pod, Zeroable};

/// A vertex's attributes beyond [`Vertex`]'s, for meshes that have them (glTF `COLOR_0`,
/// `TEXCOORD_1`): the same size as a vertex, so the GPU keeps them in the vertex buffer, after
/// every mesh's vertices (`common/scene.wgsl`, `MeshRecord::extras`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct VertexExtra {
    /// The second texture coordinates (`TEXCOORD_1`; 0 where the mesh has none).
    pub uv1: [f32; 2],
    /// Linear RGBA colour multiplying the base colour (`COLOR_0`; white where the mesh has none).
    pub color: [f32; 4],
    /// Padding to a vertex's size.
    pub _pad: [f32; 2],
}

impl Default for VertexExtra {
    fn default() -> Self {
        Self { uv1: [0.0; 2], color: [1.0; 4], _pad: [0.0; 2] }
    }
}

/// Vertex layout shared by every mesh: `@location(0)` position, `(1)` normal, `(2)` uv.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinates.
    pub uv: [f32; 2],
}
