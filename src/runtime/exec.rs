//! The executor: allocates a plan's slots, builds pipelines and bind groups from shader
//! reflection, and records every pass of a frame with a timestamp pair around it.

use super::gpu::Gpu;
use super::profiler::{FrameTimings, GpuTimer};
use super::raster::{DrawClass, InstanceClass, RenderSpec, ScenePipelines};
use crate::accel::cache::{AccelCache, AccelSettings, MergedBuilder};
use crate::accel::rt_pipeline::{RtBinding, RtPass, RtResource};
use crate::error::{ErrorKind, GraphError, RuntimeError};
use crate::gpu_util::{compute_pipeline_with, map_read, readback_buffer, storage_buffer};
use crate::graph::builtins;
use crate::graph::compile::{Plan, PlannedPass, ResourceId};
use crate::graph::desc::{Dispatch, ParamDecl, ParamValue, PassKind, ResourceDecl};
use crate::graph::reflect::BindingKind;
use crate::scene::gpu::{light_records, GpuScene, SceneContent, SceneTextures};
use crate::scene::{Camera, Scene};
use crate::uniforms::{FrameUniforms, SHADOW_MAP_SLOTS};
use std::collections::BTreeMap;
use std::time::Instant;

enum Pipeline {
    Compute(wgpu::ComputePipeline),
    /// A fullscreen pass.
    Render(wgpu::RenderPipeline),
    /// A `SceneRaster` pass: one variant per draw class (`super::raster`).
    Scene(ScenePipelines),
    /// The `Accel` node's build: the cache's update, recorded at the node's place in the schedule.
    AccelBuild,
    /// A trace pass on the `rt-pipeline` back-end: a ray-tracing pipeline recorded through
    /// wgpu-hal into a command buffer of its own (`crate::accel::rt_pipeline`).
    RayTracing(Box<RtPass>),
}

struct PassRuntime {
    pipeline: Pipeline,
    /// One per `@group`, in order; the trace module's group is in `accel_group`.
    bind_groups: Vec<wgpu::BindGroup>,
    /// Trace passes: the layout of the trace module's bind group, and the group itself (made
    /// again whenever the cache replaces its GPU objects).
    accel_layout: Option<(wgpu::BindGroupLayout, Vec<wgpu::BindGroupLayoutEntry>, Vec<String>)>,
    accel_group: Option<wgpu::BindGroup>,
    colors: Vec<ResourceId>,
    depth: Option<ResourceId>,
    groups: [u32; 3],
    /// The pass's `params` uniform buffer and the members written into it (see
    /// [`Executor::set_param`]).
    params: Option<(wgpu::Buffer, u64, Vec<crate::graph::reflect::UniformMember>)>,
}

/// The bytes of a `params` uniform of `size` bytes: each member named after a parameter gets
/// that parameter's value in the member's type.
fn encode_params(params: &BTreeMap<String, (ParamDecl, ParamValue)>, members: &[crate::graph::reflect::UniformMember], size: u64) -> Vec<u8> {
    let mut bytes = vec![0u8; (size as usize).max(16)];
    for m in members {
        let Some((decl, value)) = params.get(&m.name) else { continue };
        let word: [u8; 4] = match (decl, *value, m.scalar) {
            (_, ParamValue::Float(v), _) => (v as f32).to_le_bytes(),
            (_, ParamValue::Int(v), Some(naga::ScalarKind::Uint)) => (v as u32).to_le_bytes(),
            (_, ParamValue::Int(v), _) => (v as i32).to_le_bytes(),
            (_, ParamValue::Bool(v), _) => (v as u32).to_le_bytes(),
        };
        let o = m.offset as usize;
        bytes[o..o + 4].copy_from_slice(&word);
    }
    bytes
}

/// The `linear_sampler` built-in.
fn linear_sampler() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor {
        label: Some("linear"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    }
}

/// The `nearest_sampler` built-in.
fn nearest_sampler() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor { label: Some("nearest"), ..Default::default() }
}

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

enum Physical {
    Texture(wgpu::Texture),
    Buffer(wgpu::Buffer),
    /// An acceleration structure: owned by the [`AccelCache`], not by a slot.
    Accel,
}

/// The label of slot `i`: the resources it holds and its size, so that an allocation error
/// names them (`slot 4: gbuffer.position, 2197 MiB`).
fn slot_label(plan: &Plan, i: usize) -> String {
    let slot = &plan.slots[i];
    let names: Vec<&str> = slot.members.iter().filter_map(|r| plan.resources.get(*r).map(|r| r.name.as_str())).collect();
    format!("slot {i}: {}, {}", names.join(" + "), crate::graph::compile::fmt_bytes(slot.bytes))
}

/// A plan instantiated on a device, ready to render frames.
pub struct Executor {
    plan: Plan,
    slots: Vec<Physical>,
    passes: Vec<PassRuntime>,
    frame_uniforms: wgpu::Buffer,
    debug_counters: wgpu::Buffer,
    scene: Option<GpuScene>,
    timer: Option<GpuTimer>,
    frame_index: u32,
    /// The acceleration-structure cache (graphs whose kept passes trace rays).
    accel: Option<AccelCache>,
    accel_generation: u64,
    /// Bounding sphere of the scene (centre, radius) this frame.
    scene_sphere: (glam::Vec3, f32),
    /// What the uploaded scene was made from (see [`Executor::sync_scene`]).
    scene_content: SceneContent,
    samplers: (wgpu::Sampler, wgpu::Sampler),
    /// Whether the warning about lights without a raster shadow map was printed.
    /// Whether the scene has alpha-tested instances: the value of the trace modules' pipeline
    /// constant TRACE_ALPHA_TEST (see [`trace_constants`]); the passes are built again when it
    /// changes.
    trace_alpha_test: bool,
    warned_unshadowed: bool,
}

impl Executor {
    /// The scene as uploaded (None when no kept pass reads it).
    pub fn uploaded_scene(&self) -> Option<&GpuScene> {
        self.scene.as_ref()
    }

    /// A part of the uploaded scene; the plan's [`crate::scene::gpu::SceneUsage`] decides what
    /// was uploaded, so a missing part is an internal inconsistency reported as an error.
    fn scene_part<T>(&self, part: impl Fn(&GpuScene) -> Option<&T>) -> Result<&T, RuntimeError> {
        self.scene.as_ref().and_then(part).ok_or_else(|| RuntimeError::Gpu("a pass binds a part of the scene that the plan did not upload".into()))
    }

    /// Allocates the plan's resources and builds its pipelines. The scene is uploaded only if
    /// the plan uses it.
    pub fn new(gpu: &Gpu, plan: Plan, scene: &Scene) -> Result<Self, RuntimeError> {
        let device = &gpu.device;
        let scope = gpu.scopes();
        let slots = plan
            .slots
            .iter()
            .enumerate()
            .map(|(i, s)| match &s.decl {
                ResourceDecl::Texture(t) => {
                    let mut usage = wgpu::TextureUsages::empty();
                    if s.usage.sampled {
                        usage |= wgpu::TextureUsages::TEXTURE_BINDING;
                    }
                    if s.usage.storage {
                        usage |= wgpu::TextureUsages::STORAGE_BINDING;
                    }
                    if s.usage.attachment {
                        usage |= wgpu::TextureUsages::RENDER_ATTACHMENT;
                    }
                    // Every texture can be read back (tests, the viewer's pass inspector).
                    usage |= wgpu::TextureUsages::COPY_SRC;
                    // The rt-pipeline back-end clears what its traces write once through wgpu
                    // (RtPass::transition).
                    if s.constant.is_some() || (s.usage.storage && plan.backend == crate::backend::Backend::RtPipeline) {
                        usage |= wgpu::TextureUsages::COPY_DST;
                    }
                    Physical::Texture(device.create_texture(&wgpu::TextureDescriptor {
                        label: Some(&slot_label(&plan, i)),
                        size: wgpu::Extent3d { width: s.extent.0, height: s.extent.1, depth_or_array_layers: 1 },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: t.format.to_wgpu(),
                        usage,
                        view_formats: &[],
                    }))
                }
                ResourceDecl::Accel => Physical::Accel,
                ResourceDecl::Buffer(b) => Physical::Buffer(device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&slot_label(&plan, i)),
                    size: b.size.max(4),
                    // The rt-pipeline back-end zeroes what its traces write once through the
                    // queue (RtPass::transition).
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_SRC
                        | if plan.backend == crate::backend::Backend::RtPipeline { wgpu::BufferUsages::COPY_DST } else { wgpu::BufferUsages::empty() },
                    mapped_at_creation: false,
                })),
            })
            .collect::<Vec<_>>();

        for (slot, physical) in plan.slots.iter().zip(&slots) {
            if let (Some(value), ResourceDecl::Texture(t), Physical::Texture(texture)) = (slot.constant, &slot.decl, physical) {
                let texel = t.format.encode_texel(value).ok_or_else(|| RuntimeError::Gpu(format!("a {:?} input cannot have a fallback value", t.format)))?;
                gpu.queue.write_texture(
                    wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
                    &texel,
                    wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(texel.len() as u32), rows_per_image: Some(1) },
                    wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                );
            }
        }
        let frame_uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let debug_counters = storage_buffer(device, "debug counters", builtins::DEBUG_COUNTER_COUNT as u64 * 4);
        let plan_uploads = plan.scene_usage.any();
        let scene_gpu = if plan_uploads {
            let s = GpuScene::upload(device, &gpu.queue, scene, plan.scene_usage)?;
            log::info!("scene `{}` uploaded ({}): {} triangles, {} bytes", scene.name, plan.scene_usage.describe(), scene.triangle_count(), s.bytes);
            Some(s)
        } else {
            log::info!("scene not uploaded: no pass of the graph uses it");
            None
        };
        let linear = device.create_sampler(&linear_sampler());
        let nearest = device.create_sampler(&nearest_sampler());

        let accel = plan.passes.iter().find(|p| p.kind == PassKind::AccelBuild).map(|p| {
            let settings = AccelSettings { dedup: p.accel.as_ref().is_none_or(|a| a.dedup), merge: p.accel.as_ref().is_some_and(|a| a.merge) };
            log::info!("acceleration structures: back-end {}, {}", plan.backend, settings.describe(plan.backend));
            let mut cache = AccelCache::new(device, plan.backend, settings, plan.passes.iter().filter(|p| p.kind == PassKind::Trace).count() as u32);
            if gpu.info.device_type != wgpu::DeviceType::Cpu {
                cache.set_merged_builder(MergedBuilder::GpuRebuilds);
            }
            cache
        });
        let mut exec = Self {
            plan,
            slots,
            passes: Vec::new(),
            frame_uniforms,
            debug_counters,
            scene: scene_gpu,
            timer: None,
            frame_index: 0,
            accel,
            accel_generation: u64::MAX,
            scene_sphere: (glam::Vec3::ZERO, 1.0),
            scene_content: if plan_uploads { SceneContent::of(scene) } else { SceneContent::default() },
            samplers: (linear, nearest),
            warned_unshadowed: false,
            trace_alpha_test: scene_has_alpha_test(scene),
        };
        exec.passes = exec.build_passes(gpu)?;
        if gpu.timestamps {
            exec.timer = Some(GpuTimer::new(device, &gpu.queue, exec.plan.passes.len() as u32));
        }
        scope.finish(gpu, "creating the graph's GPU objects")?;
        Ok(exec)
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    fn build_passes(&self, gpu: &Gpu) -> Result<Vec<PassRuntime>, RuntimeError> {
        self.plan.passes.iter().map(|pass| self.build_pass(gpu, pass, &self.samplers.0, &self.samplers.1)).collect()
    }

    /// Keeps the uploaded scene equal to `scene`: moved instances are rewritten in place; any
    /// other change (meshes, materials, textures, instances added or removed) uploads the scene
    /// again and rebuilds the passes that bind it. Nothing to do for graphs that upload none.
    fn sync_scene(&mut self, gpu: &Gpu, scene: &Scene) -> Result<(), RuntimeError> {
        let alpha_test = scene_has_alpha_test(scene);
        if alpha_test != self.trace_alpha_test {
            self.trace_alpha_test = alpha_test;
            self.passes = self.build_passes(gpu)?;
            self.accel_generation = u64::MAX;
        }
        let Some(uploaded) = &self.scene else { return Ok(()) };
        let content = SceneContent::of(scene);
        if content == self.scene_content {
            return Ok(());
        }
        if content.structure == self.scene_content.structure && uploaded.write_instances(&gpu.queue, scene) {
            self.scene_content = content;
            return Ok(());
        }
        let scope = gpu.scopes();
        self.scene = Some(GpuScene::upload(&gpu.device, &gpu.queue, scene, self.plan.scene_usage)?);
        self.passes = self.build_passes(gpu)?;
        // The new passes have no accel bind group yet: make the next update re-create them.
        self.accel_generation = u64::MAX;
        scope.finish(gpu, "uploading the changed scene")?;
        log::info!("scene `{}` changed: uploaded again ({} bytes)", scene.name, self.scene.as_ref().map_or(0, |s| s.bytes));
        self.scene_content = content;
        Ok(())
    }

    fn texture_view(&self, r: ResourceId) -> wgpu::TextureView {
        match &self.slots[self.plan.resources[r].slot.expect("kept resource has a slot")] {
            Physical::Texture(t) => t.create_view(&wgpu::TextureViewDescriptor::default()),
            Physical::Buffer(_) | Physical::Accel => unreachable!("texture resource mapped to a buffer slot"),
        }
    }

    fn slot_texture(&self, r: ResourceId) -> &wgpu::Texture {
        match &self.slots[self.plan.resources[r].slot.expect("kept resource has a slot")] {
            Physical::Texture(t) => t,
            Physical::Buffer(_) | Physical::Accel => unreachable!("texture resource mapped to a buffer slot"),
        }
    }

    fn buffer(&self, r: ResourceId) -> &wgpu::Buffer {
        match &self.slots[self.plan.resources[r].slot.expect("kept resource has a slot")] {
            Physical::Buffer(b) => b,
            Physical::Texture(_) | Physical::Accel => unreachable!("buffer resource mapped to a texture slot"),
        }
    }

    fn build_pass(&self, gpu: &Gpu, pass: &PlannedPass, linear: &wgpu::Sampler, nearest: &wgpu::Sampler) -> Result<PassRuntime, RuntimeError> {
        let device = &gpu.device;
        let shader = &pass.shader;
        if pass.kind == PassKind::AccelBuild {
            return Ok(PassRuntime {
                pipeline: Pipeline::AccelBuild,
                bind_groups: Vec::new(),
                accel_layout: None,
                accel_group: None,
                colors: Vec::new(),
                depth: None,
                groups: [0; 3],
                params: None,
            });
        }
        let visibility = if pass.kind.is_compute() { wgpu::ShaderStages::COMPUTE } else { wgpu::ShaderStages::VERTEX_FRAGMENT };
        let resource_of = |name: &str| pass.reads.iter().chain(&pass.writes).find(|(l, _)| l == name).map(|(_, r)| *r);

        // Layout entries and resources, from reflection.
        let mut layout_entries = Vec::new();
        let mut views: Vec<((u32, u32), wgpu::TextureView)> = Vec::new();
        let mut view_arrays: Vec<((u32, u32), Vec<wgpu::TextureView>)> = Vec::new();
        let mut buffers: Vec<((u32, u32), wgpu::Buffer)> = Vec::new();
        let mut params_buffer: Option<((u32, u32), wgpu::Buffer)> = None;
        let mut params_members = None;
        for b in &shader.bindings {
            let ty = match &b.kind {
                BindingKind::SampledTexture { arrayed, kind, .. } => {
                    let filterable = match resource_of(&b.name) {
                        Some(r) => matches!(&self.plan.resources[r].decl, ResourceDecl::Texture(t) if t.format.is_filterable()),
                        None => true,
                    };
                    wgpu::BindingType::Texture {
                        sample_type: match kind {
                            naga::ScalarKind::Uint => wgpu::TextureSampleType::Uint,
                            naga::ScalarKind::Sint => wgpu::TextureSampleType::Sint,
                            _ => wgpu::TextureSampleType::Float { filterable },
                        },
                        view_dimension: if *arrayed { wgpu::TextureViewDimension::D2Array } else { wgpu::TextureViewDimension::D2 },
                        multisampled: false,
                    }
                }
                BindingKind::TextureBindingArray => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                BindingKind::AccelerationStructure => wgpu::BindingType::AccelerationStructure { vertex_return: false },
                BindingKind::DepthTexture => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                BindingKind::StorageTexture { access, .. } => {
                    let r = resource_of(&b.name).expect("checked by the compiler");
                    let ResourceDecl::Texture(t) = &self.plan.resources[r].decl else { unreachable!() };
                    let load = access.contains(naga::StorageAccess::LOAD);
                    wgpu::BindingType::StorageTexture {
                        access: if load { wgpu::StorageTextureAccess::ReadWrite } else { wgpu::StorageTextureAccess::WriteOnly },
                        format: t.format.to_wgpu(),
                        view_dimension: wgpu::TextureViewDimension::D2,
                    }
                }
                BindingKind::Sampler { comparison } => wgpu::BindingType::Sampler(if *comparison {
                    wgpu::SamplerBindingType::Comparison
                } else if b.name == builtins::NEAREST_SAMPLER {
                    wgpu::SamplerBindingType::NonFiltering
                } else {
                    wgpu::SamplerBindingType::Filtering
                }),
                BindingKind::Uniform { .. } => {
                    wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None }
                }
                BindingKind::Storage { read_only, .. } => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: *read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                BindingKind::Other(what) => {
                    return Err(
                        GraphError::new(ErrorKind::Unsupported, b.location.clone(), format!("binding `{}` of kind {what} is not supported", b.name)).into()
                    );
                }
            };
            let count = match b.kind {
                BindingKind::TextureBindingArray => {
                    Some(std::num::NonZeroU32::new(self.scene_part(|s| s.textures.as_ref())?.count()).expect("white texture is always there"))
                }
                _ => None,
            };
            layout_entries.push((b.group, wgpu::BindGroupLayoutEntry { binding: b.binding, visibility, ty, count }));

            if let Some(r) = resource_of(&b.name) {
                match &self.plan.resources[r].decl {
                    ResourceDecl::Texture(_) => views.push(((b.group, b.binding), self.texture_view(r))),
                    ResourceDecl::Buffer(_) => buffers.push(((b.group, b.binding), self.buffer(r).clone())),
                    ResourceDecl::Accel => {} // bound through the trace module's group
                }
                continue;
            }
            match b.name.as_str() {
                builtins::FRAME => buffers.push(((b.group, b.binding), self.frame_uniforms.clone())),
                builtins::DEBUG_COUNTERS => buffers.push(((b.group, b.binding), self.debug_counters.clone())),
                builtins::PARAMS => {
                    let BindingKind::Uniform { size, members, .. } = &b.kind else { unreachable!() };
                    let bytes = encode_params(&pass.params, members, *size as u64);
                    params_members = Some((*size as u64, members.clone()));
                    let buf = wgpu::util::DeviceExt::create_buffer_init(
                        device,
                        &wgpu::util::BufferInitDescriptor {
                            label: Some(&format!("{} params", pass.name)),
                            contents: &bytes,
                            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        },
                    );
                    params_buffer = Some(((b.group, b.binding), buf));
                }
                builtins::SCENE_INSTANCES => buffers.push(((b.group, b.binding), self.scene_part(|s| s.instances.as_ref())?.clone())),
                builtins::SCENE_MATERIALS => buffers.push(((b.group, b.binding), self.scene_part(|s| s.materials.as_ref())?.clone())),
                builtins::SCENE_VERTICES => buffers.push(((b.group, b.binding), self.scene_part(|s| s.vertices.as_ref())?.clone())),
                builtins::SCENE_INDICES => buffers.push(((b.group, b.binding), self.scene_part(|s| s.indices.as_ref())?.clone())),
                builtins::SCENE_MESHES => buffers.push(((b.group, b.binding), self.scene_part(|s| s.meshes.as_ref())?.clone())),
                builtins::SCENE_LIGHTS => buffers.push(((b.group, b.binding), self.scene_part(|s| s.lights.as_ref())?.clone())),
                builtins::SCENE_TEXTURES => match self.scene_part(|s| s.textures.as_ref())? {
                    SceneTextures::Array { view, .. } if b.kind != BindingKind::TextureBindingArray => views.push(((b.group, b.binding), view.clone())),
                    SceneTextures::Separate { views: v, .. } if b.kind == BindingKind::TextureBindingArray => {
                        view_arrays.push(((b.group, b.binding), v.clone()))
                    }
                    _ => return Err(RuntimeError::Gpu(format!("pass {}: scene textures were uploaded in the other layout than the shader binds", pass.name))),
                },
                _ => {}
            }
        }
        if pass.kind == PassKind::Trace && self.plan.backend == crate::backend::Backend::RtPipeline {
            return self.build_rt_pass(gpu, pass, &layout_entries, params_buffer, params_members);
        }
        // One bind group per @group the shader uses (group 1 holds the scene's texture binding
        // array, which may not share a group with uniform buffers).
        let group_count = shader.bindings.iter().map(|b| b.group + 1).max().unwrap_or(0);
        let view_refs: Vec<((u32, u32), Vec<&wgpu::TextureView>)> = view_arrays.iter().map(|(k, v)| (*k, v.iter().collect())).collect();
        let mut entries: Vec<((u32, u32), wgpu::BindingResource)> = Vec::new();
        entries.extend(view_refs.iter().map(|(k, a)| (*k, wgpu::BindingResource::TextureViewArray(a))));
        entries.extend(views.iter().map(|(k, v)| (*k, wgpu::BindingResource::TextureView(v))));
        entries.extend(buffers.iter().chain(params_buffer.iter()).map(|(k, buf)| (*k, buf.as_entire_binding())));
        for b in &shader.bindings {
            match b.name.as_str() {
                builtins::LINEAR_SAMPLER => entries.push(((b.group, b.binding), wgpu::BindingResource::Sampler(linear))),
                builtins::NEAREST_SAMPLER => entries.push(((b.group, b.binding), wgpu::BindingResource::Sampler(nearest))),
                _ => {}
            }
        }
        let mut layouts = Vec::new();
        let mut bind_groups = Vec::new();
        let mut accel_layout = None;
        for g in 0..group_count {
            let layout_g: Vec<wgpu::BindGroupLayoutEntry> = layout_entries.iter().filter(|(lg, _)| *lg == g).map(|(_, e)| *e).collect();
            let bgl =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(&format!("{} group {g}", pass.name)), entries: &layout_g });
            if pass.kind == PassKind::Trace && g == builtins::ACCEL_GROUP {
                // Bound per frame from the acceleration-structure cache.
                let names = layout_g
                    .iter()
                    .map(|e| shader.bindings.iter().find(|b| b.group == g && b.binding == e.binding).map(|b| b.name.clone()).unwrap_or_default())
                    .collect();
                accel_layout = Some((bgl.clone(), layout_g, names));
            } else {
                let entries_g: Vec<wgpu::BindGroupEntry> = entries
                    .iter()
                    .filter(|((eg, _), _)| *eg == g)
                    .map(|((_, binding), r)| wgpu::BindGroupEntry { binding: *binding, resource: r.clone() })
                    .collect();
                bind_groups.push(device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("{} group {g}", pass.name)),
                    layout: &bgl,
                    entries: &entries_g,
                }));
            }
            layouts.push(bgl);
        }
        let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some(&pass.name), bind_group_layouts: &layout_refs, immediate_size: 0 });
        // A layer's shader: a project file, with every runtime check (`ShaderOrigin::Project`),
        // but a trace pass's module, built on the project's traversal (`ShaderOrigin::TracePass`).
        let origin = if pass.kind == PassKind::Trace { crate::gpu_util::ShaderOrigin::TracePass } else { crate::gpu_util::ShaderOrigin::Project };
        let module = gpu.shader_module(&shader.path.display().to_string(), &shader.source.text, origin);

        let colors: Vec<ResourceId> = pass.writes.iter().map(|(_, r)| *r).filter(|r| !self.is_depth(*r)).collect();
        let depth = pass.writes.iter().map(|(_, r)| *r).find(|r| self.is_depth(*r));
        let (pipeline, groups) = match pass.kind {
            PassKind::AccelBuild => unreachable!("returned above"),
            PassKind::Compute | PassKind::Trace => {
                let constants = trace_constants(pass, self.trace_alpha_test);
                let p = compute_pipeline_with(device, &pass.name, &layout, &module, &pass.entry, &constants);
                let groups = match pass.dispatch {
                    Dispatch::Groups(x, y, z) => [x, y, z],
                    Dispatch::PerPixel => {
                        let extent = self.per_pixel_extent(pass);
                        let wg = pass.shader.entry(&pass.entry).map(|e| e.workgroup_size).unwrap_or([1, 1, 1]);
                        [extent.0.div_ceil(wg[0].max(1)), extent.1.div_ceil(wg[1].max(1)), 1]
                    }
                };
                (Pipeline::Compute(p), groups)
            }
            PassKind::Fullscreen | PassKind::SceneRaster => {
                let targets: Vec<Option<wgpu::ColorTargetState>> = colors
                    .iter()
                    .map(|r| match &self.plan.resources[*r].decl {
                        ResourceDecl::Texture(t) => {
                            Some(wgpu::ColorTargetState { format: t.format.to_wgpu(), blend: None, write_mask: wgpu::ColorWrites::ALL })
                        }
                        ResourceDecl::Buffer(_) | ResourceDecl::Accel => None,
                    })
                    .collect();
                let scene_raster = pass.kind == PassKind::SceneRaster;
                let spec = RenderSpec {
                    label: pass.name.clone(),
                    layout,
                    module,
                    vertex_entry: pass.vertex_entry.clone(),
                    fragment_entry: pass.entry.clone(),
                    targets,
                    scene_attributes: scene_raster.then(|| scene_vertex_attributes(pass)),
                    depth: depth.is_some(),
                    alpha_switch: shader.has_override(super::raster::ALPHA_TEST_CONSTANT),
                };
                if scene_raster {
                    (Pipeline::Scene(ScenePipelines::new(spec, pass.cull_back_faces)), [0, 0, 0])
                } else {
                    (Pipeline::Render(spec.create(device, DrawClass::FULLSCREEN)), [0, 0, 0])
                }
            }
        };
        let params = params_buffer.as_ref().zip(params_members).map(|((_, buf), (size, members))| (buf.clone(), size, members));
        Ok(PassRuntime { pipeline, bind_groups, accel_layout, accel_group: None, colors, depth, groups, params })
    }

    /// A trace pass on the rt-pipeline back-end: the same bindings as the compute pass would
    /// have, bound through hal bind groups of a ray-tracing pipeline.
    fn build_rt_pass(
        &self,
        gpu: &Gpu,
        pass: &PlannedPass,
        layout_entries: &[(u32, wgpu::BindGroupLayoutEntry)],
        params_buffer: Option<((u32, u32), wgpu::Buffer)>,
        params_members: Option<(u64, Vec<crate::graph::reflect::UniformMember>)>,
    ) -> Result<PassRuntime, RuntimeError> {
        let shader = &pass.shader;
        let module = shader
            .ray_tracing
            .as_ref()
            .ok_or_else(|| RuntimeError::Gpu(format!("pass {}: the shader was not compiled with the rt-pipeline trace module", pass.name)))?;
        let resource_of = |name: &str| pass.reads.iter().chain(&pass.writes).find(|(l, _)| l == name).map(|(_, r)| *r);
        let mut bindings = Vec::new();
        for b in &shader.bindings {
            let Some(entry) = layout_entries.iter().find(|(g, e)| *g == b.group && e.binding == b.binding).map(|(_, e)| *e) else { continue };
            let buffer =
                |buffer: &wgpu::Buffer| RtResource::Buffer { buffer: buffer.clone(), offset: 0, size: None, uses: buffer_uses(&b.kind), initialize: false };
            let resource = if let Some(r) = resource_of(&b.name) {
                match &self.plan.resources[r].decl {
                    ResourceDecl::Texture(_) => {
                        RtResource::Texture { texture: self.slot_texture(r).clone(), view: self.texture_view(r), uses: texture_uses(&b.kind) }
                    }
                    ResourceDecl::Buffer(_) => RtResource::Buffer {
                        buffer: self.buffer(r).clone(),
                        offset: 0,
                        size: None,
                        uses: buffer_uses(&b.kind),
                        initialize: pass.writes.iter().any(|(_, w)| *w == r),
                    },
                    ResourceDecl::Accel => continue,
                }
            } else if b.group == builtins::ACCEL_GROUP {
                RtResource::Accel(b.name.clone())
            } else {
                match b.name.as_str() {
                    builtins::FRAME => buffer(&self.frame_uniforms),
                    builtins::DEBUG_COUNTERS => buffer(&self.debug_counters),
                    builtins::PARAMS => buffer(&params_buffer.as_ref().expect("made for the params binding").1),
                    builtins::SCENE_INSTANCES => buffer(self.scene_part(|s| s.instances.as_ref())?),
                    builtins::SCENE_MATERIALS => buffer(self.scene_part(|s| s.materials.as_ref())?),
                    builtins::SCENE_VERTICES => buffer(self.scene_part(|s| s.vertices.as_ref())?),
                    builtins::SCENE_INDICES => buffer(self.scene_part(|s| s.indices.as_ref())?),
                    builtins::SCENE_MESHES => buffer(self.scene_part(|s| s.meshes.as_ref())?),
                    builtins::SCENE_LIGHTS => buffer(self.scene_part(|s| s.lights.as_ref())?),
                    builtins::SCENE_TEXTURES => match self.scene_part(|s| s.textures.as_ref())? {
                        SceneTextures::Array { texture, view } => {
                            RtResource::Texture { texture: texture.clone(), view: view.clone(), uses: wgpu::TextureUses::RESOURCE }
                        }
                        SceneTextures::Separate { textures, views } => RtResource::Textures(textures.iter().cloned().zip(views.iter().cloned()).collect()),
                    },
                    builtins::LINEAR_SAMPLER => RtResource::Sampler(linear_sampler()),
                    builtins::NEAREST_SAMPLER => RtResource::Sampler(nearest_sampler()),
                    other => return Err(RuntimeError::Gpu(format!("pass {}: binding `{other}` has no resource", pass.name))),
                }
            };
            bindings.push(RtBinding { group: b.group, entry, resource });
        }
        let rt = RtPass::new(&gpu.device, &gpu.queue, &pass.name, module, &pass.entry, bindings, builtins::ACCEL_GROUP)?;
        let wg = shader.entry(&pass.entry).map(|e| e.workgroup_size).unwrap_or([1, 1, 1]);
        // The launch grid: one ray-generation invocation per invocation of the compute dispatch.
        let launch = match pass.dispatch {
            Dispatch::Groups(x, y, z) => [x * wg[0].max(1), y * wg[1].max(1), z * wg[2].max(1)],
            Dispatch::PerPixel => {
                let extent = self.per_pixel_extent(pass);
                [extent.0, extent.1, 1]
            }
        };
        let params = params_buffer.as_ref().zip(params_members).map(|((_, buf), (size, members))| (buf.clone(), size, members));
        Ok(PassRuntime {
            pipeline: Pipeline::RayTracing(Box::new(rt)),
            bind_groups: Vec::new(),
            accel_layout: None,
            accel_group: None,
            colors: Vec::new(),
            depth: None,
            groups: launch,
            params,
        })
    }

    /// The pixels a `PerPixel` pass covers: its first written texture, else the frame.
    /// Records a fullscreen or scene raster pass: a scene pass draws every instance with the
    /// pipeline variant of its draw class, the variants in their fixed order, each class's draws
    /// in `draw_order` (front to back).
    #[allow(clippy::too_many_arguments)]
    fn record_raster(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        index: usize,
        pass: &PassRuntime,
        planned: &PlannedPass,
        color_views: &[wgpu::TextureView],
        depth_view: Option<&wgpu::TextureView>,
        instance_classes: &[InstanceClass],
        draw_order: &[usize],
    ) -> Result<(), RuntimeError> {
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
            label: Some(&planned.name),
            color_attachments: &attachments,
            depth_stencil_attachment: depth_view.map(|v| wgpu::RenderPassDepthStencilAttachment {
                view: v,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: self.timer.as_ref().and_then(|t| t.render_writes(index as u32)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for (g, bg) in pass.bind_groups.iter().enumerate() {
            rp.set_bind_group(g as u32, bg, &[]);
        }
        let pipelines = match &pass.pipeline {
            Pipeline::Render(pipeline) => {
                rp.set_pipeline(pipeline);
                rp.draw(0..3, 0..1);
                return Ok(());
            }
            Pipeline::Scene(pipelines) => pipelines,
            _ => unreachable!("record_raster is called for raster passes"),
        };
        let (Some(scene), Some(vertices), Some(indices)) =
            (self.scene.as_ref(), self.scene_part(|s| s.vertices.as_ref()).ok(), self.scene_part(|s| s.indices.as_ref()).ok())
        else {
            return Err(RuntimeError::Gpu(format!("pass {} draws the scene, but its geometry was not uploaded", planned.name)));
        };
        rp.set_vertex_buffer(0, vertices.slice(..));
        rp.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        let classes = pipelines.classes(instance_classes);
        for (class, pipeline) in pipelines.variants() {
            let mut draws = draw_order.iter().filter_map(|&k| scene.draws.get(k)).filter(|d| classes.get(d.instance as usize) == Some(&class)).peekable();
            if draws.peek().is_none() {
                continue;
            }
            rp.set_pipeline(pipeline);
            for d in draws {
                rp.draw_indexed(d.indices.clone(), d.base_vertex, d.instance..d.instance + 1);
            }
        }
        Ok(())
    }

    fn per_pixel_extent(&self, pass: &PlannedPass) -> (u32, u32) {
        pass.writes
            .iter()
            .find(|(_, r)| matches!(self.plan.resources[*r].decl, ResourceDecl::Texture(_)))
            .map(|(_, r)| self.plan.resources[*r].extent)
            .unwrap_or(self.plan.frame_size)
    }

    fn is_depth(&self, r: ResourceId) -> bool {
        self.plan.resources[r].decl.is_depth_texture()
    }

    /// Whether a kept pass draws a shadow map (a `SceneRaster` pass that writes only depth).
    fn draws_shadow_maps(&self) -> bool {
        self.plan.passes.iter().any(|p| p.kind == PassKind::SceneRaster && p.writes.iter().all(|(_, r)| self.is_depth(*r)))
    }

    /// The frame uniforms; writes the scene's light records when the plan reads them.
    fn frame_uniforms(&mut self, gpu: &Gpu, camera: &Camera, scene: &Scene) -> Result<FrameUniforms, RuntimeError> {
        let (w, h) = self.plan.frame_size;
        let vp = camera.view_proj(w as f32 / h as f32);
        let (center, radius) = self.scene_sphere;
        let lights = light_records(&scene.effective_lights(), center, radius);
        let mut shadow_view_proj = [[[0.0; 4]; 4]; SHADOW_MAP_SLOTS];
        for (slot, m) in shadow_view_proj.iter_mut().zip(&lights.shadow_view_proj) {
            *slot = m.to_cols_array_2d();
        }
        if let Some(uploaded) = self.scene.as_ref().filter(|s| s.lights.is_some()) {
            if !uploaded.write_lights(&gpu.queue, &lights.records) {
                return Err(RuntimeError::Gpu("the light buffer does not match the scene's lights".into()));
            }
            if !self.warned_unshadowed && lights.unshadowed_in_raster > 0 && self.draws_shadow_maps() {
                self.warned_unshadowed = true;
                eprintln!(
                    "warning: lights without a shadow map in raster mode: {} of {} (point lights, and directional or spot lights after the first {SHADOW_MAP_SLOTS}); they light the scene unshadowed",
                    lights.unshadowed_in_raster,
                    lights.records.len()
                );
            }
        }
        Ok(FrameUniforms {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            camera_pos: camera.position.extend(1.0).into(),
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            scene_sphere: center.extend(radius).into(),
            shadow_view_proj,
            ambient: scene.light.ambient,
            light_count: lights.records.len() as u32,
            shadow_count: lights.shadow_view_proj.len() as u32,
            frame_index: self.frame_index,
        })
    }

    /// Records and submits one frame; waits for it and returns its pass timings.
    pub fn render(&mut self, gpu: &Gpu, camera: &Camera, scene: &Scene) -> Result<FrameTimings, RuntimeError> {
        let start = Instant::now();
        if gpu.inject_device_loss_at == Some(self.frame_index) {
            log::warn!("RAYGRAPH_INJECT_DEVICE_LOSS: destroying the device at frame {}", self.frame_index);
            gpu.device.destroy();
        }
        gpu.check()?;
        self.sync_scene(gpu, scene)?;
        // Every frame: the scene may have changed since the last one.
        let b = scene.bounds();
        self.scene_sphere = if b.is_empty() { (glam::Vec3::ZERO, 1.0) } else { (b.center(), (0.5 * b.diagonal()).max(1e-6)) };
        let uniforms = self.frame_uniforms(gpu, camera, scene)?;
        gpu.queue.write_buffer(&self.frame_uniforms, 0, bytemuck::bytes_of(&uniforms));
        let scope = gpu.scopes();
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        // Command buffers before `encoder`'s, in submission order (rt-pipeline passes record
        // into command buffers of their own).
        let mut command_buffers = Vec::new();
        let mut cpu_ms = Vec::with_capacity(self.passes.len());
        // The acceleration structure is updated where the schedule puts its `Accel` node
        // (before every trace pass, which all read it), between that pass's timestamps.
        let mut accel_report = None;
        let instance_classes = InstanceClass::of_scene(scene);
        let draw_order = self.scene.as_ref().map(|s| super::raster::front_to_back(&s.draws, scene, camera.position)).unwrap_or_default();
        for pass in &mut self.passes {
            if let Pipeline::Scene(pipelines) = &mut pass.pipeline {
                pipelines.prepare(&gpu.device, &pipelines.classes(&instance_classes));
            }
        }
        let views: Vec<(Vec<wgpu::TextureView>, Option<wgpu::TextureView>)> =
            self.passes.iter().map(|p| (p.colors.iter().map(|r| self.texture_view(*r)).collect(), p.depth.map(|r| self.texture_view(r)))).collect();
        for i in 0..self.passes.len() {
            let t0 = Instant::now();
            if matches!(self.passes[i].pipeline, Pipeline::AccelBuild) {
                accel_report = self.update_accel(gpu, &mut encoder, &mut command_buffers, scene)?;
                cpu_ms.push(accel_report.as_ref().map(|(_, ms)| *ms).unwrap_or(0.0));
                continue;
            }
            let (pass, planned) = (&self.passes[i], &self.plan.passes[i]);
            if planned.shadow_slot.is_some_and(|slot| slot >= uniforms.shadow_count) {
                // A shadow map no light uses this frame: not drawn; an empty pass keeps the
                // timestamp pair (0 ms).
                if let Some(t) = &self.timer {
                    drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(&planned.name), timestamp_writes: t.compute_writes(i as u32) }));
                }
                cpu_ms.push(0.0);
                continue;
            }
            match &pass.pipeline {
                Pipeline::AccelBuild => unreachable!("recorded above"),
                Pipeline::RayTracing(rt) => {
                    let cache = self.accel.as_ref().ok_or_else(|| RuntimeError::Gpu(format!("pass {} traces rays without an Accel node", planned.name)))?;
                    rt.transition(&mut encoder, cache.stats_window(0).0);
                    if let Some(t) = &self.timer {
                        drop(
                            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("trace begin"), timestamp_writes: t.begin_writes(i as u32) }),
                        );
                    }
                    let next = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
                    command_buffers.push(std::mem::replace(&mut encoder, next).finish());
                    command_buffers.push(rt.record(pass.groups)?);
                    if let Some(t) = &self.timer {
                        drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("trace end"), timestamp_writes: t.end_writes(i as u32) }));
                    }
                }
                Pipeline::Compute(pipeline) => {
                    let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(&planned.name),
                        timestamp_writes: self.timer.as_ref().and_then(|t| t.compute_writes(i as u32)),
                    });
                    cp.set_pipeline(pipeline);
                    for (g, bg) in pass.bind_groups.iter().enumerate() {
                        cp.set_bind_group(g as u32, bg, &[]);
                    }
                    if let Some(bg) = &pass.accel_group {
                        cp.set_bind_group(builtins::ACCEL_GROUP, bg, &[]);
                    }
                    cp.dispatch_workgroups(pass.groups[0], pass.groups[1], pass.groups[2]);
                }
                Pipeline::Render(_) | Pipeline::Scene(_) => {
                    let (color_views, depth_view) = &views[i];
                    self.record_raster(&mut encoder, i, pass, planned, color_views, depth_view.as_ref(), &instance_classes, &draw_order)?;
                }
            }
            cpu_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        if let Some(timer) = &self.timer {
            timer.resolve(&mut encoder, self.passes.len() as u32);
        }
        if let Some(cache) = &self.accel {
            cache.copy_stats(&mut encoder);
        }
        command_buffers.push(encoder.finish());
        gpu.queue.submit(command_buffers);
        scope.finish(gpu, "recording the frame")?;
        if let Err(e) = gpu.wait_for(|| self.frame_work()) {
            // The frame's views may still be in use by work past the GPU deadline: releasing
            // them can block in the driver.
            std::mem::forget(views);
            return Err(e);
        }
        let gpu_ms = match &self.timer {
            Some(t) => Some(t.read(&gpu.device, self.passes.len() as u32)?),
            None => None,
        };
        // Ray counters: one window per trace pass, in schedule order.
        let mut pass_rays = vec![None; self.plan.passes.len()];
        let mut rays = None;
        if let Some(cache) = &self.accel {
            let windows = cache.read_stats(&gpu.device)?;
            let trace_passes = self.plan.passes.iter().enumerate().filter(|(_, p)| p.kind == PassKind::Trace).map(|(i, _)| i);
            for (i, stats) in trace_passes.zip(&windows) {
                pass_rays[i] = Some(*stats);
            }
            rays = Some(windows.iter().fold(crate::accel::cache::RayStats::default(), |a, b| a.add(b)));
        }
        self.frame_index += 1;
        Ok(FrameTimings { gpu_ms, cpu_ms, frame_ms: start.elapsed().as_secs_f64() * 1e3, rays, pass_rays, accel: accel_report.map(|(r, _)| r) })
    }

    /// The work one frame submits, for the GPU deadline's error: its passes in submission
    /// order with their layer and WGSL files. They are submitted together, so any of them may
    /// be the one that did not end.
    fn frame_work(&self) -> String {
        let passes: Vec<String> = self
            .plan
            .passes
            .iter()
            .filter(|p| p.kind != PassKind::AccelBuild)
            .map(|p| format!("`{}` ({}, {})", p.name, p.location.file.display(), p.shader.path.display()))
            .collect();
        match passes.as_slice() {
            [one] => format!("frame {}, pass {one}", self.frame_index),
            _ => format!("frame {}: one of its passes did not end; they were submitted together: {}", self.frame_index, passes.join(", ")),
        }
    }

    /// Runs the `Accel` node: clears the ray counters, updates the cache between a pair of
    /// timestamps, and re-creates the trace passes' accel bind groups if the cache replaced
    /// its GPU objects. Returns the build report and its CPU milliseconds.
    fn update_accel(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        command_buffers: &mut Vec<wgpu::CommandBuffer>,
        scene: &Scene,
    ) -> Result<Option<(crate::accel::cache::BuildReport, f64)>, RuntimeError> {
        let Some(cache) = self.accel.as_mut() else { return Ok(None) };
        let index = self.plan.passes.iter().position(|p| p.kind == PassKind::AccelBuild).unwrap_or(0) as u32;
        cache.clear_stats(encoder);
        if let Some(t) = &self.timer {
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("accel begin"), timestamp_writes: t.begin_writes(index) }));
        }
        let t0 = Instant::now();
        let report = cache.update(&gpu.device, &gpu.queue, encoder, scene)?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        // The rt-pipeline back-end's build, recorded through wgpu-hal: submitted between the
        // node's timestamps, before every trace.
        if let Some(build) = cache.take_pending() {
            let next = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
            command_buffers.push(std::mem::replace(encoder, next).finish());
            command_buffers.push(build);
        }
        if let Some(t) = &self.timer {
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("accel end"), timestamp_writes: t.end_writes(index) }));
        }
        if cache.generation() != self.accel_generation {
            let generation = cache.generation();
            let cache = self.accel.as_ref().expect("checked above");
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
                    let resource = cache
                        .binding(name, window as u32)
                        .ok_or_else(|| RuntimeError::Gpu(format!("the {} back-end has no binding `{name}`", cache.backend())))?;
                    bg_entries.push(wgpu::BindGroupEntry { binding: e.binding, resource });
                }
                pass.accel_group = Some(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("accel"), layout, entries: &bg_entries }));
            }
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

    /// Changes parameter `name` of node `node` in the running plan: the value is checked against
    /// its declaration and written into the `params` uniform of every pass of the node, ready
    /// for the next frame. `Ok(false)`: the plan must be compiled again with the value, because
    /// the parameter is read when an executor is made (the `Accel` node's settings) or no kept
    /// pass has it (the node's passes are culled; the compiler checks the name then).
    pub fn set_param(&mut self, gpu: &Gpu, node: &str, name: &str, value: ParamValue) -> Result<bool, String> {
        // Checked on every pass first, so that nothing is written when a compile is needed.
        let mut found = false;
        for pass in self.plan.passes.iter().filter(|p| p.node == node) {
            let Some((decl, _)) = pass.params.get(name) else { continue };
            crate::graph::compile::check_param(decl, value).map_err(|(_, msg, help)| format!("parameter `{name}` of node `{node}`: {msg} ({help})"))?;
            if pass.kind == PassKind::AccelBuild {
                return Ok(false);
            }
            found = true;
        }
        if !found {
            return Ok(false);
        }
        for (i, pass) in self.plan.passes.iter_mut().enumerate() {
            if pass.node != node {
                continue;
            }
            let Some((decl, current)) = pass.params.get_mut(name) else { continue };
            *current = crate::graph::compile::check_param(decl, value).map_err(|(_, msg, _)| msg)?;
            if let Some((buf, size, members)) = &self.passes[i].params {
                gpu.queue.write_buffer(buf, 0, &encode_params(&pass.params, members, *size));
            }
        }
        Ok(true)
    }

    /// The texture a kept texture resource lives in (shared with the resources of its slot).
    pub fn texture(&self, r: ResourceId) -> Option<&wgpu::Texture> {
        match self.plan.resources.get(r)?.slot.and_then(|s| self.slots.get(s))? {
            Physical::Texture(t) => Some(t),
            _ => None,
        }
    }

    /// Reads back the graph output as tightly packed RGBA8 rows.
    pub fn read_output(&self, gpu: &Gpu) -> Result<image::RgbaImage, RuntimeError> {
        self.read_texture_rgba8(gpu, self.plan.output)
    }

    /// Reads back any kept RGBA8 texture resource.
    pub fn read_texture_rgba8(&self, gpu: &Gpu, r: ResourceId) -> Result<image::RgbaImage, RuntimeError> {
        let (w, h, format, data) = self.read_texture_bytes(gpu, r)?;
        if format.bytes_per_texel() != 4 || format.is_uint() {
            return Err(RuntimeError::Gpu(format!("{} is {format:?}, not an 8-bit RGBA texture", self.plan.resources[r].name)));
        }
        image::RgbaImage::from_raw(w, h, data).ok_or_else(|| RuntimeError::Gpu("readback size mismatch".into()))
    }

    /// Reads back any kept colour texture as RGBA f32 per texel (row-major; missing channels
    /// 0, alpha 1); float, half and 8-bit unorm formats.
    pub fn read_texture_f32(&self, gpu: &Gpu, r: ResourceId) -> Result<(u32, u32, Vec<[f32; 4]>), RuntimeError> {
        let (w, h, format, data) = self.read_texture_bytes(gpu, r)?;
        use crate::graph::desc::TexelKind;
        if format.is_uint() {
            return Err(RuntimeError::Gpu(format!("{format:?} is not a float format")));
        }
        let (channels, kind) = format.texel_layout();
        let size = kind.bytes();
        let texel = channels * size;
        let texels = data
            .chunks_exact(texel)
            .map(|t| {
                let mut v = [0.0, 0.0, 0.0, 1.0];
                for (c, b) in t.chunks_exact(size).enumerate() {
                    v[c] = match kind {
                        TexelKind::Unorm8 => b[0] as f32 / 255.0,
                        TexelKind::Float16 => crate::graph::desc::f16_to_f32(u16::from_le_bytes([b[0], b[1]])),
                        TexelKind::Float32 | TexelKind::Uint32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                    };
                }
                v
            })
            .collect();
        Ok((w, h, texels))
    }

    /// A kept texture's texels, tightly packed rows.
    fn read_texture_bytes(&self, gpu: &Gpu, r: ResourceId) -> Result<(u32, u32, crate::graph::desc::Format, Vec<u8>), RuntimeError> {
        let (w, h) = self.plan.resources[r].extent;
        let ResourceDecl::Texture(t) = &self.plan.resources[r].decl else {
            return Err(RuntimeError::Gpu(format!("{} is not a texture", self.plan.resources[r].name)));
        };
        let Physical::Texture(texture) = &self.slots[self.plan.resources[r].slot.ok_or_else(|| RuntimeError::Gpu("resource is not allocated".into()))?] else {
            return Err(RuntimeError::Gpu("resource is not a texture".into()));
        };
        Ok((w, h, t.format, read_texture(gpu, texture, t.format.bytes_per_texel() as u32)?))
    }

    /// Reads the `debug_counters` buffer (shaders may count events into it).
    pub fn read_debug_counters(&self, gpu: &Gpu) -> Result<Vec<u32>, RuntimeError> {
        let size = builtins::DEBUG_COUNTER_COUNT as u64 * 4;
        let buf = readback_buffer(&gpu.device, "counter readback", size);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.debug_counters, 0, &buf, 0, size);
        gpu.queue.submit([encoder.finish()]);
        let data = map_read(&gpu.device, buf.slice(..))?;
        let v = bytemuck::cast_slice::<u8, u32>(&data).to_vec();
        drop(data);
        buf.unmap();
        Ok(v)
    }
}

/// Writes an image as PNG atomically (temporary file, then rename): a failed write never
/// leaves a truncated file behind.
/// Reads back the whole of `texture` (`texel_bytes` bytes per texel; it needs `COPY_SRC`) as
/// tightly packed rows.
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, texel_bytes: u32) -> Result<Vec<u8>, RuntimeError> {
    let (w, h) = (texture.width(), texture.height());
    let row = w * texel_bytes;
    let padded = row.div_ceil(256) * 256;
    let buf = readback_buffer(&gpu.device, "texture readback", padded as u64 * h as u64);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo { buffer: &buf, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: Some(h) } },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([encoder.finish()]);
    let data = map_read(&gpu.device, buf.slice(..))?;
    let mut bytes = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        bytes.extend_from_slice(&data[y * padded as usize..y * padded as usize + row as usize]);
    }
    drop(data);
    buf.unmap();
    Ok(bytes)
}

pub fn write_png(path: &std::path::Path, img: &image::RgbaImage) -> Result<(), RuntimeError> {
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| RuntimeError::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    crate::util::write_atomic(path, &png).map_err(|source| RuntimeError::Output { path: path.to_path_buf(), source })
}

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

/// The trace module's pipeline constant that compiles the alpha test into the traversal
/// (`shaders/trace/alpha.wgsl`).
pub const TRACE_ALPHA_CONSTANT: &str = "TRACE_ALPHA_TEST";

/// Whether any instance of `scene` is alpha-tested.
fn scene_has_alpha_test(scene: &Scene) -> bool {
    (0..scene.instances.len()).any(|i| crate::accel::alpha::instance_tested(scene, i))
}

/// Pipeline constants of a compute or trace pass: a trace pass whose module declares
/// [`TRACE_ALPHA_CONSTANT`] gets the alpha test only when the scene has alpha-tested geometry,
/// so a scene without any runs a traversal with no trace of the test.
fn trace_constants(pass: &PlannedPass, alpha_test: bool) -> Vec<(&'static str, f64)> {
    if pass.kind == PassKind::Trace && pass.shader.has_override(TRACE_ALPHA_CONSTANT) {
        vec![(TRACE_ALPHA_CONSTANT, if alpha_test { 1.0 } else { 0.0 })]
    } else {
        Vec::new()
    }
}
