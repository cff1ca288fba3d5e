//! What the viewer's viewport shows: the graph's output, or any texture of the running plan
//! (the pass inspector), drawn into one `Rgba8Unorm` display texture that egui draws.
//! Colour textures are copied and mapped on the GPU (`shaders/viewer/visualize.wgsl`: a scale
//! and bias per channel); depth textures are read back and mapped on the CPU.

use crate::gpu_util::compute_pipeline;
use crate::graph::compile::ResourceId;
use crate::graph::desc::{Format, ResourceDecl};
use crate::runtime::{Executor, Gpu};

/// How a texture's values become display colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapping {
    /// Per channel, the factor a value is multiplied by (`value * scale + bias`, clamped to [0, 1]).
    pub scale: [f32; 4],
    /// Per channel, the offset added after the scale.
    pub bias: [f32; 4],
    /// Channels of the format (1: grey, 2: red/green, 3-4: colour).
    pub channels: u32,
    /// The values are linear and get sRGB-encoded for display.
    pub encode_srgb: bool,
}

impl Mapping {
    /// Values shown as they are (the graph's output: display-encoded unless it is an sRGB
    /// format, whose texels read back linear).
    pub(crate) fn identity(format: Format) -> Self {
        Self { scale: [1.0; 4], bias: [0.0; 4], channels: format.texel_layout().0 as u32, encode_srgb: format == Format::Rgba8UnormSrgb }
    }

    /// Each channel's finite range over `texels` stretched to [0, 1] (a constant channel maps
    /// to its value clamped), shown linear.
    pub(crate) fn auto_range(format: Format, texels: &[[f32; 4]]) -> Self {
        let mut lo = [f32::INFINITY; 4];
        let mut hi = [f32::NEG_INFINITY; 4];
        for t in texels {
            for c in 0..4 {
                if t[c].is_finite() {
                    lo[c] = lo[c].min(t[c]);
                    hi[c] = hi[c].max(t[c]);
                }
            }
        }
        let mut m = Self { scale: [1.0; 4], bias: [0.0; 4], channels: format.texel_layout().0 as u32, encode_srgb: false };
        for c in 0..4 {
            if lo[c].is_finite() && hi[c] > lo[c] {
                m.scale[c] = 1.0 / (hi[c] - lo[c]);
                m.bias[c] = -lo[c] * m.scale[c];
            }
        }
        m
    }

    fn apply(&self, t: [f32; 4]) -> [u8; 4] {
        if !t.iter().all(|v| v.is_finite()) {
            return [255, 0, 255, 255];
        }
        let v: [f32; 4] = std::array::from_fn(|c| (t[c] * self.scale[c] + self.bias[c]).clamp(0.0, 1.0));
        let rgb = match self.channels {
            1 => [v[0]; 3],
            2 => [v[0], v[1], 0.0],
            _ => [v[0], v[1], v[2]],
        };
        let enc = |x: f32| if self.encode_srgb { crate::util::linear_to_srgb(x as f64) as f32 } else { x };
        [(enc(rgb[0]) * 255.0).round() as u8, (enc(rgb[1]) * 255.0).round() as u8, (enc(rgb[2]) * 255.0).round() as u8, 255]
    }
}

/// The texture format of a planned texture resource.
pub(crate) fn format_of(exec: &Executor, r: ResourceId) -> Option<Format> {
    match &exec.plan().resources.get(r)?.decl {
        ResourceDecl::Texture(t) => Some(t.format),
        _ => None,
    }
}

/// The display texture, its egui id and the GPU mapping pass.
pub struct Display {
    size: (u32, u32),
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// A copy of the shown texture (same format, sampled), made again when the format or size
    /// changes.
    source: Option<(wgpu::TextureFormat, (u32, u32), wgpu::Texture)>,
}

impl Display {
    /// The view of the display texture (what the overlay shows).
    pub(crate) fn view(&self) -> &wgpu::TextureView {
        &self.view
    }
}

const UNIFORM_BYTES: u64 = 48;

impl Display {
    pub(crate) fn new(gpu: &Gpu, size: (u32, u32), shader_source: &str) -> Self {
        let device = gpu.device();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewer display"),
            size: wgpu::Extent3d { width: size.0.max(1), height: size.1.max(1), depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let module = gpu.shader_module("viewer visualize", shader_source, crate::gpu_util::ShaderOrigin::Project);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewer visualize"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba8Unorm,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewer visualize"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = compute_pipeline(device, "viewer visualize", &pipeline_layout, &module, "cs_main");
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewer visualize"),
            size: UNIFORM_BYTES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { size, texture, view, pipeline, layout, uniforms, source: None }
    }

    /// Draws texture resource `r` of `exec` into the display texture with `mapping`.
    pub fn show(&mut self, gpu: &Gpu, exec: &Executor, r: ResourceId, mapping: &Mapping) -> Result<(), String> {
        let format = format_of(exec, r).ok_or("not a texture")?;
        let extent = exec.plan().resources[r].extent;
        if format.is_depth() {
            return self.show_on_cpu(gpu, exec, r, mapping);
        }
        if format.is_uint() {
            return Err(format!("{format:?} textures cannot be shown"));
        }
        let texture = exec.texture(r).ok_or("the texture is not allocated")?;
        let wgpu_format = format.to_wgpu();
        if !matches!(&self.source, Some((f, e, _)) if *f == wgpu_format && *e == extent) {
            let t = gpu.device().create_texture(&wgpu::TextureDescriptor {
                label: Some("viewer inspected copy"),
                size: wgpu::Extent3d { width: extent.0, height: extent.1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu_format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            self.source = Some((wgpu_format, extent, t));
        }
        let Some((_, _, source)) = &self.source else { unreachable!() };
        let mut words = [0u8; UNIFORM_BYTES as usize];
        for (i, v) in mapping.scale.iter().chain(&mapping.bias).enumerate() {
            words[i * 4..i * 4 + 4].copy_from_slice(&v.to_le_bytes());
        }
        words[32..36].copy_from_slice(&mapping.channels.to_le_bytes());
        words[36..40].copy_from_slice(&(mapping.encode_srgb as u32).to_le_bytes());
        gpu.queue().write_buffer(&self.uniforms, 0, &words);
        let source_view = source.create_view(&Default::default());
        let group = gpu.device().create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewer visualize"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&source_view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&self.view) },
                wgpu::BindGroupEntry { binding: 2, resource: self.uniforms.as_entire_binding() },
            ],
        });
        let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("viewer visualize") });
        encoder.copy_texture_to_texture(
            texture.as_image_copy(),
            source.as_image_copy(),
            wgpu::Extent3d { width: extent.0, height: extent.1, depth_or_array_layers: 1 },
        );
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("viewer visualize"), timestamp_writes: None });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        }
        gpu.queue().submit([encoder.finish()]);
        Ok(())
    }

    /// Depth textures cannot be copied into a colour texture: read back and mapped here.
    fn show_on_cpu(&mut self, gpu: &Gpu, exec: &Executor, r: ResourceId, mapping: &Mapping) -> Result<(), String> {
        let (w, h, texels) = exec.read_texture_f32(gpu, r).map_err(|e| e.to_string())?;
        let (dw, dh) = self.size;
        let mut rgba = vec![0u8; (dw * dh * 4) as usize];
        for y in 0..dh {
            for x in 0..dw {
                let (sx, sy) = ((x as u64 * w as u64 / dw as u64) as usize, (y as u64 * h as u64 / dh as u64) as usize);
                let px = mapping.apply(texels[sy * w as usize + sx]);
                let o = ((y * dw + x) * 4) as usize;
                rgba[o..o + 4].copy_from_slice(&px);
            }
        }
        gpu.queue().write_texture(
            self.texture.as_image_copy(),
            &rgba,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(dw * 4), rows_per_image: None },
            wgpu::Extent3d { width: dw, height: dh, depth_or_array_layers: 1 },
        );
        Ok(())
    }
}
