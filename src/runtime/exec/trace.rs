//! `Trace` passes: the trace module's bind group (re-made whenever the acceleration-structure
//! cache replaces its GPU objects), and on the `rt-pipeline` back-end the ray-tracing pipeline
//! (`crate::accel::rt_pipeline`), built from the same bindings and recorded into a command
//! buffer of its own. On the other back-ends a trace pass is a compute dispatch
//! ([`super::compute`]).

use super::bindings::{linear_sampler, nearest_sampler, resource_of, PassBindings};
use super::{Executor, FrameInputs, FrameRecording, PassRuntime, Pipeline};
use crate::accel::rt_pipeline::{RtBinding, RtPass, RtResource};
use crate::error::RuntimeError;
use crate::graph::builtins;
use crate::graph::compile::PlannedPass;
use crate::graph::desc::{Dispatch, ResourceDecl};
use crate::graph::reflect::{BindingKind, ShaderBinding};
use crate::runtime::gpu::Gpu;
use crate::runtime::scene_upload::SceneTextures;

/// The state a binding's resource is in while a pass uses it (the rt-pipeline back-end's
/// explicit transitions).
fn texture_uses(kind: &BindingKind) -> wgpu::TextureUses {
    match kind {
        BindingKind::StorageTexture { access, .. } if access.contains(naga::StorageAccess::LOAD) => wgpu::TextureUses::STORAGE_READ_WRITE,
        BindingKind::StorageTexture { .. } => wgpu::TextureUses::STORAGE_WRITE_ONLY,
        _ => wgpu::TextureUses::RESOURCE,
    }
}

fn buffer_uses(kind: &BindingKind) -> wgpu::BufferUses {
    match kind {
        BindingKind::Uniform { .. } => wgpu::BufferUses::UNIFORM,
        BindingKind::Storage { read_only: true, .. } => wgpu::BufferUses::STORAGE_READ_ONLY,
        _ => wgpu::BufferUses::STORAGE_READ_WRITE,
    }
}

impl Executor {
    /// A trace pass on the rt-pipeline back-end: the same bindings as the compute pass would
    /// have, bound through hal bind groups of a ray-tracing pipeline.
    pub(super) fn build_rt_pass(&self, gpu: &Gpu, pass: &PlannedPass, bindings: PassBindings) -> Result<PassRuntime, RuntimeError> {
        let shader = &pass.shader;
        let module = shader
            .ray_tracing
            .as_ref()
            .ok_or_else(|| RuntimeError::Gpu(format!("pass {}: the shader was not compiled with the rt-pipeline trace module", pass.name)))?;
        let mut rt_bindings = Vec::new();
        for b in &shader.bindings {
            let Some(entry) = bindings.layout_entries.iter().find(|(g, e)| *g == b.group && e.binding == b.binding).map(|(_, e)| *e) else { continue };
            let Some(resource) = self.rt_resource(pass, b, &bindings)? else { continue };
            rt_bindings.push(RtBinding { group: b.group, entry, resource });
        }
        // The ray-generation stage's constants: all but the alpha test (the any-hit shader's own).
        let constants: naga::back::PipelineConstants = self
            .features
            .constants(pass)
            .into_iter()
            .filter(|(name, _)| *name != super::features::TRACE_ALPHA_CONSTANT)
            .map(|(name, value)| (name.to_string(), value))
            .collect();
        let rt = RtPass::new(gpu.device(), gpu.queue(), &pass.name, module, &pass.entry, &constants, rt_bindings, builtins::ACCEL_GROUP)?;
        let wg = shader.entry(&pass.entry).map(|e| e.workgroup_size).unwrap_or([1, 1, 1]);
        // The launch grid: one ray-generation invocation per invocation of the compute dispatch.
        let launch = match pass.dispatch {
            Dispatch::Groups(x, y, z) => [x * wg[0].max(1), y * wg[1].max(1), z * wg[2].max(1)],
            Dispatch::PerPixel => {
                let extent = self.per_pixel_extent(pass);
                [extent.0, extent.1, 1]
            }
        };
        Ok(PassRuntime { groups: launch, params: bindings.params(), ..PassRuntime::bare(Pipeline::RayTracing(Box::new(rt))) })
    }

    /// The resource of binding `b` of an rt-pipeline trace pass; `None` for a declared
    /// acceleration structure (bound through the trace module's group).
    fn rt_resource(&self, pass: &PlannedPass, b: &ShaderBinding, bindings: &PassBindings) -> Result<Option<RtResource>, RuntimeError> {
        let buffer =
            |buffer: &wgpu::Buffer| RtResource::Buffer { buffer: buffer.clone(), offset: 0, size: None, uses: buffer_uses(&b.kind), initialize: false };
        if let Some(r) = resource_of(pass, &b.name) {
            return Ok(match &self.plan.resources[r].decl {
                ResourceDecl::Texture(_) => {
                    Some(RtResource::Texture { texture: self.slot_texture(r).clone(), view: self.texture_view(r), uses: texture_uses(&b.kind) })
                }
                ResourceDecl::Buffer(_) => Some(RtResource::Buffer {
                    buffer: self.buffer(r).clone(),
                    offset: 0,
                    size: None,
                    uses: buffer_uses(&b.kind),
                    initialize: pass.writes.iter().any(|(_, w)| *w == r),
                }),
                ResourceDecl::Accel => None,
            });
        }
        if b.group == builtins::ACCEL_GROUP {
            return Ok(Some(RtResource::Accel(b.name.clone())));
        }
        Ok(Some(match b.name.as_str() {
            builtins::FRAME => buffer(&self.frame_uniforms),
            builtins::DEBUG_COUNTERS => buffer(&self.debug_counters),
            builtins::PARAMS => buffer(&bindings.params_buffer.as_ref().expect("made for the params binding").1),
            builtins::SCENE_INSTANCES => buffer(self.scene_part(|s| s.instances())?),
            builtins::SCENE_MATERIALS => buffer(self.scene_part(|s| s.materials())?),
            builtins::SCENE_VERTICES => buffer(self.scene_part(|s| s.vertices())?),
            builtins::SCENE_INDICES => buffer(self.scene_part(|s| s.indices())?),
            builtins::SCENE_MESHES => buffer(self.scene_part(|s| s.meshes())?),
            builtins::SCENE_LIGHTS => buffer(self.scene_part(|s| s.lights())?),
            builtins::SCENE_EMITTERS => buffer(self.scene_part(|s| s.emitters())?),
            builtins::SCENE_MOTION => buffer(self.scene_part(|s| s.motion())?),
            builtins::SCENE_TEXTURES => match self.scene_part(|s| s.textures())? {
                SceneTextures::Array { texture, view } => {
                    RtResource::Texture { texture: texture.clone(), view: view.clone(), uses: wgpu::TextureUses::RESOURCE }
                }
                SceneTextures::Pooled { textures, views } => RtResource::Textures(textures.iter().cloned().zip(views.iter().cloned()).collect()),
            },
            builtins::SCENE_ENVIRONMENT | builtins::SCENE_ENVIRONMENT_IRRADIANCE => {
                let env = self.scene_part(|s| s.environment())?;
                let (texture, view) = if b.name == builtins::SCENE_ENVIRONMENT { env.radiance() } else { env.irradiance() };
                RtResource::Texture { texture: texture.clone(), view: view.clone(), uses: wgpu::TextureUses::RESOURCE }
            }
            builtins::SCENE_ENVIRONMENT_PARAMS => buffer(self.scene_part(|s| s.environment())?.params()),
            builtins::SCENE_ENVIRONMENT_TABLE => buffer(self.scene_part(|s| s.environment())?.table()),
            builtins::ENVIRONMENT_SAMPLER => RtResource::Sampler(crate::runtime::environment_upload::sampler_descriptor()),
            builtins::LINEAR_SAMPLER => RtResource::Sampler(linear_sampler()),
            builtins::NEAREST_SAMPLER => RtResource::Sampler(nearest_sampler()),
            other => return Err(RuntimeError::Gpu(format!("pass {}: binding `{other}` has no resource", pass.name))),
        }))
    }

    /// Records rt-pipeline trace pass `i`: its resources' transitions, then its own command
    /// buffer between the pass's timestamps.
    pub(super) fn record_rt_pass(&self, gpu: &Gpu, frame: &mut FrameRecording, inputs: &FrameInputs, i: usize, rt: &RtPass) -> Result<(), RuntimeError> {
        let (pass, planned) = (&self.passes[i], &self.plan.passes[i]);
        let cache = self.accel.as_ref().ok_or_else(|| RuntimeError::Gpu(format!("pass {} traces rays without an Accel node", planned.name)))?;
        rt.transition(&mut frame.encoder, cache.stats_window(0).0);
        if let Some(t) = &self.timer {
            t.mark(&mut frame.encoder, i as u32, false, inputs.merged, "trace begin");
        }
        let next = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        frame.command_buffers.push(std::mem::replace(&mut frame.encoder, next).finish());
        frame.command_buffers.push(rt.record(pass.groups)?);
        if let Some(t) = &self.timer {
            t.mark(&mut frame.encoder, i as u32, true, inputs.merged, "trace end");
        }
        Ok(())
    }

    /// Binds every trace pass to the cache's current GPU objects: the trace module's group of
    /// a compute dispatch, the acceleration structure and buffers of a ray-tracing pipeline.
    pub(super) fn bind_trace_passes_to_accel(&mut self, gpu: &Gpu) -> Result<(), RuntimeError> {
        let Some(cache) = self.accel.as_ref() else { return Ok(()) };
        let trace_passes = self.passes.iter_mut().filter(|p| p.accel_layout.is_some() || matches!(p.pipeline, Pipeline::RayTracing(_)));
        for (window, pass) in trace_passes.enumerate() {
            if let Pipeline::RayTracing(rt) = &mut pass.pipeline {
                let built = cache.rt_accel().ok_or_else(|| RuntimeError::Gpu("the rt-pipeline acceleration structure is not built".into()))?;
                rt.bind_accel(built, &crate::accel::cache::cache_buffers(cache, window as u32))?;
                continue;
            }
            let Some((layout, entries, names)) = &pass.accel_layout else { continue };
            let mut bg_entries = Vec::new();
            for (e, name) in entries.iter().zip(names) {
                let resource =
                    cache.binding(name, window as u32).ok_or_else(|| RuntimeError::Gpu(format!("the {} back-end has no binding `{name}`", cache.backend())))?;
                bg_entries.push(wgpu::BindGroupEntry { binding: e.binding, resource });
            }
            pass.accel_group = Some(gpu.device().create_bind_group(&wgpu::BindGroupDescriptor { label: Some("accel"), layout, entries: &bg_entries }));
        }
        Ok(())
    }
}
