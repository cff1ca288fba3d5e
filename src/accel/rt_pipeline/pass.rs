//! [`RtPass`]: one trace pass of the `rt-pipeline` back-end as a ray-tracing pipeline (see
//! the module docs of [`super`]): made from its pipeline ([`PassPipeline`]) and its bind
//! groups, rebound as batches and acceleration structures change, and recorded into command
//! buffers of its own after wgpu's transitions.

use super::bind_group;
use super::bindings::{AccelBuffers, RtBinding, RtResource};
use super::hal_objects::{record_raw, HalObjects};
use super::pipeline::{PassPipeline, PipelineSource};
use super::structures::RtAccel;
use crate::error::RuntimeError;
use wgpu::hal;
use wgpu::hal::CommandEncoder as _;

/// A trace pass as a ray-tracing pipeline (see the module docs).
pub(crate) struct RtPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    label: String,
    objects: HalObjects,
    /// Per group: index into `objects.bind_group_layouts`, and of its bind group (`None` until
    /// bound).
    groups: Vec<(usize, Option<usize>)>,
    pipeline_layout: usize,
    pipeline: usize,
    sbt: usize,
    /// (offset, stride) of the ray-generation, miss and hit-group records.
    regions: [(u64, u64); 3],
    bindings: Vec<RtBinding>,
    accel_group: u32,
    /// The accel bind group's objects (replaced by every `bind_accel`).
    accel_objects: HalObjects,
    /// The cache's wgpu buffers the accel bind group refers to.
    accel_buffers: Vec<wgpu::Buffer>,
    /// Whether the written resources were cleared through wgpu (first `transition`).
    initialized: std::sync::atomic::AtomicBool,
}

impl RtPass {
    /// Makes the ray-tracing pipeline of a trace pass: `module` holds the pass's entry point
    /// `entry` as a ray-generation shader and the trace module's miss, closest-hit and any-hit
    /// shaders; `bindings` lists every binding of every group (`accel_group` is bound later by
    /// [`RtPass::bind_accel`]). The shader binding table is built here and uploaded on `queue`.
    /// `constants`: the pipeline constants of the ray-generation, miss and closest-hit stages.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        label: &str,
        module: &crate::graph::reflect::RayTracingModule,
        entry: &str,
        constants: &naga::back::PipelineConstants,
        bindings: Vec<RtBinding>,
        accel_group: u32,
    ) -> Result<Self, RuntimeError> {
        let source = PipelineSource { label, module, entry, constants };
        let PassPipeline { objects, groups, pipeline_layout, pipeline, sbt, regions } = PassPipeline::make(device, queue, &source, &bindings, accel_group)?;
        let group_count = groups.len() as u32;
        let mut pass = Self {
            device: device.clone(),
            queue: queue.clone(),
            label: label.to_string(),
            objects,
            groups,
            pipeline_layout,
            pipeline,
            sbt,
            regions,
            bindings,
            accel_group,
            accel_objects: HalObjects::default(),
            accel_buffers: Vec::new(),
            initialized: std::sync::atomic::AtomicBool::new(false),
        };
        for g in 0..group_count {
            if g != accel_group {
                let (bg, extra) = pass.make_group(g, None)?;
                pass.objects.bind_groups.push(bg);
                pass.objects.samplers.extend(extra.samplers);
                pass.objects.texture_views.extend(extra.texture_views);
                pass.groups[g as usize].1 = Some(pass.objects.bind_groups.len() - 1);
            }
        }
        Ok(pass)
    }

    /// A hal bind group for group `g`; `accel` binds the trace module's bindings. Returns the
    /// group and the objects made for it (texture views, samplers), which live as long as it.
    fn make_group(&self, g: u32, accel: Option<(&RtAccel, &AccelBuffers)>) -> Result<(hal::vulkan::BindGroup, HalObjects), RuntimeError> {
        let bindings: Vec<&RtBinding> = self.bindings.iter().filter(|b| b.group == g).collect();
        bind_group::make_group(&self.device, &self.label, &self.objects.bind_group_layouts[self.groups[g as usize].0], &bindings, accel)
    }

    /// Binds group `g` (not the trace module's) to other resources of the same layout: the
    /// batch tracer's ray and result buffers change with every batch. The old bind group is
    /// destroyed once the device is idle.
    pub(crate) fn set_group(&mut self, g: u32, bindings: Vec<RtBinding>) -> Result<(), RuntimeError> {
        if g == self.accel_group || g as usize >= self.groups.len() {
            return Err(RuntimeError::Gpu(format!("pass {}: group {g} cannot be rebound", self.label)));
        }
        self.bindings.retain(|b| b.group != g);
        self.bindings.extend(bindings.into_iter().map(|b| RtBinding { group: g, ..b }));
        let (bg, extra) = self.make_group(g, None)?;
        let mut old = HalObjects::default();
        if let Some(i) = self.groups[g as usize].1 {
            old.bind_groups.push(std::mem::replace(&mut self.objects.bind_groups[i], bg));
        } else {
            self.objects.bind_groups.push(bg);
            self.groups[g as usize].1 = Some(self.objects.bind_groups.len() - 1);
        }
        // The old group's views and samplers stay until the pass is dropped (a batch rebinds
        // only buffers, which make none).
        self.objects.samplers.extend(extra.samplers);
        self.objects.texture_views.extend(extra.texture_views);
        old.destroy(&self.device);
        Ok(())
    }

    /// Binds the trace module's group to `accel` and to the cache's buffers `cache` names
    /// (again whenever the cache replaces its acceleration structures).
    pub(crate) fn bind_accel(&mut self, accel: &RtAccel, cache: &AccelBuffers) -> Result<(), RuntimeError> {
        let (bg, mut extra) = self.make_group(self.accel_group, Some((accel, cache)))?;
        self.accel_objects.destroy(&self.device);
        // The cache's buffers stay alive as long as the bind group that names them.
        self.accel_buffers =
            self.bindings.iter().filter_map(|b| if let RtResource::Accel(n) = &b.resource { cache(n) } else { None }).map(|(b, _, _)| b).collect();
        extra.bind_groups.push(bg);
        self.accel_objects = extra;
        self.groups[self.accel_group as usize].1 = Some(usize::MAX);
        Ok(())
    }

    /// Puts every texture and buffer the pass binds into the state its bind groups were made
    /// for (step 1 of the module docs). The trace module's acceleration-structure buffers are
    /// hal's own and need none.
    ///
    /// wgpu zero-fills a texture or buffer before its first read if it never saw it written,
    /// and it does not see what hal commands write: without more, the first frame's trace
    /// results were zeroed before the next pass read them (tests/rt_pipeline.rs). The first
    /// call therefore writes zeros through the queue (before the frame's commands, and not a
    /// `clear_texture`, which wgpu does not count as initializing) into every texture and
    /// marked buffer the pass writes.
    pub(crate) fn transition(&self, encoder: &mut wgpu::CommandEncoder, stats: &wgpu::Buffer) {
        if !self.initialized.swap(true, std::sync::atomic::Ordering::Relaxed) {
            for b in &self.bindings {
                match &b.resource {
                    RtResource::Texture { texture, uses, .. }
                        if uses.intersects(wgpu::TextureUses::STORAGE_WRITE_ONLY | wgpu::TextureUses::STORAGE_READ_WRITE) =>
                    {
                        // A queue write is what wgpu certainly counts as initializing (a
                        // `clear_texture` is not).
                        let texel = texture.format().block_copy_size(None).unwrap_or(4);
                        let zeros = vec![0u8; (texture.width() * texture.height() * texel) as usize];
                        self.queue.write_texture(
                            wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
                            &zeros,
                            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(texture.width() * texel), rows_per_image: Some(texture.height()) },
                            wgpu::Extent3d { width: texture.width(), height: texture.height(), depth_or_array_layers: 1 },
                        );
                    }
                    RtResource::Buffer { buffer, initialize: true, .. } => self.queue.write_buffer(buffer, 0, &vec![0u8; buffer.size() as usize]),
                    _ => {}
                }
            }
        }
        let mut buffers: Vec<wgpu::BufferTransition<&wgpu::Buffer>> =
            vec![wgpu::BufferTransition { buffer: stats, state: wgpu::BufferUses::STORAGE_READ_WRITE }];
        let mut textures: Vec<wgpu::TextureTransition<&wgpu::Texture>> = Vec::new();
        for b in &self.bindings {
            match &b.resource {
                RtResource::Buffer { buffer, uses, .. } => buffers.push(wgpu::BufferTransition { buffer, state: *uses }),
                RtResource::Texture { texture, uses, .. } => textures.push(wgpu::TextureTransition { texture, selector: None, state: *uses }),
                RtResource::Textures(list) => {
                    textures.extend(list.iter().map(|(t, _)| wgpu::TextureTransition { texture: t, selector: None, state: wgpu::TextureUses::RESOURCE }))
                }
                RtResource::Sampler(_) | RtResource::Accel(_) => {}
            }
        }
        encoder.transition_resources(buffers.into_iter(), textures.into_iter());
    }

    /// The trace: `launch` ray-generation invocations, in a command buffer of its own (submit
    /// it after a wgpu command buffer that called [`RtPass::transition`]).
    pub fn record(&self, launch: [u32; 3]) -> Result<wgpu::CommandBuffer, RuntimeError> {
        if self.groups.iter().any(|(_, g)| g.is_none()) {
            return Err(RuntimeError::Gpu(format!("pass {}: the acceleration structure is not bound", self.label)));
        }
        record_raw(&self.device, &self.label, |_, enc| {
            let accel_group = self.accel_objects.bind_groups.last();
            let sbt = &self.objects.buffers[self.sbt];
            let data = |(offset, stride): (u64, u64)| hal::PipelineGroupData { buffer: sbt, offset, stride, count: 1 };
            // SAFETY: the pipeline, layout and bind groups were made by this device for each
            // other and are alive (owned by `self`, the accel group's resources by the caller's
            // `RtAccel`); the SBT regions lie inside the table at the device's alignments.
            unsafe {
                enc.begin_ray_tracing_pass(&hal::RayTracingPassDescriptor { label: Some(&self.label) });
                enc.set_ray_tracing_pipeline(&self.objects.pipelines[self.pipeline]);
                let layout = &self.objects.pipeline_layouts[self.pipeline_layout];
                for (g, (_, bg)) in self.groups.iter().enumerate() {
                    let group = match bg {
                        Some(usize::MAX) => accel_group.expect("bound by bind_accel"),
                        Some(i) => &self.objects.bind_groups[*i],
                        None => unreachable!("checked above"),
                    };
                    enc.set_bind_group(layout, g as u32, group, &[]);
                }
                enc.trace_rays(launch, data(self.regions[0]), data(self.regions[1]), data(self.regions[2]));
                enc.end_ray_tracing_pass();
            }
            Ok(())
        })
    }
}

impl Drop for RtPass {
    fn drop(&mut self) {
        self.accel_objects.destroy(&self.device);
        self.objects.destroy(&self.device);
    }
}
