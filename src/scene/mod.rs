//! The CPU scene (meshes, materials, instances, textures, camera, light), the built-in
//! default scene, and its upload to the GPU ([`gpu`]).

pub mod builtin;
pub mod camera;
pub mod gpu;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

pub use camera::Camera;

/// Vertex layout shared by every mesh: `@location(0)` position, `(1)` normal, `(2)` uv.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

#[derive(Debug, Clone)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

#[derive(Debug, Clone)]
pub struct Material {
    pub name: String,
    pub base_color: [f32; 4],
    /// Index into [`Scene::textures`].
    pub texture: Option<usize>,
}

/// One placement of a mesh.
#[derive(Debug, Clone)]
pub struct Instance {
    pub mesh: usize,
    pub material: usize,
    pub transform: Mat4,
}

/// An RGBA8 sRGB image.
#[derive(Debug, Clone)]
pub struct TextureImage {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// A directional light.
#[derive(Debug, Clone, Copy)]
pub struct Light {
    /// Unit direction from surfaces towards the light.
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub ambient: f32,
}

#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub instances: Vec<Instance>,
    pub textures: Vec<TextureImage>,
    pub camera: Camera,
    pub light: Light,
}

impl Scene {
    pub fn triangle_count(&self) -> usize {
        self.instances.iter().map(|i| self.meshes[i.mesh].triangle_count()).sum()
    }
}
