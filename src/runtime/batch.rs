//! Tracing a list of rays through a back-end outside any graph: the harness that tests compare
//! with the f64 reference, and that benches use for raw traversal throughput. It compiles
//! `shaders/batch/batch.wgsl` with the back-end's trace module, exactly as a graph's trace pass
//! would be. The trace module's alpha test reads the scene's textures (`scene_textures`, group
//! 1), which the tracer uploads when the module declares them.

use crate::accel::cache::{AccelCache, AccelSettings, BuildReport, RayStats};
use crate::accel::cpu_traverse::TraceFlags;
use crate::accel::rt_pipeline::{RtBinding, RtPass, RtResource};
use crate::backend::Backend;
use crate::error::{GraphError, Location, RuntimeError};
use crate::gpu_util::{map_read, storage_with_readback};
use crate::graph::compile::CompileOptions;
use crate::graph::reflect;
use crate::runtime::gpu::include_aliases;
use crate::runtime::scene_upload::{GpuScene, SceneTextures};
use crate::runtime::Gpu;
use crate::scene::usage::SceneUsage;
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use std::path::Path;
use wgpu::util::DeviceExt;

/// Mirrors `struct Ray` in `shaders/trace/common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct GpuRay {
    /// World-space origin.
    pub origin: [f32; 3],
    /// The closest distance a hit may be at.
    pub t_min: f32,
    /// World-space direction (not necessarily unit length).
    pub dir: [f32; 3],
    /// The farthest distance a hit may be at.
    pub t_max: f32,
}

/// One result of a batch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchHit {
    /// Distance to the hit along the ray, in units of `dir`.
    pub t: f32,
    /// Index of the instance hit.
    pub instance: u32,
    /// Index of the triangle in the instance's mesh.
    pub primitive: u32,
    /// Barycentric coordinates (u, v) of the hit in its triangle.
    pub bary: [f32; 2],
    /// Whether the ray hit the triangle's front face.
    pub front_face: bool,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RawResult {
    t: f32,
    instance: u32,
    primitive: u32,
    flags: u32,
    bary: [f32; 2],
    _pad: [u32; 2],
}

/// A back-end with a scene's acceleration structure built, ready to trace batches.
pub struct BatchTracer {
    cache: AccelCache,
    /// The scene's textures, when the trace module binds them (kept alive for the bind groups).
    _textures: Option<GpuScene>,
    tracer: Tracer,
    timer: Option<crate::runtime::profiler::GpuTimer>,
    /// What building the scene's acceleration structure did.
    build: BuildReport,
    /// Wall milliseconds of the build, from the start of the update until the GPU finished it.
    build_wall_ms: f64,
}

impl BatchTracer {
    /// What building the scene's acceleration structure did.
    pub fn build_report(&self) -> &BuildReport {
        &self.build
    }

    /// Wall milliseconds of the build, from the start of the update until the GPU finished it.
    pub fn build_wall_ms(&self) -> f64 {
        self.build_wall_ms
    }
}

/// How the batch is traced.
enum Tracer {
    /// A compute pipeline (`compute`, `ray-query`).
    Compute { pipeline: wgpu::ComputePipeline, layout0: wgpu::BindGroupLayout, texture_group: wgpu::BindGroup, accel_group: wgpu::BindGroup },
    /// The rt-pipeline back-end's ray-tracing pipeline; the batch's buffers are bound per
    /// batch ([`RtPass::set_group`]).
    RayTracing(std::sync::Mutex<RtPass>),
}

/// A binding of `batch.wgsl` or of its trace module, seen by the compute stage.
fn compute_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// A storage buffer binding.
fn storage_buffer(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None }
}

/// The layout of group 0 of `batch.wgsl`: the parameters, the rays and the results.
fn group0_entries() -> [wgpu::BindGroupLayoutEntry; 3] {
    let uniform = wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None };
    [compute_entry(0, uniform), compute_entry(1, storage_buffer(true)), compute_entry(2, storage_buffer(false))]
}

/// The layout entry of a trace module's binding in the acceleration-structure group.
fn accel_entry(b: &reflect::ShaderBinding) -> wgpu::BindGroupLayoutEntry {
    let ty = match &b.kind {
        reflect::BindingKind::AccelerationStructure => wgpu::BindingType::AccelerationStructure { vertex_return: false },
        reflect::BindingKind::Storage { read_only, .. } => storage_buffer(*read_only),
        other => unreachable!("trace modules bind buffers and acceleration structures, not {other:?}"),
    };
    compute_entry(b.binding, ty)
}

/// Group 0 of `batch.wgsl` for the rt-pipeline back-end.
fn rt_group0(params: &wgpu::Buffer, rays: &wgpu::Buffer, results: &wgpu::Buffer) -> Vec<RtBinding> {
    let buffer = |b: &wgpu::Buffer, uses| RtResource::Buffer { buffer: b.clone(), offset: 0, size: None, uses, initialize: false };
    let [params_entry, rays_entry, results_entry] = group0_entries();
    vec![
        RtBinding { group: 0, entry: params_entry, resource: buffer(params, wgpu::BufferUses::UNIFORM) },
        RtBinding { group: 0, entry: rays_entry, resource: buffer(rays, wgpu::BufferUses::STORAGE_READ_ONLY) },
        RtBinding { group: 0, entry: results_entry, resource: buffer(results, wgpu::BufferUses::STORAGE_READ_WRITE) },
    ]
}

/// The scene's textures as the trace module's `scene_textures` (group 1) binds them.
struct SceneTextureBinding {
    /// The upload (kept alive for the bind groups).
    uploaded: GpuScene,
    /// The layout entry.
    entry: wgpu::BindGroupLayoutEntry,
    /// The texture array, or the array textures of a binding array.
    resource: RtResource,
}

/// The scene's textures for the trace module's `scene_textures` (group 1), if it declares it:
/// the upload, the layout entry and the resource.
fn scene_textures(gpu: &Gpu, scene: &Scene, info: &reflect::ShaderInfo) -> Result<Option<SceneTextureBinding>, RuntimeError> {
    let Some(b) = info.bindings.iter().find(|b| b.name == crate::graph::builtins::SCENE_TEXTURES) else { return Ok(None) };
    let array = b.kind == reflect::BindingKind::TextureBindingArray;
    let usage = SceneUsage { textures: true, texture_binding_array: array, ..Default::default() };
    let uploaded = GpuScene::upload(gpu.device(), gpu.queue(), scene, usage, None)?;
    let textures = uploaded.textures().ok_or_else(|| RuntimeError::Gpu("the scene's textures were not uploaded".into()))?;
    let ty = wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable: true },
        view_dimension: wgpu::TextureViewDimension::D2Array,
        multisampled: false,
    };
    let count = if array { std::num::NonZeroU32::new(textures.count()) } else { None };
    let entry = wgpu::BindGroupLayoutEntry { binding: b.binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count };
    let resource = match textures {
        SceneTextures::Array { texture, view } => RtResource::Texture { texture: texture.clone(), view: view.clone(), uses: wgpu::TextureUses::RESOURCE },
        SceneTextures::Pooled { textures, views } => RtResource::Textures(textures.iter().cloned().zip(views.iter().cloned()).collect()),
    };
    Ok(Some(SceneTextureBinding { uploaded, entry, resource }))
}

/// `shaders/batch/batch.wgsl` reflected with `backend`'s trace module and the device's include
/// substitutions.
fn batch_shader(gpu: &Gpu, backend: Backend, shaders_dir: &Path) -> Result<reflect::ShaderInfo, RuntimeError> {
    let options = CompileOptions { includes: include_aliases(gpu.texture_binding_arrays()), backend, ..Default::default() };
    let path = shaders_dir.join("batch/batch.wgsl");
    reflect::reflect_with(&path, shaders_dir, &Location::file_start(&path), &options.all_includes()).map_err(|e: GraphError| RuntimeError::Graph(e))
}

/// `scene`'s acceleration structure built for `backend` and waited for (its alpha records
/// naming `pooled` textures or not): the cache, what the build did, and its wall milliseconds.
fn build_accel(gpu: &Gpu, backend: Backend, scene: &Scene, settings: AccelSettings, pooled: bool) -> Result<(AccelCache, BuildReport, f64), RuntimeError> {
    let device = gpu.device();
    let start = web_time::Instant::now();
    let mut cache = AccelCache::new(device, backend, settings, 1);
    cache.set_pooled_textures(pooled);
    let mut encoder = device.create_command_encoder(&Default::default());
    let build = cache.update(device, gpu.queue(), &mut encoder, scene)?;
    // The rt-pipeline back-end's build comes as a command buffer of its own.
    gpu.queue().submit([encoder.finish()].into_iter().chain(cache.take_pending()));
    gpu.wait()?;
    Ok((cache, build, start.elapsed().as_secs_f64() * 1e3))
}

/// The rt-pipeline back-end's tracer: `batch.wgsl` as the ray-generation shader of the trace
/// `module`, its group 0 bound per batch (placeholder buffers until then).
fn rt_tracer(
    gpu: &Gpu,
    module: &reflect::RayTracingModule,
    info: &reflect::ShaderInfo,
    textures: Option<&SceneTextureBinding>,
    cache: &AccelCache,
) -> Result<Tracer, RuntimeError> {
    let device = gpu.device();
    let placeholder = |usage| device.create_buffer(&wgpu::BufferDescriptor { label: Some("batch placeholder"), size: 64, usage, mapped_at_creation: false });
    let group0 = rt_group0(&placeholder(wgpu::BufferUsages::UNIFORM), &placeholder(wgpu::BufferUsages::STORAGE), &placeholder(wgpu::BufferUsages::STORAGE));
    let accel = info.bindings.iter().filter(|b| b.group == crate::graph::builtins::ACCEL_GROUP).map(|b| RtBinding {
        group: b.group,
        entry: accel_entry(b),
        resource: RtResource::Accel(b.name.clone()),
    });
    let texture_binding = textures.map(|t| RtBinding { group: crate::graph::builtins::SCENE_TEXTURES_GROUP, entry: t.entry, resource: t.resource.clone() });
    let bindings = group0.into_iter().chain(texture_binding).chain(accel).collect();
    let mut pass = RtPass::new(device, gpu.queue(), "batch", module, "cs_main", &Default::default(), bindings, crate::graph::builtins::ACCEL_GROUP)?;
    let built = cache.rt_accel().ok_or_else(|| RuntimeError::Gpu("the rt-pipeline acceleration structure is not built".into()))?;
    pass.bind_accel(built, &crate::accel::cache::cache_buffers(cache, 0))?;
    Ok(Tracer::RayTracing(std::sync::Mutex::new(pass)))
}

/// A bind group of the compute tracer with its layout and the layout's entries.
struct BoundGroup {
    entries: Vec<wgpu::BindGroupLayoutEntry>,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

/// Group 1 of the compute tracer: the scene's textures, or nothing.
fn texture_group(device: &wgpu::Device, textures: Option<&SceneTextureBinding>) -> BoundGroup {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = textures.map(|t| vec![t.entry]).unwrap_or_default();
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("batch textures"), entries: &entries });
    let views: Vec<&wgpu::TextureView> = match textures.map(|t| &t.resource) {
        Some(RtResource::Textures(list)) => list.iter().map(|(_, v)| v).collect(),
        Some(RtResource::Texture { view, .. }) => vec![view],
        _ => Vec::new(),
    };
    let group_entries: Vec<wgpu::BindGroupEntry> = match (textures, views.as_slice()) {
        (Some(t @ SceneTextureBinding { resource: RtResource::Textures(_), .. }), views) => {
            vec![wgpu::BindGroupEntry { binding: t.entry.binding, resource: wgpu::BindingResource::TextureViewArray(views) }]
        }
        (Some(t), [view]) => vec![wgpu::BindGroupEntry { binding: t.entry.binding, resource: wgpu::BindingResource::TextureView(view) }],
        _ => Vec::new(),
    };
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("batch textures"), layout: &layout, entries: &group_entries });
    BoundGroup { entries, layout, group }
}

/// Group 2 of the compute tracer: the trace module's acceleration-structure bindings, bound to
/// the cache's buffers.
fn accel_group(device: &wgpu::Device, backend: Backend, info: &reflect::ShaderInfo, cache: &AccelCache) -> Result<BoundGroup, RuntimeError> {
    let bindings: Vec<&reflect::ShaderBinding> = info.bindings.iter().filter(|b| b.group == crate::graph::builtins::ACCEL_GROUP).collect();
    let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings.iter().map(|b| accel_entry(b)).collect();
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("batch accel"), entries: &entries });
    let mut group_entries = Vec::new();
    for b in &bindings {
        let resource = cache.binding(&b.name, 0).ok_or_else(|| RuntimeError::Gpu(format!("back-end {backend} has no binding `{}`", b.name)))?;
        group_entries.push(wgpu::BindGroupEntry { binding: b.binding, resource });
    }
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("batch accel"), layout: &layout, entries: &group_entries });
    Ok(BoundGroup { entries, layout, group })
}

/// The `compute` and `ray-query` back-ends' tracer: `batch.wgsl` as a compute pipeline, its
/// groups 1 (scene textures) and 2 (acceleration structure) bound once.
fn compute_tracer(
    gpu: &Gpu,
    backend: Backend,
    info: &reflect::ShaderInfo,
    textures: Option<&SceneTextureBinding>,
    cache: &AccelCache,
) -> Result<Tracer, RuntimeError> {
    let device = gpu.device();
    let entries0 = group0_entries();
    let layout0 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("batch"), entries: &entries0 });
    let textures = texture_group(device, textures);
    let accel = accel_group(device, backend, info, cache)?;
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("batch"),
        bind_group_layouts: &[Some(&layout0), Some(&textures.layout), Some(&accel.layout)],
        immediate_size: 0,
    });
    // The batch tracer is part of the program (tests, benches), not of a project: its loops are
    // the traversal's and its own ray loop, all of which end (`ShaderOrigin::BuiltInTraversal`).
    let groups = [entries0.to_vec(), textures.entries, accel.entries];
    let (module, constants) = gpu.traversal_module("batch.wgsl", info.source.text(), "cs_main", crate::gpu_util::ShaderOrigin::BuiltInTraversal, &[], &groups);
    let pipeline = crate::gpu_util::compute_pipeline_with(device, "batch", &pipeline_layout, &module, "cs_main", &constants);
    Ok(Tracer::Compute { pipeline, layout0, texture_group: textures.group, accel_group: accel.group })
}

/// Workgroup size of `batch.wgsl`.
const GROUP: u32 = 64;

impl BatchTracer {
    /// Builds `scene`'s acceleration structure for `backend` (de-duplication on).
    pub fn new(gpu: &Gpu, backend: Backend, scene: &Scene, shaders_dir: &Path) -> Result<Self, RuntimeError> {
        Self::with_settings(gpu, backend, scene, shaders_dir, AccelSettings { dedup: true, merge: false })
    }

    /// [`BatchTracer::new`] with the `Accel` node's settings (de-duplication off: one BLAS per
    /// instance; merge: one BVH over all instances, `compute` and `rt-pipeline`).
    pub fn with_settings(gpu: &Gpu, backend: Backend, scene: &Scene, shaders_dir: &Path, settings: AccelSettings) -> Result<Self, RuntimeError> {
        if !gpu.backends().contains(&backend) {
            return Err(RuntimeError::Gpu(format!("back-end {backend} is not available on {}", gpu.info().name)));
        }
        let info = batch_shader(gpu, backend, shaders_dir)?;
        // The alpha records name the textures as the trace module binds them.
        let pooled = info.bindings.iter().any(|b| b.name == crate::graph::builtins::SCENE_TEXTURES && b.kind == reflect::BindingKind::TextureBindingArray);
        let (cache, build, build_wall_ms) = build_accel(gpu, backend, scene, settings, pooled)?;
        let scope = gpu.scopes();
        let timer = gpu.timestamps().then(|| crate::runtime::profiler::GpuTimer::new(gpu.device(), gpu.queue(), 1));
        let textures = scene_textures(gpu, scene, &info)?;
        let tracer = match &info.ray_tracing {
            Some(module) => rt_tracer(gpu, module, &info, textures.as_ref(), &cache)?,
            None => compute_tracer(gpu, backend, &info, textures.as_ref(), &cache)?,
        };
        scope.finish(gpu, "creating the batch tracer")?;
        Ok(Self { cache, _textures: textures.map(|t| t.uploaded), tracer, timer, build, build_wall_ms })
    }

    /// Closest hits of `rays` (`None`: miss), and the GPU ray counters.
    pub fn closest(&self, gpu: &Gpu, rays: &[GpuRay]) -> Result<(Vec<Option<BatchHit>>, RayStats), RuntimeError> {
        self.closest_flags(gpu, rays, TraceFlags::NONE)
    }

    /// [`BatchTracer::closest`] with the trace interface's per-ray `flags` on every ray
    /// (`trace_closest_flags`).
    pub(crate) fn closest_flags(&self, gpu: &Gpu, rays: &[GpuRay], flags: TraceFlags) -> Result<(Vec<Option<BatchHit>>, RayStats), RuntimeError> {
        let (raw, stats, _) = self.run(gpu, rays, 0, flags)?;
        let hits = raw
            .iter()
            .map(|r| {
                (r.flags & 1 != 0).then_some(BatchHit { t: r.t, instance: r.instance, primitive: r.primitive, bary: r.bary, front_face: r.flags & 2 != 0 })
            })
            .collect();
        Ok((hits, stats))
    }

    /// Whether each ray hits anything (terminating on the first hit).
    pub fn any(&self, gpu: &Gpu, rays: &[GpuRay]) -> Result<(Vec<bool>, RayStats), RuntimeError> {
        self.any_flags(gpu, rays, TraceFlags::NONE)
    }

    /// [`BatchTracer::any`] with the trace interface's per-ray `flags` on every ray
    /// (`trace_any_flags`).
    pub(crate) fn any_flags(&self, gpu: &Gpu, rays: &[GpuRay], flags: TraceFlags) -> Result<(Vec<bool>, RayStats), RuntimeError> {
        let (raw, stats, _) = self.run(gpu, rays, 1, flags)?;
        Ok((raw.iter().map(|r| r.flags & 1 != 0).collect(), stats))
    }

    /// Traces `rays` for their closest hits and returns the counters and the dispatch's GPU
    /// milliseconds (timestamp queries; `None` without them).
    #[cfg(feature = "cli")]
    pub(crate) fn time_closest(&self, gpu: &Gpu, rays: &[GpuRay]) -> Result<(RayStats, Option<f64>), RuntimeError> {
        let (_, stats, ms) = self.run(gpu, rays, 0, TraceFlags::NONE)?;
        Ok((stats, ms))
    }

    fn run(&self, gpu: &Gpu, rays: &[GpuRay], mode: u32, flags: TraceFlags) -> Result<(Vec<RawResult>, RayStats, Option<f64>), RuntimeError> {
        let device = gpu.device();
        let n = rays.len().max(1);
        let groups = (n as u32).div_ceil(GROUP);
        let (gx, gy) = if groups <= 65_535 { (groups, 1) } else { (65_535, groups.div_ceil(65_535)) };
        let params: [u32; 4] = [rays.len() as u32, mode, flags.0, gx * GROUP];
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("batch params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let padded: Vec<GpuRay> = if rays.is_empty() { vec![GpuRay::zeroed()] } else { rays.to_vec() };
        let ray_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("batch rays"),
            contents: bytemuck::cast_slice(&padded),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (n * std::mem::size_of::<RawResult>()) as u64;
        let (results, readback) = storage_with_readback(device, "batch results", size);
        let mut command_buffers = Vec::new();
        let mut encoder = device.create_command_encoder(&Default::default());
        self.cache.clear_stats(&mut encoder);
        let (pipeline, layout0, texture_group, accel_group) = match &self.tracer {
            Tracer::Compute { pipeline, layout0, texture_group, accel_group } => (pipeline, layout0, texture_group, accel_group),
            Tracer::RayTracing(rt) => {
                let mut rt = rt.lock().map_err(|_| RuntimeError::Gpu("the batch tracer's pipeline is poisoned".into()))?;
                rt.set_group(0, rt_group0(&uniform, &ray_buf, &results))?;
                // A new buffer every batch: written through wgpu once so that wgpu counts it
                // initialized (see RtPass::transition).
                encoder.clear_buffer(&results, 0, None);
                rt.transition(&mut encoder, self.cache.stats_window(0).0);
                if let Some(t) = &self.timer {
                    drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("batch begin"), timestamp_writes: t.begin_writes(0) }));
                }
                command_buffers.push(encoder.finish());
                command_buffers.push(rt.record([gx * GROUP, gy, 1])?);
                encoder = device.create_command_encoder(&Default::default());
                if let Some(t) = &self.timer {
                    drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("batch end"), timestamp_writes: t.end_writes(0) }));
                }
                return self.finish_run(gpu, command_buffers, encoder, &results, &readback, size, rays.len());
            }
        };
        let bg0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("batch"),
            layout: layout0,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: ray_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: results.as_entire_binding() },
            ],
        });
        {
            let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("batch"),
                timestamp_writes: self.timer.as_ref().and_then(|t| t.compute_writes(0)),
            });
            cp.set_pipeline(pipeline);
            cp.set_bind_group(0, &bg0, &[]);
            cp.set_bind_group(1, texture_group, &[]);
            cp.set_bind_group(2, accel_group, &[]);
            cp.dispatch_workgroups(gx, gy, 1);
        }
        self.finish_run(gpu, command_buffers, encoder, &results, &readback, size, rays.len())
    }

    /// Copies the results and counters out, submits, waits and reads them back.
    #[allow(clippy::too_many_arguments)]
    fn finish_run(
        &self,
        gpu: &Gpu,
        mut command_buffers: Vec<wgpu::CommandBuffer>,
        mut encoder: wgpu::CommandEncoder,
        results: &wgpu::Buffer,
        readback: &wgpu::Buffer,
        size: u64,
        count: usize,
    ) -> Result<(Vec<RawResult>, RayStats, Option<f64>), RuntimeError> {
        let device = gpu.device();
        encoder.copy_buffer_to_buffer(results, 0, readback, 0, size);
        self.cache.copy_stats(&mut encoder);
        if let Some(t) = &self.timer {
            t.resolve(&mut encoder, 1);
        }
        command_buffers.push(encoder.finish());
        gpu.queue().submit(command_buffers);
        gpu.wait()?;
        let data = map_read(device, readback.slice(..))?;
        let out: Vec<RawResult> = bytemuck::cast_slice::<u8, RawResult>(&data)[..count].to_vec();
        drop(data);
        readback.unmap();
        let stats = pollster::block_on(self.cache.read_stats(device))?[0];
        let ms = match &self.timer {
            Some(t) => pollster::block_on(t.read(device, 1))?.first().copied(),
            None => None,
        };
        Ok((out, stats, ms))
    }
}
