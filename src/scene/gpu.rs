//! The scene on the GPU: one vertex and one index buffer for all meshes, a storage buffer of
//! instances, and a 2D texture array of all textures (layer 0 is plain white). Uploaded only
//! when the compiled plan uses the scene.

use super::Scene;
use crate::runtime::uniforms::InstanceUniforms;
use wgpu::util::DeviceExt;

/// One indexed draw per instance.
#[derive(Debug, Clone)]
pub struct Draw {
    pub indices: std::ops::Range<u32>,
    pub base_vertex: i32,
    pub instance: u32,
}

pub struct GpuScene {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub instances: wgpu::Buffer,
    pub textures: wgpu::Texture,
    pub texture_view: wgpu::TextureView,
    pub draws: Vec<Draw>,
    /// Bytes uploaded.
    pub bytes: u64,
}

/// Side of the square layers of the texture array.
pub const TEXTURE_SIZE: u32 = 256;

impl GpuScene {
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Self {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut ranges = Vec::new();
        for mesh in &scene.meshes {
            let first_index = indices.len() as u32;
            let base_vertex = vertices.len() as i32;
            vertices.extend_from_slice(&mesh.vertices);
            indices.extend_from_slice(&mesh.indices);
            ranges.push((first_index..indices.len() as u32, base_vertex));
        }
        let instances: Vec<InstanceUniforms> = scene
            .instances
            .iter()
            .map(|inst| {
                let m = &scene.materials[inst.material];
                InstanceUniforms {
                    model: inst.transform.to_cols_array_2d(),
                    normal_matrix: inst.transform.inverse().transpose().to_cols_array_2d(),
                    base_color: m.base_color,
                    texture: m.texture.map(|t| t as u32 + 1).unwrap_or(0),
                    _pad: [0; 3],
                }
            })
            .collect();
        let draws = scene
            .instances
            .iter()
            .enumerate()
            .map(|(i, inst)| Draw { indices: ranges[inst.mesh].0.clone(), base_vertex: ranges[inst.mesh].1, instance: i as u32 })
            .collect();

        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let vbuf = init("scene vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
        let ibuf = init("scene indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
        let instance_bytes: &[u8] = if instances.is_empty() { &[0u8; std::mem::size_of::<InstanceUniforms>()] } else { bytemuck::cast_slice(&instances) };
        let inst_buf = init("scene instances", instance_bytes, wgpu::BufferUsages::STORAGE);

        let layers = scene.textures.len() as u32 + 1;
        let textures = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene textures"),
            size: wgpu::Extent3d { width: TEXTURE_SIZE, height: TEXTURE_SIZE, depth_or_array_layers: layers },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let white = vec![255u8; (TEXTURE_SIZE * TEXTURE_SIZE * 4) as usize];
        let mut tex_bytes = 0u64;
        for layer in 0..layers {
            let data = if layer == 0 { white.clone() } else { resample(&scene.textures[layer as usize - 1]) };
            tex_bytes += data.len() as u64;
            queue.write_texture(
                wgpu::TexelCopyTextureInfo { texture: &textures, mip_level: 0, origin: wgpu::Origin3d { x: 0, y: 0, z: layer }, aspect: wgpu::TextureAspect::All },
                &data,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(TEXTURE_SIZE * 4), rows_per_image: Some(TEXTURE_SIZE) },
                wgpu::Extent3d { width: TEXTURE_SIZE, height: TEXTURE_SIZE, depth_or_array_layers: 1 },
            );
        }
        let texture_view = textures.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() });
        let bytes = (vertices.len() * std::mem::size_of::<super::Vertex>() + indices.len() * 4 + instance_bytes.len()) as u64 + tex_bytes;
        Self { vertices: vbuf, indices: ibuf, instances: inst_buf, textures, texture_view, draws, bytes }
    }
}

/// Nearest-neighbour resample of an image to TEXTURE_SIZE².
fn resample(img: &super::TextureImage) -> Vec<u8> {
    if img.width == TEXTURE_SIZE && img.height == TEXTURE_SIZE {
        return img.rgba.clone();
    }
    let mut out = Vec::with_capacity((TEXTURE_SIZE * TEXTURE_SIZE * 4) as usize);
    for y in 0..TEXTURE_SIZE {
        for x in 0..TEXTURE_SIZE {
            let sx = (x * img.width / TEXTURE_SIZE).min(img.width.saturating_sub(1));
            let sy = (y * img.height / TEXTURE_SIZE).min(img.height.saturating_sub(1));
            let i = ((sy * img.width + sx) * 4) as usize;
            out.extend_from_slice(img.rgba.get(i..i + 4).unwrap_or(&[255, 0, 255, 255]));
        }
    }
    out
}
