//! The ray-tracing pipeline of a trace pass, made in named steps: the entry points found, the
//! bind group and pipeline layouts, the shader modules (naga's and the patched any-hit SPIR-V),
//! the pipeline, and the shader binding table uploaded from a staging buffer.

use super::any_hit;
use super::bindings::RtBinding;
use super::hal_objects::{alignments, count_made, empty_device_buffer, hal_error, record_raw, upload, HalDevice, HalObjects};
use crate::error::RuntimeError;
use wgpu::hal;
use wgpu::hal::Device as _;

/// Every ray-tracing stage, the visibility of every binding of a ray-tracing pipeline.
const RT_STAGES: wgpu::ShaderStages =
    wgpu::ShaderStages::RAY_GENERATION.union(wgpu::ShaderStages::MISS).union(wgpu::ShaderStages::CLOSEST_HIT).union(wgpu::ShaderStages::ANY_HIT);

/// What a pass's pipeline is made from: the trace module with the pass's entry point `entry`
/// as its ray-generation shader, and the pipeline constants of the ray-generation, miss and
/// closest-hit stages.
pub(super) struct PipelineSource<'a> {
    pub(super) label: &'a str,
    pub(super) module: &'a crate::graph::reflect::RayTracingModule,
    pub(super) entry: &'a str,
    pub(super) constants: &'a naga::back::PipelineConstants,
}

/// The trace module's entry points of the stages after ray generation.
struct EntryPoints {
    miss: String,
    closest: String,
    any_hit: String,
}

/// The trace module's miss, closest-hit and any-hit entry points; fails if one is missing or
/// the pass's entry point is not a ray-generation one.
fn entry_points(source: &PipelineSource) -> Result<EntryPoints, RuntimeError> {
    let PipelineSource { label, module, entry, .. } = source;
    let stage_name = |stage: naga::ShaderStage| {
        module
            .module
            .entry_points
            .iter()
            .find(|e| e.stage == stage)
            .map(|e| e.name.clone())
            .ok_or_else(|| RuntimeError::Gpu(format!("pass {label}: the rt-pipeline trace module has no {stage:?} entry point")))
    };
    let miss = stage_name(naga::ShaderStage::Miss)?;
    let closest = stage_name(naga::ShaderStage::ClosestHit)?;
    let any_hit = stage_name(naga::ShaderStage::AnyHit)?;
    if !module.module.entry_points.iter().any(|e| e.name == *entry && e.stage == naga::ShaderStage::RayGeneration) {
        return Err(RuntimeError::Gpu(format!("pass {label}: `{entry}` is not a ray-generation entry point")));
    }
    Ok(EntryPoints { miss, closest, any_hit })
}

/// The hal objects of a pass's pipeline, and where each is in `objects`.
pub(super) struct PassPipeline {
    pub(super) objects: HalObjects,
    /// Per group: index into `objects.bind_group_layouts`, and of its bind group (`None` until
    /// bound).
    pub(super) groups: Vec<(usize, Option<usize>)>,
    pub(super) pipeline_layout: usize,
    pub(super) pipeline: usize,
    pub(super) sbt: usize,
    /// (offset, stride) of the ray-generation, miss and hit-group records.
    pub(super) regions: [(u64, u64); 3],
}

impl PassPipeline {
    /// Makes the pipeline of `source` for `bindings` (every binding of every group, the
    /// `accel_group` bound later), and uploads its shader binding table on `queue`.
    pub(super) fn make(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &PipelineSource,
        bindings: &[RtBinding],
        accel_group: u32,
    ) -> Result<Self, RuntimeError> {
        let names = entry_points(source)?;
        let group_count = bindings.iter().map(|b| b.group + 1).max().unwrap_or(0).max(accel_group + 1);
        let mut made = PassPipeline { objects: HalObjects::default(), groups: Vec::new(), pipeline_layout: 0, pipeline: 0, sbt: 0, regions: [(0, 0); 3] };
        let mut staging = HalObjects::default();
        // Per group, its layout's entries in order (the any-hit module's bindings follow them).
        let layout_entries: Vec<Vec<wgpu::BindGroupLayoutEntry>> = (0..group_count)
            .map(|g| bindings.iter().filter(|b| b.group == g).map(|b| wgpu::BindGroupLayoutEntry { visibility: RT_STAGES, ..b.entry }).collect())
            .collect();
        let module = source.module;
        let any_hit_words = any_hit::any_hit_spirv(&module.module, &module.info, &names.any_hit, source.entry, any_hit::binding_map(&layout_entries))
            .map_err(|e| RuntimeError::Gpu(format!("pass {}: the any-hit shader: {e}", source.label)))?;
        let commands = record_raw(device, "rt-pipeline shader binding table", |d, enc| {
            made.make_layouts(d, source.label, &layout_entries)?;
            made.make_shaders(d, source, &any_hit_words)?;
            made.make_pipeline(d, source, &names)?;
            made.make_binding_table(d, enc, &mut staging)
        });
        let commands = match commands {
            Ok(c) => c,
            Err(e) => {
                made.objects.destroy(device);
                staging.destroy(device);
                return Err(e);
            }
        };
        queue.submit([commands]);
        staging.destroy(device);
        Ok(made)
    }

    /// A bind group layout per group (`layout_entries`), and the pipeline layout over them.
    fn make_layouts(&mut self, d: &HalDevice, label: &str, layout_entries: &[Vec<wgpu::BindGroupLayoutEntry>]) -> Result<(), RuntimeError> {
        let objects = &mut self.objects;
        for entries in layout_entries {
            // SAFETY: a layout from plain entries.
            let layout = unsafe {
                d.create_bind_group_layout(&hal::BindGroupLayoutDescriptor { label: Some(label), flags: hal::BindGroupLayoutFlags::empty(), entries })
            }
            .map(count_made)
            .map_err(|e| hal_error("creating a bind group layout", e))?;
            objects.bind_group_layouts.push(layout);
            self.groups.push((objects.bind_group_layouts.len() - 1, None));
        }
        let layout_refs: Vec<Option<&hal::vulkan::BindGroupLayout>> = objects.bind_group_layouts.iter().map(Some).collect();
        // SAFETY: a pipeline layout over the layouts just made.
        let layout = unsafe {
            d.create_pipeline_layout(&hal::PipelineLayoutDescriptor {
                label: Some(label),
                flags: hal::PipelineLayoutFlags::empty(),
                bind_group_layouts: &layout_refs,
                immediate_size: 0,
            })
        }
        .map(count_made)
        .map_err(|e| hal_error("creating the pipeline layout", e))?;
        objects.pipeline_layouts.push(layout);
        self.pipeline_layout = objects.pipeline_layouts.len() - 1;
        Ok(())
    }

    /// The shader modules: the trace module compiled from naga IR (ray generation, miss and
    /// closest hit), then the any-hit shader from its patched SPIR-V `any_hit_words`.
    fn make_shaders(&mut self, d: &HalDevice, source: &PipelineSource, any_hit_words: &[u32]) -> Result<(), RuntimeError> {
        let (label, module) = (source.label, source.module);
        // SAFETY: the module is naga IR validated by the compiler
        // (graph::reflect::reflect_with); the runtime checks of a trace pass
        // (gpu_util::ShaderOrigin::TracePass).
        let shader = unsafe {
            d.create_shader_module(
                &hal::ShaderModuleDescriptor { label: Some(label), runtime_checks: crate::gpu_util::ShaderOrigin::TracePass.checks() },
                hal::ShaderInput::Naga(hal::NagaShader {
                    module: std::borrow::Cow::Owned((*module.module).clone()),
                    info: (*module.info).clone(),
                    debug_source: None,
                }),
            )
        }
        .map(count_made)
        .map_err(|e| hal_error("compiling the shaders", e))?;
        self.objects.shader_modules.push(shader);
        // SAFETY: SPIR-V written by naga from the same validated module, with the
        // pipeline layout's bindings, and patched (any_hit.rs); the validation layer checks
        // it when the pipeline is made.
        let any_hit_shader = unsafe {
            d.create_shader_module(
                &hal::ShaderModuleDescriptor { label: Some(label), runtime_checks: crate::gpu_util::ShaderOrigin::TracePass.checks() },
                hal::ShaderInput::SpirV(any_hit_words),
            )
        }
        .map(count_made)
        .map_err(|e| hal_error("compiling the any-hit shader", e))?;
        self.objects.shader_modules.push(any_hit_shader);
        Ok(())
    }

    /// The ray-tracing pipeline over the shader modules and the pipeline layout.
    fn make_pipeline(&mut self, d: &HalDevice, source: &PipelineSource, names: &EntryPoints) -> Result<(), RuntimeError> {
        let objects = &mut self.objects;
        let constants = source.constants;
        let stage = |module, entry_point| hal::ProgrammableStage { module, entry_point, constants, zero_initialize_workgroup_memory: true };
        let (naga_stages, spirv_stage) = (&objects.shader_modules[0], &objects.shader_modules[1]);
        // One hit group for every instance: the any-hit shader runs only on non-opaque
        // geometry (alpha-tested instances, RtAccel::update), so opaque hits never reach it.
        let hit_groups =
            [hal::RayObjectIntersectionState { closest_hit: stage(naga_stages, &names.closest), any_hit: Some(stage(spirv_stage, &names.any_hit)) }];
        // SAFETY: stages of a module made above, a layout made above; recursion depth 1:
        // hit and miss shaders trace no rays.
        let p = unsafe {
            d.create_ray_tracing_pipeline(&hal::RayTracingPipelineDescriptor {
                label: Some(source.label),
                layout: &objects.pipeline_layouts[self.pipeline_layout],
                ray_generation: stage(naga_stages, source.entry),
                miss: stage(naga_stages, &names.miss),
                intersection: &hit_groups,
                max_recursion_depth: 1,
                cache: None,
            })
        }
        .map(count_made)
        .map_err(|e| hal_error("creating the ray-tracing pipeline", e))?;
        objects.pipelines.push(p);
        self.pipeline = objects.pipelines.len() - 1;
        Ok(())
    }

    /// The shader binding table: group 0 ray generation, 1 miss, 2 the hit group, each record
    /// at the device's alignments, uploaded into a buffer of its own by a copy recorded into
    /// `enc` (the staging buffer kept in `staging`).
    fn make_binding_table(&mut self, d: &HalDevice, enc: &mut hal::vulkan::CommandEncoder, staging: &mut HalObjects) -> Result<(), RuntimeError> {
        let align = alignments(d);
        // SAFETY: the pipeline was made above with three groups.
        let handles = unsafe { d.get_raytracing_pipeline_group_data(&self.objects.pipelines[self.pipeline], 0..3) }
            .map_err(|e| hal_error("reading shader group handles", e))?;
        let handle = handles.len() as u64 / 3;
        if handle != align.handle_size {
            return Err(RuntimeError::Gpu(format!("rt-pipeline back-end: shader group handles of {handle} bytes, the device reports {}", align.handle_size)));
        }
        let stride = handle.next_multiple_of(align.handle_alignment);
        let region = stride.next_multiple_of(align.base_alignment);
        // Each region's device address must be a multiple of the base alignment, which the
        // buffer's own address need not be: the table starts at the first such address.
        let label = "rt shader binding table";
        let table_buffer = empty_device_buffer(d, label, 3 * region + align.base_alignment, wgpu::BufferUses::RAY_TRACING_PIPELINE_SHADER_DATA)?;
        // SAFETY: the address of a buffer made above with SHADER_DEVICE_ADDRESS usage
        // (hal adds it for shader data), through the extension hal enabled for ray tracing.
        let address = unsafe {
            ash::khr::buffer_device_address::Device::new(d.shared_instance().raw_instance(), d.raw_device())
                .get_buffer_device_address(&ash::vk::BufferDeviceAddressInfo::default().buffer(table_buffer.raw_handle()))
        };
        let start = address.next_multiple_of(align.base_alignment) - address;
        let mut table = vec![0u8; (start + 3 * region) as usize];
        for g in 0..3 {
            let src = &handles[(g * handle) as usize..((g + 1) * handle) as usize];
            let at = (start + g * region) as usize;
            table[at..at + handle as usize].copy_from_slice(src);
        }
        self.regions = [(start, stride), (start + region, stride), (start + 2 * region, stride)];
        self.objects.buffers.push(table_buffer);
        self.sbt = self.objects.buffers.len() - 1;
        upload(d, enc, staging, label, &self.objects.buffers[self.sbt], &table)
    }
}
