//! `Compute` passes (and `Trace` passes on the compute and ray-query back-ends, which are
//! compute dispatches too): the compute pipeline, the dispatch size, and the recorded dispatch.

use super::bindings::{shader_module, PassBindings, PassLayout};
use super::{Executor, PassRuntime, Pipeline};
use crate::gpu_util::{compute_pipeline_with, ShaderOrigin};
use crate::graph::builtins;
use crate::graph::compile::PlannedPass;
use crate::graph::desc::{Dispatch, PassKind};
use crate::runtime::gpu::Gpu;

impl Executor {
    pub(super) fn build_compute_pass(&self, gpu: &Gpu, pass: &PlannedPass, layout: PassLayout, bindings: PassBindings) -> PassRuntime {
        let constants = self.features.constants(pass);
        let (module, constants) = if pass.kind == PassKind::Trace {
            let groups = bindings.layout_groups();
            gpu.traversal_module(&pass.shader.path.display().to_string(), pass.shader.source.text(), &pass.entry, ShaderOrigin::TracePass, &constants, &groups)
        } else {
            (shader_module(gpu, pass), constants)
        };
        let (colors, depth) = self.attachments(pass);
        let p = compute_pipeline_with(gpu.device(), &pass.name, &layout.layout, &module, &pass.entry, &constants);
        let PassLayout { bind_groups, accel_layout, .. } = layout;
        PassRuntime {
            bind_groups,
            accel_layout,
            colors,
            depth,
            groups: self.workgroups(pass),
            params: bindings.params(),
            ..PassRuntime::bare(Pipeline::Compute(p))
        }
    }

    /// The workgroups a compute pass dispatches: the pass's `Groups`, or enough of the shader's
    /// workgroup size to cover its `PerPixel` extent.
    fn workgroups(&self, pass: &PlannedPass) -> [u32; 3] {
        match pass.dispatch {
            Dispatch::Groups(x, y, z) => [x, y, z],
            Dispatch::PerPixel => {
                let extent = self.per_pixel_extent(pass);
                let wg = pass.shader.entry(&pass.entry).map(|e| e.workgroup_size).unwrap_or([1, 1, 1]);
                [extent.0.div_ceil(wg[0].max(1)), extent.1.div_ceil(wg[1].max(1)), 1]
            }
        }
    }

    /// Records compute pass `i`: its bind groups (a trace pass's trace module group too) and
    /// the dispatch, between the pass's timestamps.
    pub(super) fn record_compute_pass(&self, encoder: &mut wgpu::CommandEncoder, i: usize, pipeline: &wgpu::ComputePipeline) {
        let (pass, planned) = (&self.passes[i], &self.plan.passes[i]);
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(&planned.name),
            timestamp_writes: self.timer.as_ref().and_then(|t| t.compute_writes(i as u32)),
        });
        cp.set_pipeline(pipeline);
        for (g, bg) in pass.bind_groups(self.history.swapped).iter().enumerate() {
            cp.set_bind_group(g as u32, bg, &[]);
        }
        if let Some(bg) = &pass.accel_group {
            cp.set_bind_group(builtins::ACCEL_GROUP, bg, &[]);
        }
        cp.dispatch_workgroups(pass.groups[0], pass.groups[1], pass.groups[2]);
    }
}
