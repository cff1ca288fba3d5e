//! What `Fullscreen` and `SceneRaster` passes share: the render pipeline's spec from the
//! pass's shader and attachments, the attachments' views (made with the pass, not per frame),
//! and the render pass each records into (attachments cleared, the pass's bind groups set,
//! timestamps around it).

use super::bindings::{shader_module, PassBindings, PassLayout};
use super::{Executor, PassRuntime, Pipeline};
use crate::graph::compile::PlannedPass;
use crate::graph::desc::{PassKind, ResourceDecl};
use crate::runtime::gpu::Gpu;
use crate::runtime::raster::RenderSpec;

/// The scene vertex attributes (position, normal, uv) that `pass`'s vertex stage reads.
fn scene_vertex_attributes(pass: &PlannedPass) -> Vec<wgpu::VertexAttribute> {
    let attributes = [
        wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 },
        wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 12, shader_location: 1 },
        wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x2, offset: 24, shader_location: 2 },
    ];
    let locations = pass.shader.entry(&pass.vertex_entry).map(|e| e.locations.clone()).unwrap_or_default();
    attributes.iter().filter(|a| locations.contains(&a.shader_location)).copied().collect()
}

/// The blending of colour target `k` of a translucent pass (`PassDesc::translucent`): the first
/// premultiplied-alpha "over", back to front; the others `src + (1 - src) x dst` per channel.
fn translucent_blend(k: usize) -> wgpu::BlendState {
    if k == 0 {
        return wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING;
    }
    let one_minus_product =
        wgpu::BlendComponent { src_factor: wgpu::BlendFactor::One, dst_factor: wgpu::BlendFactor::OneMinusSrc, operation: wgpu::BlendOperation::Add };
    wgpu::BlendState { color: one_minus_product, alpha: one_minus_product }
}

impl Executor {
    /// A raster pass whose pipeline `pipeline` makes from the pass's [`RenderSpec`].
    pub(super) fn build_render_pass(
        &self,
        gpu: &Gpu,
        pass: &PlannedPass,
        layout: PassLayout,
        bindings: PassBindings,
        pipeline: impl FnOnce(RenderSpec) -> Pipeline,
    ) -> PassRuntime {
        let module = shader_module(gpu, pass);
        let (colors, depth) = self.attachments(pass);
        let targets: Vec<Option<wgpu::ColorTargetState>> = colors
            .iter()
            .enumerate()
            .map(|(k, r)| match &self.plan.resources[*r].decl {
                ResourceDecl::Texture(t) => Some(wgpu::ColorTargetState {
                    format: t.format.to_wgpu(),
                    blend: pass.translucent.then_some(translucent_blend(k)),
                    write_mask: wgpu::ColorWrites::ALL,
                }),
                ResourceDecl::Buffer(_) | ResourceDecl::Accel => None,
            })
            .collect();
        let PassLayout { layout, bind_groups, accel_layout } = layout;
        let alpha_switch = pass.shader.has_override(crate::runtime::raster::ALPHA_TEST_CONSTANT);
        let views = [false, true].map(|swapped| {
            (colors.iter().map(|r| self.attachment_view_at(*r, swapped, pass.layer)).collect(), depth.map(|r| self.attachment_view_at(r, swapped, pass.layer)))
        });
        let spec = RenderSpec {
            label: pass.name.clone(),
            layout,
            module,
            vertex_entry: pass.vertex_entry.clone(),
            fragment_entry: pass.entry.clone(),
            targets,
            scene_attributes: (pass.kind == PassKind::SceneRaster).then(|| scene_vertex_attributes(pass)),
            depth: depth.is_some(),
            alpha_switch,
            scene_constants: self.features.constants(pass),
            fragment_only_alpha_tests: alpha_switch && colors.is_empty() && pass.shader.source.is_builtin(),
        };
        PassRuntime { bind_groups, accel_layout, views, params: bindings.params(), ..PassRuntime::bare(pipeline(spec)) }
    }

    /// The render pass of raster pass `i` over its attachments (all cleared), with the pass's
    /// bind groups set.
    pub(super) fn begin_render_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder, i: usize) -> wgpu::RenderPass<'e> {
        let (color_views, depth_view) = self.passes[i].views(self.history.swapped);
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = color_views
            .iter()
            .map(|v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
                })
            })
            .collect();
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&self.plan.passes[i].name),
            color_attachments: &attachments,
            depth_stencil_attachment: depth_view.as_ref().map(|v| wgpu::RenderPassDepthStencilAttachment {
                view: v,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: self.timer.as_ref().and_then(|t| t.render_writes(i as u32)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for (g, bg) in self.passes[i].bind_groups(self.history.swapped).iter().enumerate() {
            rp.set_bind_group(g as u32, bg, &[]);
        }
        rp
    }
}
