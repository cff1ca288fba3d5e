//! The scene's environment map on the device (`shaders/common/environment.wgsl`, bind group 3
//! of the passes that read it): the radiance as a half-float equirectangular texture whose mip
//! levels hold it prefiltered for glossy reflections (`Environment::specular_chain`), the
//! irradiance on a 64 x 32 grid of normals, the importance sampler's alias table
//! and the parameters (intensity, rotation). A scene without a map binds 1x1 stand-ins that no
//! shader reads (`SCENE_ENVIRONMENT` is false there).

use crate::graph::desc::f32_to_f16;
use crate::scene::environment::{Environment, EnvironmentSampler};
use crate::uniforms::EnvironmentUniforms;
use wgpu::util::DeviceExt;

/// Mip levels of the radiance texture: the map, then GGX lobes of roughness 0.2, 0.4, ... 1
/// (fewer for a map too small to halve that often).
pub const SPECULAR_LEVELS: usize = 6;

/// Columns of the irradiance grid (rows: half as many): scene::environment's tests measure a
/// 64 x 32 grid within 10% of the exact sums on the two maps of assets/env.
pub const IRRADIANCE_GRID_WIDTH: usize = 64;

/// The environment's device resources.
pub struct GpuEnvironment {
    /// The map they were made from: its address, intensity and rotation (`None`: stand-ins).
    source: Option<(usize, u32, u32)>,
    radiance: (wgpu::Texture, wgpu::TextureView),
    irradiance: (wgpu::Texture, wgpu::TextureView),
    table: wgpu::Buffer,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    bytes: u64,
}

/// What identifies a map's uploaded form: the map (by address: a scene's map is shared, never
/// edited in place), its intensity and its rotation.
fn source_of(env: Option<&std::sync::Arc<Environment>>) -> Option<(usize, u32, u32)> {
    env.map(|e| (std::sync::Arc::as_ptr(e) as usize, e.intensity.to_bits(), e.rotation.to_bits()))
}

impl GpuEnvironment {
    /// Whether these resources were made from `env` (the prefiltering need not run again).
    pub fn made_from(&self, env: Option<&std::sync::Arc<Environment>>) -> bool {
        self.source == source_of(env)
    }

    /// Uploads `env` (1x1 stand-ins for `None`).
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, env: Option<&std::sync::Arc<Environment>>) -> Self {
        let source = source_of(env);
        let env = env.map(|e| e.as_ref());
        let chain = env.map(|e| e.specular_chain(SPECULAR_LEVELS)).unwrap_or_default();
        let levels: Vec<Level> = chain.iter().map(|e| Level { size: e.size(), texels: e.texels() }).collect();
        let radiance = half_texture(device, queue, "environment radiance", &levels);
        let grid = env.map(|e| e.irradiance_map(IRRADIANCE_GRID_WIDTH));
        let grid_texels: Vec<[f32; 3]> = grid.iter().flat_map(|g| g.texels().iter().map(|t| t.to_array())).collect();
        let grid_level: Vec<Level> = grid.iter().map(|g| Level { size: g.size(), texels: &grid_texels }).collect();
        let irradiance = half_texture(device, queue, "environment irradiance", &grid_level);
        let sampler_table = env.and_then(EnvironmentSampler::new);
        let slots = sampler_table.as_ref().map_or_else(|| vec![[0u32; 4]], EnvironmentSampler::gpu_slots);
        let table = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("environment table"),
            contents: bytemuck::cast_slice(&slots),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let (width, height) = env.map_or((1, 1), Environment::size);
        let uniforms = EnvironmentUniforms {
            intensity: env.map_or(0.0, |e| e.intensity),
            rotation_cos: env.map_or(1.0, |e| e.rotation.cos()),
            rotation_sin: env.map_or(0.0, |e| e.rotation.sin()),
            levels: levels.len().max(1) as f32,
            width: width as u32,
            height: height as u32,
            sampled: u32::from(sampler_table.is_some()),
            _pad: 0,
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("environment params"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let sampler = device.create_sampler(&sampler_descriptor());
        let texel_bytes: usize = levels.iter().chain(&grid_level).map(|l| l.texels.len() * 8).sum();
        Self { source, radiance, irradiance, table, params, sampler, bytes: (texel_bytes + slots.len() * 16) as u64 }
    }

    /// The radiance texture and its view (`scene_environment`).
    pub fn radiance(&self) -> &(wgpu::Texture, wgpu::TextureView) {
        &self.radiance
    }

    /// The irradiance grid and its view (`scene_environment_irradiance`).
    pub fn irradiance(&self) -> &(wgpu::Texture, wgpu::TextureView) {
        &self.irradiance
    }

    /// The sampler's alias table (`scene_environment_table`).
    pub fn table(&self) -> &wgpu::Buffer {
        &self.table
    }

    /// The parameters (`scene_environment_params`).
    pub fn params(&self) -> &wgpu::Buffer {
        &self.params
    }

    /// The sampler (`environment_sampler`): linear, repeating around, clamped at the poles.
    pub fn sampler(&self) -> &wgpu::Sampler {
        &self.sampler
    }

    /// Bytes uploaded.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

/// The sampler's descriptor (`environment_sampler`): linear, repeating around the up axis,
/// clamped at the poles.
pub fn sampler_descriptor() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor {
        label: Some("environment sampler"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    }
}

/// One mip level's texels (linear RGB, row-major).
struct Level<'a> {
    size: (usize, usize),
    texels: &'a [[f32; 3]],
}

/// A half-float RGBA texture of `levels` (one mip each; one black texel for none).
fn half_texture(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, levels: &[Level]) -> (wgpu::Texture, wgpu::TextureView) {
    let black = [Level { size: (1, 1), texels: &[[0.0; 3]] }];
    let levels = if levels.is_empty() { &black[..] } else { levels };
    let (width, height) = levels[0].size;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: width as u32, height: height as u32, depth_or_array_layers: 1 },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (mip, level) in levels.iter().enumerate() {
        let (w, h) = level.size;
        // Half floats end at 65504: a brighter texel (a sun's core) is held at that.
        let halves: Vec<u16> = level.texels.iter().flat_map(|t| [t[0], t[1], t[2], 1.0]).map(|c| f32_to_f16(c.min(65504.0))).collect();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo { texture: &texture, mip_level: mip as u32, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
            bytemuck::cast_slice(&halves),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8 * w as u32), rows_per_image: Some(h as u32) },
            wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: 1 },
        );
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}
