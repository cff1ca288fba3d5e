//! `Compute` passes (and `Trace` passes on the compute and ray-query back-ends, which are
//! compute dispatches too): the compute pipeline, the dispatch size, and the recorded dispatch.
//! Where the device writes timestamps inside passes (`Gpu::merges_compute_passes`), a run of
//! consecutive compute nodes is recorded as one wgpu compute pass, each node's dispatch between
//! its own pair of timestamps: wgpu orders the dispatches of one pass as it orders passes, so
//! the frame is the same, with a fraction of the command buffers and barrier sets to encode.

use super::bindings::{shader_module, PassBindings, PassLayout};
use super::{Executor, FrameInputs, PassRuntime, Pipeline};
use crate::gpu_util::{compute_pipeline_with, ShaderOrigin};
use crate::graph::builtins;
use crate::graph::compile::PlannedPass;
use crate::graph::desc::{Dispatch, PassKind};
use crate::runtime::gpu::Gpu;
use std::ops::Range;
use web_time::Instant;

impl Executor {
    pub(super) fn build_compute_pass(&self, gpu: &Gpu, pass: &PlannedPass, layout: PassLayout, bindings: PassBindings) -> PassRuntime {
        let mut constants = self.features.constants(pass);
        let merged = self.accel.as_ref().is_some_and(|a| a.merged_layout());
        if pass.kind == PassKind::Trace && merged && pass.shader.has_override(super::features::TRACE_MERGED_CONSTANT) {
            constants.push((super::features::TRACE_MERGED_CONSTANT, 1.0));
        }
        let (module, constants) = if pass.kind == PassKind::Trace {
            let groups = bindings.layout_groups();
            gpu.traversal_module(&pass.shader.path.display().to_string(), pass.shader.source.text(), &pass.entry, ShaderOrigin::TracePass, &constants, &groups)
        } else {
            (shader_module(gpu, pass), constants)
        };
        let p = compute_pipeline_with(gpu.device(), &pass.name, &layout.layout, &module, &pass.entry, &constants);
        let PassLayout { bind_groups, accel_layout, .. } = layout;
        PassRuntime { bind_groups, accel_layout, groups: self.workgroups(pass), params: bindings.params(), ..PassRuntime::bare(Pipeline::Compute(p)) }
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
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(&self.plan.passes[i].name),
            timestamp_writes: self.timer.as_ref().and_then(|t| t.compute_writes(i as u32)),
        });
        self.record_dispatch(&mut cp, i, pipeline);
    }

    /// The end of the run of compute nodes that starts at pass `i` (`i` itself when none
    /// starts there, or when the frame records one pass per node): compute dispatches, and
    /// raster and rt-pipeline passes the frame skips (nothing recorded).
    pub(super) fn compute_run_end(&self, inputs: &FrameInputs, i: usize) -> usize {
        if !inputs.merged {
            return i;
        }
        let joins = |k: usize| match self.passes[k].pipeline {
            Pipeline::Compute(_) => true,
            Pipeline::Render(_) | Pipeline::Scene(_) | Pipeline::RayTracing(_) => inputs.skipped[k],
            Pipeline::AccelBuild | Pipeline::Rust { .. } => false,
        };
        (i..self.passes.len()).find(|&k| !joins(k)).unwrap_or(self.passes.len())
    }

    /// Records passes `run` ([`Executor::compute_run_end`]) as one compute pass (their `zeroed`
    /// buffers cleared first), each node between its own timestamps written inside it, in a
    /// debug group of its name; pushes each node's CPU milliseconds to `cpu_ms`. A pass the
    /// frame skips records nothing (no timestamps either: `GpuTimer::skip`).
    pub(super) fn record_compute_run(&self, encoder: &mut wgpu::CommandEncoder, run: Range<usize>, skipped: &[bool], cpu_ms: &mut Vec<f64>) {
        // A buffer cannot be cleared inside a compute pass: the run's `zeroed` buffers are
        // cleared before it, which is before each of their writers.
        for i in run.clone() {
            self.zero_buffers_written(encoder, i);
        }
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("compute nodes"), timestamp_writes: None });
        for i in run {
            let t0 = Instant::now();
            cp.push_debug_group(&self.plan.passes[i].name);
            if let Some(t) = &self.timer {
                t.write_in_pass(&mut cp, i as u32, false);
            }
            match &self.passes[i].pipeline {
                Pipeline::Compute(pipeline) if !skipped[i] => self.record_dispatch(&mut cp, i, pipeline),
                _ => {}
            }
            if let Some(t) = &self.timer {
                t.write_in_pass(&mut cp, i as u32, true);
            }
            cp.pop_debug_group();
            cpu_ms.push(if matches!(self.passes[i].pipeline, Pipeline::Compute(_)) && !skipped[i] { t0.elapsed().as_secs_f64() * 1e3 } else { 0.0 });
        }
    }

    /// Records compute node `i`'s pipeline, bind groups and dispatch into `cp`.
    fn record_dispatch(&self, cp: &mut wgpu::ComputePass<'_>, i: usize, pipeline: &wgpu::ComputePipeline) {
        let pass = &self.passes[i];
        cp.set_pipeline(pipeline);
        for (g, bg) in pass.bind_groups(self.history.swapped).iter().enumerate() {
            // A trace pass's own groups skip the trace module's (set below).
            let index = if pass.accel_layout.is_some() && g as u32 >= builtins::ACCEL_GROUP { g as u32 + 1 } else { g as u32 };
            cp.set_bind_group(index, bg, &[]);
        }
        if let Some(bg) = &pass.accel_group {
            cp.set_bind_group(builtins::ACCEL_GROUP, bg, &[]);
        }
        cp.dispatch_workgroups(pass.groups[0], pass.groups[1], pass.groups[2]);
    }
}
