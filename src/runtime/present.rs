//! Showing the graph's output in a window or a canvas: a copy of the output texture drawn
//! texel for texel into the surface's texture (no scaling, no colour conversion: the output is
//! display-encoded, and the surface view is the non-sRGB view of its format). The winit
//! example and the web page present through it.

use crate::error::RuntimeError;
use crate::runtime::{Executor, Gpu};

const BLIT_WGSL: &str = r#"
@group(0) @binding(0) var source: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let texel = min(vec2<u32>(position.xy), textureDimensions(source) - 1u);
    return vec4<f32>(textureLoad(source, texel, 0).rgb, 1.0);
}
"#;

/// Draws an executor's output into surface textures of one format.
pub struct Presenter {
    format: wgpu::TextureFormat,
    pipeline: wgpu::RenderPipeline,
    /// The copy of the output the blit reads, and its bind group; made again on a new size.
    copy: Option<(wgpu::Texture, wgpu::BindGroup)>,
}

impl Presenter {
    /// For surface textures of `format` (an sRGB format is drawn through its non-sRGB view,
    /// which the surface must list among its view formats).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        let device = gpu.device();
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("present"), source: wgpu::ShaderSource::Wgsl(BLIT_WGSL.into()) });
        let format = format.remove_srgb_suffix();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("present"),
            layout: None,
            vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[] },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { format, pipeline, copy: None }
    }

    /// Records and submits the draw of `exec`'s output (after its frame) into `target`.
    pub fn present(&mut self, gpu: &Gpu, exec: &Executor, target: &wgpu::Texture) -> Result<(), RuntimeError> {
        let output = exec.texture(exec.plan().output()).ok_or_else(|| RuntimeError::Gpu("the graph's output is not a texture".into()))?;
        let size = output.size();
        if !self.copy.as_ref().is_some_and(|(t, _)| t.size() == size && t.format() == output.format()) {
            let texture = gpu.device().create_texture(&wgpu::TextureDescriptor {
                label: Some("graph output copy"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: output.format(),
                usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let bind_group = gpu.device().create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("present"),
                layout: &self.pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&texture.create_view(&Default::default())) }],
            });
            self.copy = Some((texture, bind_group));
        }
        let Some((copy, bind_group)) = &self.copy else { unreachable!("made above") };
        let view = target.create_view(&wgpu::TextureViewDescriptor { format: Some(self.format), ..Default::default() });
        let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("present") });
        encoder.copy_texture_to_texture(output.as_image_copy(), copy.as_image_copy(), size);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("present"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.queue().submit([encoder.finish()]);
        Ok(())
    }
}
