//! The vertex layout every mesh shares (its own file: the animation data holds rest vertices
//! without depending on the scene that holds the animation).

use bytemuck::{Pod, Zeroable};

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
