//! `AccelBuild` passes, the `Accel` node's build: the acceleration-structure cache made from
//! the node's settings, and its update recorded at the node's place in the schedule between a
//! pair of timestamps (the trace passes then bound to what it built).

use super::{Executor, FrameInputs, PassRuntime, Pipeline};
use crate::accel::cache::{AccelCache, AccelSettings, BuildReport, MergedBuilder};
use crate::error::RuntimeError;
use crate::graph::compile::Plan;
use crate::graph::desc::PassKind;
use crate::runtime::gpu::Gpu;
use web_time::Instant;

impl Executor {
    /// The cache of the plan's `Accel` node, if it has one (settings from the node; the GPU
    /// builder for merged rebuilds on a real GPU).
    pub(super) fn accel_cache(gpu: &Gpu, plan: &Plan) -> Option<AccelCache> {
        plan.passes.iter().find(|p| p.kind == PassKind::AccelBuild).map(|p| {
            let settings = AccelSettings { dedup: p.accel.as_ref().is_none_or(|a| a.dedup), merge: p.accel.as_ref().is_some_and(|a| a.merge) };
            log::info!("acceleration structures: back-end {}, {}", plan.backend, settings.describe(plan.backend));
            let mut cache = AccelCache::new(gpu.device(), plan.backend, settings, plan.passes.iter().filter(|p| p.kind == PassKind::Trace).count() as u32);
            // The GPU builder waits for a few words it reads back after its kernels, which a
            // browser cannot wait for within a frame: on the web the CPU builds.
            if gpu.info().device_type != wgpu::DeviceType::Cpu && !cfg!(target_arch = "wasm32") {
                cache.set_merged_builder(MergedBuilder::GpuRebuilds);
            }
            cache.set_pooled_textures(plan.scene_usage.texture_binding_array);
            if gpu.packed_accel_arrays() && plan.backend == crate::backend::Backend::Compute {
                cache.pack_arrays();
            }
            cache
        })
    }

    /// The pass of an `Accel` node: no pipeline, no bindings.
    pub(super) fn accel_build_pass() -> PassRuntime {
        PassRuntime::bare(Pipeline::AccelBuild)
    }

    /// Runs the `Accel` node: clears the ray counters, updates the cache between a pair of
    /// timestamps, and re-creates the trace passes' accel bind groups if the cache replaced
    /// its GPU objects. Returns the build report and its CPU milliseconds.
    pub(super) fn update_accel(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        command_buffers: &mut Vec<wgpu::CommandBuffer>,
        inputs: &FrameInputs,
    ) -> Result<Option<(BuildReport, f64)>, RuntimeError> {
        let scene = inputs.scene;
        let Some(cache) = self.accel.as_mut() else { return Ok(None) };
        let index = self.plan.passes.iter().position(|p| p.kind == PassKind::AccelBuild).unwrap_or(0) as u32;
        cache.clear_stats(encoder);
        if let Some(t) = &self.timer {
            t.mark(encoder, index, false, inputs.merged, "accel begin");
        }
        let t0 = Instant::now();
        let report = cache.update(gpu.device(), gpu.queue(), encoder, scene)?;
        cache.record_packing(gpu.device(), gpu.queue(), encoder)?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        // The rt-pipeline back-end's build, recorded through wgpu-hal: submitted between the
        // node's timestamps, before every trace.
        if let Some(build) = cache.take_pending() {
            let next = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
            command_buffers.push(std::mem::replace(encoder, next).finish());
            command_buffers.push(build);
        }
        if let Some(t) = &self.timer {
            t.mark(encoder, index, true, inputs.merged, "accel end");
        }
        let generation = cache.generation();
        if generation != self.accel_generation {
            self.bind_trace_passes_to_accel(gpu)?;
            // Only once every pass is bound to the new objects: a failure above rebinds them
            // all next frame.
            self.accel_generation = generation;
        }
        Ok(Some((report, ms)))
    }

    /// The acceleration-structure cache, for graphs that trace rays.
    pub fn accel(&self) -> Option<&AccelCache> {
        self.accel.as_ref()
    }

    /// The acceleration-structure cache, to change how it builds (before the first frame).
    pub fn accel_mut(&mut self) -> Option<&mut AccelCache> {
        self.accel.as_mut()
    }
}
