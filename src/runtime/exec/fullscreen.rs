//! `Fullscreen` passes: a render pipeline with no vertex buffer, one triangle covering the
//! pass's attachments.

use super::bindings::{PassBindings, PassLayout};
use super::{Executor, PassRuntime, Pipeline};
use crate::graph::compile::PlannedPass;
use crate::runtime::gpu::Gpu;
use crate::runtime::raster::DrawClass;

impl Executor {
    pub(super) fn build_fullscreen_pass(&self, gpu: &Gpu, pass: &PlannedPass, layout: PassLayout, bindings: PassBindings) -> PassRuntime {
        self.build_render_pass(gpu, pass, layout, bindings, |spec| Pipeline::Render(spec.create(gpu.device(), DrawClass::FULLSCREEN, 0)))
    }

    /// Records fullscreen pass `i`: one triangle into its attachments.
    pub(super) fn record_fullscreen_pass(&self, encoder: &mut wgpu::CommandEncoder, i: usize, pipeline: &wgpu::RenderPipeline) {
        let mut rp = self.begin_render_pass(encoder, i);
        rp.set_pipeline(pipeline);
        rp.draw(0..3, 0..1);
    }
}
