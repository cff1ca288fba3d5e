//! Back-end `rt-pipeline`: the ray-tracing pipeline with a shader binding table (DXR's model,
//! Vulkan's `VK_KHR_ray_tracing_pipeline`), reached through wgpu-hal because wgpu 30 has no
//! public API for it. Every unsafe call of the project into wgpu-hal and Vulkan is in this
//! module, each block with its `// SAFETY:` argument.
//!
//! What it owns:
//! - [`RtAccel`]: the acceleration structures, built through wgpu-hal: a BLAS per mesh
//!   (triangles the other back-ends leave out become degenerate, so primitive indices stay the
//!   mesh's own; built OPAQUE unless an alpha-tested instance uses it), a TLAS whose instances
//!   carry the scene instance index as custom data and hit group 0 (opaque instances forced
//!   opaque), and the object-space positions and indices the closest-hit shader reads to
//!   compute barycentrics (naga's closest-hit stage has no hit attributes).
//! - `RtPass`: one trace pass as a ray-tracing pipeline: the pass's compute entry point made
//!   the ray-generation shader ([`crate::graph::reflect::compute_to_ray_generation`]), the miss
//!   and closest-hit shaders of `shaders/trace/rt_pipeline.wgsl`, its any-hit shader as patched
//!   SPIR-V (`any_hit`: the alpha test, which only non-opaque geometry reaches), bind groups
//!   made through wgpu-hal over the same wgpu textures and buffers a compute pass would bind,
//!   and the shader binding table (ray generation, miss, hit group records at the device's
//!   alignments).
//!
//! Synchronization with wgpu. wgpu forbids mixing its encoding API with raw recording in one
//! command encoder, so hal work is recorded into command encoders of its own that the caller
//! submits in order between wgpu's (`Queue::submit` of several command buffers executes them
//! in order on one queue). wgpu does not see what those command buffers touch, so the contract
//! is explicit:
//! 1. before a trace, the caller's wgpu encoder calls `RtPass::transition`: wgpu moves every
//!    texture and buffer the pass binds into the state (and Vulkan image layout) the hal bind
//!    groups were made for, and records that state in its tracker;
//! 2. the hal command buffer starts with a memory barrier from all earlier commands' writes to
//!    the ray-tracing stages' reads and writes, and ends with one from the ray-tracing stages'
//!    writes to every later command, so wgpu's next barrier (whose source stages never include
//!    the ray-tracing stages) is not relied on;
//! 3. the hal command buffer changes no image layout, so wgpu's tracker stays true.
//!
//! Acceleration-structure builds are recorded the same way and submitted at once, before the
//! frame that uses them. Objects made through wgpu-hal are destroyed in `Drop` after the device
//! is idle.

mod any_hit;
mod bindings;

pub use any_hit::{any_hit_spirv, binding_map as any_hit_binding_map};
pub use bindings::{AccelBuffers, RtBinding, RtResource};

use super::alpha::instance_tested as alpha_tested;
use crate::error::RuntimeError;
use crate::scene::Scene;
use std::num::NonZeroU64;
use wgpu::hal;
use wgpu::hal::{CommandEncoder as _, Device as _};

type Vk = hal::api::Vulkan;
type HalDevice = hal::vulkan::Device;
type HalBuffer = hal::vulkan::Buffer;
type HalAccel = hal::vulkan::AccelerationStructure;

/// Every ray-tracing stage, the visibility of every binding of a ray-tracing pipeline.
const RT_STAGES: wgpu::ShaderStages =
    wgpu::ShaderStages::RAY_GENERATION.union(wgpu::ShaderStages::MISS).union(wgpu::ShaderStages::CLOSEST_HIT).union(wgpu::ShaderStages::ANY_HIT);

/// Objects this module has made through wgpu-hal and not yet destroyed (tests check that it
/// returns to where it was once everything is dropped).
static LIVE_OBJECTS: std::sync::atomic::AtomicIsize = std::sync::atomic::AtomicIsize::new(0);

/// The number of objects made through wgpu-hal by this back-end and still alive.
pub fn live_hal_objects() -> isize {
    LIVE_OBJECTS.load(std::sync::atomic::Ordering::SeqCst)
}

/// Counts an object just made (see [`live_hal_objects`]).
fn count_made<T>(object: T) -> T {
    LIVE_OBJECTS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    object
}

/// Counts `n` objects destroyed.
fn destroyed(n: usize) {
    LIVE_OBJECTS.fetch_sub(n as isize, std::sync::atomic::Ordering::SeqCst);
}

fn hal_error(what: &str, e: impl std::fmt::Display) -> RuntimeError {
    RuntimeError::Gpu(format!("rt-pipeline back-end: {what}: {e}"))
}

/// Runs `f` with the wgpu device's Vulkan hal device.
fn with_hal<R>(device: &wgpu::Device, f: impl FnOnce(&HalDevice) -> Result<R, RuntimeError>) -> Result<R, RuntimeError> {
    // SAFETY: the guard lives only for `f`; objects made through it are destroyed through it
    // (see `HalObjects::drop`) before the wgpu device, whose clone each owner keeps.
    let guard = unsafe { device.as_hal::<Vk>() };
    match guard {
        Some(d) => f(&d),
        None => Err(RuntimeError::Gpu("the rt-pipeline back-end needs wgpu's Vulkan back-end".into())),
    }
}

/// Records hal commands into a command encoder of their own (see the module docs), each
/// block of commands between the two memory barriers.
fn record_raw(
    device: &wgpu::Device,
    label: &str,
    f: impl FnOnce(&HalDevice, &mut hal::vulkan::CommandEncoder) -> Result<(), RuntimeError>,
) -> Result<wgpu::CommandBuffer, RuntimeError> {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
    with_hal(device, |hal_device| {
        // SAFETY: the encoder is used only through hal inside this call (wgpu's API is never
        // called on it before `finish`), and the callback does not end the command buffer.
        unsafe {
            encoder.as_hal_mut::<Vk, _, _>(|raw| {
                let raw = raw.ok_or_else(|| RuntimeError::Gpu("the rt-pipeline back-end needs wgpu's Vulkan back-end".into()))?;
                memory_barrier(hal_device, raw, vk_all_commands(), vk_rt_and_build());
                f(hal_device, raw)?;
                memory_barrier(hal_device, raw, vk_rt_and_build(), vk_all_commands());
                Ok(())
            })
        }
    })?;
    Ok(encoder.finish())
}

fn vk_all_commands() -> ash::vk::PipelineStageFlags {
    ash::vk::PipelineStageFlags::ALL_COMMANDS
}

fn vk_rt_and_build() -> ash::vk::PipelineStageFlags {
    ash::vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR | ash::vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR | ash::vk::PipelineStageFlags::TRANSFER
}

/// A global memory barrier: every write of `src` stages visible to every access of `dst`.
fn memory_barrier(device: &HalDevice, encoder: &mut hal::vulkan::CommandEncoder, src: ash::vk::PipelineStageFlags, dst: ash::vk::PipelineStageFlags) {
    let barrier = ash::vk::MemoryBarrier::default()
        .src_access_mask(ash::vk::AccessFlags::MEMORY_WRITE)
        .dst_access_mask(ash::vk::AccessFlags::MEMORY_READ | ash::vk::AccessFlags::MEMORY_WRITE);
    // SAFETY: the command buffer is the encoder's open one (inside `as_hal_mut`), outside any
    // render pass; a global memory barrier names no resource and changes no layout.
    unsafe {
        device.raw_device().cmd_pipeline_barrier(encoder.raw_handle(), src, dst, ash::vk::DependencyFlags::empty(), &[barrier], &[], &[]);
    }
}

/// The device's ray-tracing alignments (Vulkan properties).
#[derive(Debug, Clone, Copy)]
struct Alignments {
    handle_size: u64,
    handle_alignment: u64,
    base_alignment: u64,
    scratch_alignment: u64,
}

fn alignments(device: &HalDevice) -> Alignments {
    let mut rt = ash::vk::PhysicalDeviceRayTracingPipelinePropertiesKHR::default();
    let mut accel = ash::vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut props = ash::vk::PhysicalDeviceProperties2::default().push_next(&mut rt).push_next(&mut accel);
    // SAFETY: a query of the physical device the hal device was opened on, into structures
    // that outlive the call.
    unsafe { device.shared_instance().raw_instance().get_physical_device_properties2(device.raw_physical_device(), &mut props) };
    Alignments {
        handle_size: rt.shader_group_handle_size.max(1) as u64,
        handle_alignment: rt.shader_group_handle_alignment.max(1) as u64,
        base_alignment: rt.shader_group_base_alignment.max(1) as u64,
        scratch_alignment: accel.min_acceleration_structure_scratch_offset_alignment.max(1) as u64,
    }
}

/// Objects made through wgpu-hal, destroyed (after the device is idle) when dropped.
#[derive(Default)]
struct HalObjects {
    buffers: Vec<HalBuffer>,
    accels: Vec<HalAccel>,
    bind_groups: Vec<hal::vulkan::BindGroup>,
    bind_group_layouts: Vec<hal::vulkan::BindGroupLayout>,
    pipeline_layouts: Vec<hal::vulkan::PipelineLayout>,
    shader_modules: Vec<hal::vulkan::ShaderModule>,
    pipelines: Vec<hal::vulkan::RayTracingPipeline>,
    samplers: Vec<hal::vulkan::Sampler>,
    texture_views: Vec<hal::vulkan::TextureView>,
}

impl HalObjects {
    fn len(&self) -> usize {
        self.buffers.len()
            + self.accels.len()
            + self.bind_groups.len()
            + self.bind_group_layouts.len()
            + self.pipeline_layouts.len()
            + self.shader_modules.len()
            + self.pipelines.len()
            + self.samplers.len()
            + self.texture_views.len()
    }

    /// Destroys every object once the GPU has finished all submitted work.
    fn destroy(&mut self, device: &wgpu::Device) {
        let count = self.len();
        if count == 0 {
            return;
        }
        // Command buffers that use these objects were submitted before this point. If the
        // device cannot be waited for (lost, or the wait timed out), the objects are left
        // rather than destroyed while the GPU may still use them.
        let waited = device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(std::time::Duration::from_secs(120)) });
        if let Err(e) = waited {
            log::warn!("rt-pipeline back-end: the device could not be waited for ({e}); its objects are left to the driver");
            *self = HalObjects::default();
            return;
        }
        let _ = with_hal(device, |d| {
            destroyed(count);
            // SAFETY: every object was made by this device and the GPU is idle (above); each
            // is destroyed once (drained) and nothing refers to it afterwards.
            unsafe {
                for p in self.pipelines.drain(..) {
                    d.destroy_ray_tracing_pipeline(p);
                }
                for g in self.bind_groups.drain(..) {
                    d.destroy_bind_group(g);
                }
                for l in self.pipeline_layouts.drain(..) {
                    d.destroy_pipeline_layout(l);
                }
                for l in self.bind_group_layouts.drain(..) {
                    d.destroy_bind_group_layout(l);
                }
                for m in self.shader_modules.drain(..) {
                    d.destroy_shader_module(m);
                }
                for s in self.samplers.drain(..) {
                    d.destroy_sampler(s);
                }
                for v in self.texture_views.drain(..) {
                    d.destroy_texture_view(v);
                }
                for a in self.accels.drain(..) {
                    d.destroy_acceleration_structure(a);
                }
                for b in self.buffers.drain(..) {
                    d.destroy_buffer(b);
                }
            }
            Ok(())
        });
    }
}

/// A buffer made through wgpu-hal in device memory, filled from `data` by a copy recorded
/// into `encoder` from a host-visible staging buffer (kept in `staging` until the device is
/// idle).
fn device_buffer(
    d: &HalDevice,
    encoder: &mut hal::vulkan::CommandEncoder,
    staging: &mut HalObjects,
    label: &str,
    data: &[u8],
    usage: wgpu::BufferUses,
) -> Result<HalBuffer, RuntimeError> {
    let buffer = empty_device_buffer(d, label, data.len() as u64, usage)?;
    if let Err(e) = upload(d, encoder, staging, label, &buffer, data) {
        staging.buffers.push(buffer);
        return Err(e);
    }
    Ok(buffer)
}

/// A device-memory buffer of at least `size` bytes (16, in whole words) that copies can fill.
fn empty_device_buffer(d: &HalDevice, label: &str, size: u64, usage: wgpu::BufferUses) -> Result<HalBuffer, RuntimeError> {
    let size = size.max(16).next_multiple_of(4);
    // SAFETY: plain buffer creation; the caller destroys it through `HalObjects`.
    unsafe {
        d.create_buffer(&hal::BufferDescriptor { label: Some(label), size, usage: usage | wgpu::BufferUses::COPY_DST, memory_flags: hal::MemoryFlags::empty() })
    }
    .map(count_made)
    .map_err(|e| hal_error(label, e))
}

/// Records a copy of `data` into the start of `buffer` (at least `data.len()` bytes, made with
/// COPY_DST) from a host-visible staging buffer, kept in `staging` until the device is idle.
fn upload(
    d: &HalDevice,
    encoder: &mut hal::vulkan::CommandEncoder,
    staging: &mut HalObjects,
    label: &str,
    buffer: &HalBuffer,
    data: &[u8],
) -> Result<(), RuntimeError> {
    let size = (data.len() as u64).max(16).next_multiple_of(4);
    // SAFETY: a host-visible buffer of `size` >= data.len() bytes, mapped, written and unmapped
    // here; the copy is recorded into the open encoder and the staging buffer stays alive until
    // the device is idle (`staging` is destroyed after a wait).
    unsafe {
        let stage = d
            .create_buffer(&hal::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUses::MAP_WRITE | wgpu::BufferUses::COPY_SRC,
                memory_flags: hal::MemoryFlags::PREFER_COHERENT,
            })
            .map(count_made)
            .map_err(|e| hal_error(label, e))?;
        let mapping = match d.map_buffer(&stage, 0..size) {
            Ok(m) => m,
            Err(e) => {
                staging.buffers.push(stage);
                return Err(hal_error(label, e));
            }
        };
        std::ptr::copy_nonoverlapping(data.as_ptr(), mapping.ptr.as_ptr(), data.len());
        if !mapping.is_coherent {
            d.flush_mapped_ranges(&stage, std::iter::once(0..size));
        }
        d.unmap_buffer(&stage);
        encoder.copy_buffer_to_buffer(
            &stage,
            buffer,
            std::iter::once(hal::BufferCopy { src_offset: 0, dst_offset: 0, size: NonZeroU64::new(size).expect("size >= 16") }),
        );
        staging.buffers.push(stage);
    }
    Ok(())
}

/// The acceleration structures of a scene, built through wgpu-hal (see the module docs): a
/// BLAS per unit (mesh, or instance without de-duplication) rebuilt only when its unit
/// changed, and a TLAS and the closest-hit shader's geometry arrays made again on every change.
pub struct RtAccel {
    device: wgpu::Device,
    /// Per unit; `None` for a unit without a valid triangle (its instances are left out).
    blases: Vec<Option<HalAccel>>,
    /// Per unit, the (triangle count, opaque) of each geometry its BLAS was built with.
    blas_kinds: Vec<Option<Vec<(u32, bool)>>>,
    tlas: Option<HalAccel>,
    /// The positions, indices, per-instance first triangles and the merged layout's triangle
    /// owners (`accel_positions`, `accel_indices`, `accel_first_triangle`, `accel_owners`).
    geometry: Vec<HalBuffer>,
    /// Instances in the TLAS (those whose unit has a BLAS and whose transform is finite).
    instance_count: usize,
    /// What the last update replaced, and its staging and scratch memory: destroyed at the
    /// next update or on drop, once the device is idle (the build's command buffer is
    /// submitted by the caller, with the frame).
    retired: HalObjects,
}

impl RtAccel {
    /// Instances in the TLAS (those whose unit has a BLAS and whose transform is finite).
    pub fn instance_count(&self) -> usize {
        self.instance_count
    }
}

/// The custom data of the merged layout's one instance (`MERGED_INSTANCE` in
/// `shaders/trace/rt_pipeline.wgsl`).
const MERGED_INSTANCE: u32 = 0xFF_FFFF;

/// One geometry of a BLAS: a range of the packed triangles, opaque or alpha-tested.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Geometry {
    first: u32,
    count: u32,
    opaque: bool,
}

/// Every unit's triangles packed into one position and one index array (indices already
/// offset to the packed positions), which the BLAS builds read and so do the hit shaders.
struct Packed {
    positions: Vec<[f32; 3]>,
    indices: Vec<u32>,
    /// Per unit, its BLAS's geometries (`None`: no valid triangle, no BLAS).
    spans: Vec<Option<Vec<Geometry>>>,
    /// The merged layout: each merged triangle's instance and primitive (bit 31: mirrored).
    owners: Vec<[u32; 2]>,
    /// `accel_first_triangle`: per scene instance its unit's first triangle; merged, per
    /// geometry of the one BLAS its first triangle.
    first_triangles: Vec<u32>,
}

/// Packs the scene's triangles (see [`Packed`]). Two levels: a unit's one geometry is
/// alpha-tested when any instance of it is (its opaque instances are forced opaque in the
/// TLAS). Merged: opaque triangles first, then alpha-tested ones, as two geometries.
fn pack(scene: &Scene, unit_meshes: &[usize], unit_of_instance: &dyn Fn(usize) -> usize, merged: bool) -> Packed {
    let mut packed = Packed { positions: Vec::new(), indices: Vec::new(), spans: Vec::new(), owners: Vec::new(), first_triangles: Vec::new() };
    if merged {
        // One unit: every instance's triangles in world space (`layout::merge_instances`),
        // mirrored instances' triangles wound back so that facing stays the object-space
        // facing the other layouts report and cull by.
        let (mesh, origin) = super::layout::merge_instances(scene);
        let Some((p, i)) = super::bvh::driver_triangles(&mesh) else {
            packed.spans.push(None);
            packed.spans.resize(unit_meshes.len(), None);
            return packed;
        };
        let alpha: Vec<bool> = (0..scene.instances().len()).map(|i| alpha_tested(scene, i)).collect();
        let mut geometries = Vec::new();
        for opaque in [true, false] {
            let first = (packed.indices.len() / 3) as u32;
            for (t, o) in origin.iter().enumerate().filter(|(_, o)| alpha[o.instance as usize] != opaque) {
                let tri = &i[3 * t..3 * t + 3];
                packed.indices.extend(if o.mirrored { [tri[0], tri[2], tri[1]] } else { [tri[0], tri[1], tri[2]] });
                packed.owners.push([o.instance, o.prim | (o.mirrored as u32) << 31]);
            }
            let count = (packed.indices.len() / 3) as u32 - first;
            if count > 0 {
                geometries.push(Geometry { first, count, opaque });
                packed.first_triangles.push(first);
            }
        }
        packed.positions = p;
        packed.spans.push(Some(geometries));
    } else {
        let mut unit_alpha = vec![false; unit_meshes.len()];
        for i in (0..scene.instances().len()).filter(|&i| alpha_tested(scene, i)) {
            if let Some(a) = unit_alpha.get_mut(unit_of_instance(i)) {
                *a = true;
            }
        }
        for (u, &mesh) in unit_meshes.iter().enumerate() {
            let Some((p, i)) = scene.meshes().get(mesh).and_then(|m| super::bvh::driver_triangles(m)) else {
                packed.spans.push(None);
                continue;
            };
            let base = packed.positions.len() as u32;
            let geometry = Geometry { first: (packed.indices.len() / 3) as u32, count: (i.len() / 3) as u32, opaque: !unit_alpha[u] };
            packed.spans.push(Some(vec![geometry]));
            packed.positions.extend_from_slice(&p);
            packed.indices.extend(i.iter().map(|&x| x + base));
        }
        packed.first_triangles =
            (0..scene.instances().len()).map(|i| packed.spans.get(unit_of_instance(i)).and_then(|s| s.as_ref()).map_or(0, |g| g[0].first)).collect();
    }
    packed.spans.resize(unit_meshes.len(), None);
    packed
}

/// VkGeometryInstanceFlagBitsKHR: FORCE_OPAQUE.
const INSTANCE_FORCE_OPAQUE: u8 = 0x4;

/// A TLAS instance (VkAccelerationStructureInstanceKHR) of hit group 0, the one hit group,
/// every ray mask bit, and FORCE_OPAQUE when `force_opaque`; hal's `TlasInstance` has no
/// instance flags, so they are set in the bytes it writes (the top byte of the word at 52).
fn tlas_instance(d: &HalDevice, transform: [f32; 12], custom_data: u32, blas_address: u64, force_opaque: bool) -> Vec<u8> {
    let mut bytes = d.tlas_instance_to_bytes(hal::TlasInstance { transform, custom_data, mask: 0xff, blas_address, pipeline_intersection_data_offset: 0 });
    debug_assert_eq!(bytes.len(), 64, "VkAccelerationStructureInstanceKHR is 64 bytes");
    if force_opaque {
        bytes[55] |= INSTANCE_FORCE_OPAQUE;
    }
    bytes
}

impl RtAccel {
    /// No acceleration structure yet (the first [`RtAccel::update`] builds every unit).
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            device: device.clone(),
            blases: Vec::new(),
            blas_kinds: Vec::new(),
            tlas: None,
            geometry: Vec::new(),
            instance_count: 0,
            retired: HalObjects::default(),
        }
    }

    /// Brings the structures up to date with `scene`: units (`unit_meshes[u]` is unit `u`'s
    /// mesh) listed in `changed` get a new BLAS, the TLAS and the geometry arrays are made
    /// again. Returns the number of BLAS built and the build's command buffer, which the caller
    /// submits before any command buffer that traces (the executor between the `Accel` node's
    /// timestamps); what the build replaced is destroyed at the next update, once the device
    /// is idle.
    pub fn update(
        &mut self,
        scene: &Scene,
        unit_meshes: &[usize],
        unit_of_instance: &dyn Fn(usize) -> usize,
        changed: &[usize],
        merged: bool,
    ) -> Result<(usize, wgpu::CommandBuffer), RuntimeError> {
        // Custom data has 24 bits, and the largest value marks the merged layout's instance.
        const MAX_CUSTOM_DATA: usize = MERGED_INSTANCE as usize - 1;
        if scene.instances().len() > MAX_CUSTOM_DATA {
            return Err(RuntimeError::Gpu(format!(
                "scene `{}` has {} instances; the rt-pipeline back-end identifies instances in 24 bits (at most {MAX_CUSTOM_DATA}); use --backend compute",
                scene.name(),
                scene.instances().len()
            )));
        }
        let device = self.device.clone();
        // The previous build has run: the frames that used what it replaced were waited for.
        let mut previous = std::mem::take(&mut self.retired);
        previous.destroy(&device);
        let Packed { positions, indices, spans, owners, first_triangles } = pack(scene, unit_meshes, unit_of_instance, merged);
        let mut retired = HalObjects::default();
        let mut fresh = HalObjects::default();
        let mut blases = std::mem::take(&mut self.blases);
        // Units gone (meshes or instances removed): their BLAS are retired with the rest.
        if blases.len() > unit_meshes.len() {
            retired.accels.extend(blases.drain(unit_meshes.len()..).flatten());
        }
        blases.resize_with(unit_meshes.len(), || None);
        let mut rebuild: Vec<usize> = changed.iter().copied().filter(|&u| u < unit_meshes.len()).collect();
        // A unit with geometry but no BLAS (an earlier failed update) is built too, and so is
        // one whose geometries changed opacity (an instance's material changed alpha mode).
        let kinds = |g: &Option<Vec<Geometry>>| g.as_ref().map(|g| g.iter().map(|g| (g.count, g.opaque)).collect::<Vec<_>>());
        let mut blas_kinds = std::mem::take(&mut self.blas_kinds);
        blas_kinds.resize(unit_meshes.len(), None);
        rebuild.extend(
            (0..unit_meshes.len()).filter(|&u| (blases[u].is_none() || blas_kinds[u] != kinds(&spans[u])) && spans[u].is_some() && !changed.contains(&u)),
        );
        let mut instance_count = 0;
        let mut new_tlas = None;
        let commands = record_raw(&device, "rt-pipeline acceleration structures", |d, enc| {
            let align = alignments(d);
            let geometry_use = wgpu::BufferUses::BOTTOM_LEVEL_ACCELERATION_STRUCTURE_INPUT | wgpu::BufferUses::STORAGE_READ_ONLY;
            fresh.buffers.push(device_buffer(d, enc, &mut retired, "rt positions", bytemuck::cast_slice(&positions), geometry_use)?);
            fresh.buffers.push(device_buffer(d, enc, &mut retired, "rt indices", bytemuck::cast_slice(&indices), geometry_use)?);
            fresh.buffers.push(device_buffer(
                d,
                enc,
                &mut retired,
                "rt first triangles",
                bytemuck::cast_slice(&first_triangles),
                wgpu::BufferUses::STORAGE_READ_ONLY,
            )?);
            fresh.buffers.push(device_buffer(d, enc, &mut retired, "rt triangle owners", bytemuck::cast_slice(&owners), wgpu::BufferUses::STORAGE_READ_ONLY)?);
            // The copies above land before the builds read them.
            memory_barrier(d, enc, vk_all_commands(), vk_rt_and_build());
            let (pos_buf, idx_buf) = (&fresh.buffers[0], &fresh.buffers[1]);
            let flags = hal::AccelerationStructureBuildFlags::PREFER_FAST_TRACE;
            let entries: Vec<(usize, hal::AccelerationStructureEntries<HalBuffer>)> = rebuild
                .iter()
                .filter_map(|&u| {
                    // Alpha-tested geometry is built without OPAQUE: the any-hit shader runs on it, once a
                    // primitive (a transmittance ray takes each BLEND surface out once).
                    let geometry = |g: &Geometry| hal::AccelerationStructureTriangles {
                        vertex_buffer: Some(pos_buf),
                        vertex_format: wgpu::VertexFormat::Float32x3,
                        first_vertex: 0,
                        vertex_count: positions.len() as u32,
                        vertex_stride: 12,
                        indices: Some(hal::AccelerationStructureTriangleIndices {
                            format: wgpu::IndexFormat::Uint32,
                            buffer: Some(idx_buf),
                            offset: g.first * 12,
                            count: g.count * 3,
                        }),
                        transform: None,
                        flags: if g.opaque {
                            hal::AccelerationStructureGeometryFlags::OPAQUE
                        } else {
                            hal::AccelerationStructureGeometryFlags::NO_DUPLICATE_ANY_HIT_INVOCATION
                        },
                    };
                    Some((u, hal::AccelerationStructureEntries::Triangles(spans[u].as_ref()?.iter().map(geometry).collect())))
                })
                .collect();
            // Units rebuilt without geometry lose their BLAS.
            for &u in &rebuild {
                if spans[u].is_none() {
                    if let Some(old) = blases[u].take() {
                        retired.accels.push(old);
                    }
                }
            }
            let mut made = Vec::new();
            let mut scratch_offsets = Vec::new();
            let mut scratch_size = 0u64;
            for (_, e) in &entries {
                // SAFETY: a size query and the creation of an acceleration structure over
                // buffers made above; nothing is recorded yet.
                let sizes = unsafe { d.get_acceleration_structure_build_sizes(&hal::GetAccelerationStructureBuildSizesDescriptor { entries: e, flags }) };
                // SAFETY: a new acceleration structure of the size just queried; it is built
                // below and destroyed through `HalObjects` or `RtAccel::drop`.
                let accel = unsafe {
                    d.create_acceleration_structure(&hal::AccelerationStructureDescriptor {
                        label: Some("rt blas"),
                        size: sizes.acceleration_structure_size,
                        format: hal::AccelerationStructureFormat::BottomLevel,
                        allow_compaction: false,
                    })
                }
                .map(count_made)
                .map_err(|e| hal_error("creating a BLAS", e))?;
                made.push(accel);
                scratch_offsets.push(scratch_size);
                scratch_size = (scratch_size + sizes.build_scratch_size).next_multiple_of(align.scratch_alignment);
            }
            if !entries.is_empty() {
                // SAFETY: a device-local scratch buffer for the builds below.
                let scratch = unsafe {
                    d.create_buffer(&hal::BufferDescriptor {
                        label: Some("rt blas scratch"),
                        size: scratch_size.max(align.scratch_alignment),
                        usage: wgpu::BufferUses::ACCELERATION_STRUCTURE_SCRATCH,
                        memory_flags: hal::MemoryFlags::empty(),
                    })
                }
                .map(count_made)
                .map_err(|e| hal_error("creating BLAS scratch memory", e))?;
                let descriptors: Vec<hal::BuildAccelerationStructureDescriptor<HalBuffer, HalAccel>> = entries
                    .iter()
                    .zip(&made)
                    .zip(&scratch_offsets)
                    .map(|(((_, e), a), &offset)| hal::BuildAccelerationStructureDescriptor {
                        entries: e,
                        mode: hal::AccelerationStructureBuildMode::Build,
                        flags,
                        source_acceleration_structure: None,
                        destination_acceleration_structure: a,
                        scratch_buffer: &scratch,
                        scratch_buffer_offset: offset,
                    })
                    .collect();
                // SAFETY: each BLAS is written once, each with its own scratch range; the
                // inputs were copied before the barrier above.
                unsafe { enc.build_acceleration_structures(descriptors.len() as u32, descriptors) };
                retired.buffers.push(scratch);
            }
            for ((u, _), accel) in entries.iter().zip(made) {
                if let Some(old) = blases[*u].replace(accel) {
                    retired.accels.push(old);
                }
                blas_kinds[*u] = kinds(&spans[*u]);
            }
            // The TLAS: one instance per scene instance whose unit has a BLAS and whose
            // transform is finite.
            let mut instance_bytes = Vec::new();
            if let (true, Some(Some(blas))) = (merged, blases.first()) {
                // SAFETY: the address of a BLAS made by this device and alive.
                let blas_address = unsafe { d.get_acceleration_structure_device_address(blas) };
                let identity = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
                // Opacity per geometry (opaque and alpha-tested triangles apart).
                instance_bytes.extend(tlas_instance(d, identity, MERGED_INSTANCE, blas_address, false));
                instance_count += 1;
            }
            for (i, inst) in scene.instances().iter().enumerate().filter(|_| !merged) {
                let Some(Some(blas)) = blases.get(unit_of_instance(i)) else { continue };
                if super::bvh::instance_transform(&inst.transform).is_none() {
                    continue;
                }
                let m = inst.transform;
                let rows = [0, 1, 2].map(|r| [m.x_axis[r], m.y_axis[r], m.z_axis[r], m.w_axis[r]]);
                // SAFETY: the address of a BLAS made by this device and alive.
                let blas_address = unsafe { d.get_acceleration_structure_device_address(blas) };
                // An opaque instance of a BLAS that alpha-tested instances share is forced
                // opaque: the any-hit shader runs only for alpha-tested instances.
                instance_bytes.extend(tlas_instance(d, bytemuck::cast(rows), i as u32, blas_address, !alpha_tested(scene, i)));
                instance_count += 1;
            }
            let instance_buffer =
                device_buffer(d, enc, &mut retired, "rt instances", &instance_bytes, wgpu::BufferUses::TOP_LEVEL_ACCELERATION_STRUCTURE_INPUT)?;
            // The BLAS builds and the instance copy before the TLAS build.
            memory_barrier(d, enc, vk_rt_and_build(), vk_rt_and_build());
            let tlas_entries = hal::AccelerationStructureEntries::Instances(hal::AccelerationStructureInstances {
                buffer: Some(&instance_buffer),
                offset: 0,
                count: instance_count as u32,
            });
            // SAFETY: as for the BLAS: a size query, the creation, and one build with its own
            // scratch buffer, recorded after the barrier that orders it after the BLAS builds.
            unsafe {
                let sizes = d.get_acceleration_structure_build_sizes(&hal::GetAccelerationStructureBuildSizesDescriptor { entries: &tlas_entries, flags });
                let tlas = d
                    .create_acceleration_structure(&hal::AccelerationStructureDescriptor {
                        label: Some("rt tlas"),
                        size: sizes.acceleration_structure_size,
                        format: hal::AccelerationStructureFormat::TopLevel,
                        allow_compaction: false,
                    })
                    .map(count_made)
                    .map_err(|e| hal_error("creating the TLAS", e))?;
                let scratch = d
                    .create_buffer(&hal::BufferDescriptor {
                        label: Some("rt tlas scratch"),
                        size: sizes.build_scratch_size.max(align.scratch_alignment),
                        usage: wgpu::BufferUses::ACCELERATION_STRUCTURE_SCRATCH,
                        memory_flags: hal::MemoryFlags::empty(),
                    })
                    .map(count_made)
                    .map_err(|e| hal_error("creating TLAS scratch memory", e))?;
                enc.build_acceleration_structures(
                    1,
                    std::iter::once(hal::BuildAccelerationStructureDescriptor {
                        entries: &tlas_entries,
                        mode: hal::AccelerationStructureBuildMode::Build,
                        flags,
                        source_acceleration_structure: None,
                        destination_acceleration_structure: &tlas,
                        scratch_buffer: &scratch,
                        scratch_buffer_offset: 0,
                    }),
                );
                new_tlas = Some(tlas);
                retired.buffers.push(scratch);
            }
            retired.buffers.push(instance_buffer);
            Ok(())
        });
        let built = rebuild.iter().filter(|&&u| spans[u].is_some()).count();
        match commands {
            Ok(commands) => {
                retired.accels.extend(self.tlas.take());
                retired.buffers.append(&mut self.geometry);
                self.tlas = new_tlas;
                self.geometry = fresh.buffers.drain(..).collect();
                self.blases = blases;
                self.blas_kinds = blas_kinds;
                self.instance_count = instance_count;
                self.retired = retired;
                Ok((built, commands))
            }
            Err(e) => {
                // Nothing was submitted. The old TLAS may refer to BLAS replaced above, so
                // everything goes, old and new: with no TLAS, binding fails ("not built") until
                // an update succeeds, and the next update builds every unit.
                fresh.accels.extend(new_tlas);
                fresh.accels.extend(blases.into_iter().flatten());
                fresh.accels.extend(self.tlas.take());
                fresh.buffers.append(&mut self.geometry);
                self.instance_count = 0;
                fresh.destroy(&device);
                retired.destroy(&device);
                Err(e)
            }
        }
    }

    /// The number of BLAS geometries built without the OPAQUE flag (alpha-tested triangles,
    /// the only ones the any-hit shader runs on); 0 for an opaque scene.
    pub fn non_opaque_geometries(&self) -> usize {
        self.blases.iter().zip(&self.blas_kinds).filter(|(b, _)| b.is_some()).flat_map(|(_, k)| k.iter().flatten()).filter(|(_, opaque)| !opaque).count()
    }

    /// The trace module's bindings of [`RtAccel::geometry`], in its order; with `accel_tlas`,
    /// the bindings [`RtPass::bind_accel`] takes from the `RtAccel` itself.
    const GEOMETRY_BINDINGS: [&'static str; 4] = ["accel_positions", "accel_indices", "accel_first_triangle", "accel_owners"];

    /// Whether [`RtPass::bind_accel`] takes binding `name` from the `RtAccel` itself (not from
    /// the cache's buffers).
    fn owns_binding(name: &str) -> bool {
        name == "accel_tlas" || Self::GEOMETRY_BINDINGS.contains(&name)
    }

    fn tlas(&self) -> Option<&HalAccel> {
        self.tlas.as_ref()
    }
}

impl Drop for RtAccel {
    fn drop(&mut self) {
        let mut all = std::mem::take(&mut self.retired);
        all.buffers.append(&mut self.geometry);
        all.accels.extend(self.tlas.take());
        all.accels.extend(self.blases.drain(..).flatten());
        all.destroy(&self.device);
    }
}

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
        if !module.module.entry_points.iter().any(|e| e.name == entry && e.stage == naga::ShaderStage::RayGeneration) {
            return Err(RuntimeError::Gpu(format!("pass {label}: `{entry}` is not a ray-generation entry point")));
        }
        let group_count = bindings.iter().map(|b| b.group + 1).max().unwrap_or(0).max(accel_group + 1);
        let mut objects = HalObjects::default();
        let mut groups = Vec::new();
        let mut pipeline_layout = 0;
        let mut pipeline = 0;
        let mut sbt = 0;
        let mut regions = [(0, 0); 3];
        let mut staging = HalObjects::default();
        // Per group, its layout's entries in order (the any-hit module's bindings follow them).
        let layout_entries: Vec<Vec<wgpu::BindGroupLayoutEntry>> = (0..group_count)
            .map(|g| bindings.iter().filter(|b| b.group == g).map(|b| wgpu::BindGroupLayoutEntry { visibility: RT_STAGES, ..b.entry }).collect())
            .collect();
        let any_hit_words = any_hit::any_hit_spirv(&module.module, &module.info, &any_hit, any_hit::binding_map(&layout_entries))
            .map_err(|e| RuntimeError::Gpu(format!("pass {label}: the any-hit shader: {e}")))?;
        let made = record_raw(device, "rt-pipeline shader binding table", |d, enc| {
            for entries in &layout_entries {
                // SAFETY: a layout from plain entries.
                let layout = unsafe {
                    d.create_bind_group_layout(&hal::BindGroupLayoutDescriptor { label: Some(label), flags: hal::BindGroupLayoutFlags::empty(), entries })
                }
                .map(count_made)
                .map_err(|e| hal_error("creating a bind group layout", e))?;
                objects.bind_group_layouts.push(layout);
                groups.push((objects.bind_group_layouts.len() - 1, None));
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
            pipeline_layout = objects.pipeline_layouts.len() - 1;
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
            objects.shader_modules.push(shader);
            // SAFETY: SPIR-V written by naga from the same validated module, with the
            // pipeline layout's bindings, and patched (any_hit.rs); the validation layer checks
            // it when the pipeline is made.
            let any_hit_shader = unsafe {
                d.create_shader_module(
                    &hal::ShaderModuleDescriptor { label: Some(label), runtime_checks: crate::gpu_util::ShaderOrigin::TracePass.checks() },
                    hal::ShaderInput::SpirV(&any_hit_words),
                )
            }
            .map(count_made)
            .map_err(|e| hal_error("compiling the any-hit shader", e))?;
            objects.shader_modules.push(any_hit_shader);
            let stage = |module, entry_point| hal::ProgrammableStage { module, entry_point, constants, zero_initialize_workgroup_memory: true };
            let (naga_stages, spirv_stage) = (&objects.shader_modules[0], &objects.shader_modules[1]);
            // One hit group for every instance: the any-hit shader runs only on non-opaque
            // geometry (alpha-tested instances, RtAccel::update), so opaque hits never reach it.
            let hit_groups = [hal::RayObjectIntersectionState { closest_hit: stage(naga_stages, &closest), any_hit: Some(stage(spirv_stage, &any_hit)) }];
            // SAFETY: stages of a module made above, a layout made above; recursion depth 1:
            // hit and miss shaders trace no rays.
            let p = unsafe {
                d.create_ray_tracing_pipeline(&hal::RayTracingPipelineDescriptor {
                    label: Some(label),
                    layout: &objects.pipeline_layouts[pipeline_layout],
                    ray_generation: stage(naga_stages, entry),
                    miss: stage(naga_stages, &miss),
                    intersection: &hit_groups,
                    max_recursion_depth: 1,
                    cache: None,
                })
            }
            .map(count_made)
            .map_err(|e| hal_error("creating the ray-tracing pipeline", e))?;
            objects.pipelines.push(p);
            pipeline = objects.pipelines.len() - 1;
            // The shader binding table: group 0 ray generation, 1 miss, 2 the hit group.
            let align = alignments(d);
            // SAFETY: the pipeline was made above with three groups.
            let handles = unsafe { d.get_raytracing_pipeline_group_data(&objects.pipelines[pipeline], 0..3) }
                .map_err(|e| hal_error("reading shader group handles", e))?;
            let handle = handles.len() as u64 / 3;
            if handle != align.handle_size {
                return Err(RuntimeError::Gpu(format!(
                    "rt-pipeline back-end: shader group handles of {handle} bytes, the device reports {}",
                    align.handle_size
                )));
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
            regions = [(start, stride), (start + region, stride), (start + 2 * region, stride)];
            objects.buffers.push(table_buffer);
            sbt = objects.buffers.len() - 1;
            upload(d, enc, &mut staging, label, &objects.buffers[sbt], &table)?;
            Ok(())
        });
        let commands = match made {
            Ok(c) => c,
            Err(e) => {
                objects.destroy(device);
                staging.destroy(device);
                return Err(e);
            }
        };
        queue.submit([commands]);
        staging.destroy(device);
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
        // The Vulkan handles of the wgpu objects, one guard at a time (wgpu-core forbids
        // holding two of its hal guards at once).
        let raw_buffer = |buffer: &wgpu::Buffer| -> Result<ash::vk::Buffer, RuntimeError> {
            // SAFETY: only the handle is read; the wgpu buffer outlives the bind group (kept in
            // `self.bindings`, or the cache's counters owned by the caller).
            unsafe { buffer.as_hal::<Vk>().map(|b| b.raw_handle()) }.ok_or_else(|| hal_error("binding", "not a Vulkan buffer"))
        };
        let raw_image = |texture: &wgpu::Texture| -> Result<ash::vk::Image, RuntimeError> {
            // SAFETY: as above, for the texture's image.
            unsafe { texture.as_hal::<Vk>().map(|t| t.raw_handle()) }.ok_or_else(|| hal_error("binding", "not a Vulkan texture"))
        };
        let mut images: Vec<(ash::vk::Image, wgpu::Texture, wgpu::TextureViewDimension, wgpu::TextureUses)> = Vec::new();
        let mut buffers: Vec<ash::vk::Buffer> = Vec::new();
        for b in &bindings {
            match &b.resource {
                RtResource::Texture { texture, uses, .. } => {
                    let dimension = match b.entry.ty {
                        wgpu::BindingType::Texture { view_dimension, .. } | wgpu::BindingType::StorageTexture { view_dimension, .. } => view_dimension,
                        _ => wgpu::TextureViewDimension::D2,
                    };
                    images.push((raw_image(texture)?, texture.clone(), dimension, *uses));
                }
                RtResource::Textures(list) => {
                    for (t, _) in list {
                        images.push((raw_image(t)?, t.clone(), wgpu::TextureViewDimension::D2, wgpu::TextureUses::RESOURCE));
                    }
                }
                RtResource::Buffer { buffer, .. } => buffers.push(raw_buffer(buffer)?),
                RtResource::Accel(name) if !RtAccel::owns_binding(name) => {
                    let (_, cache) = accel.ok_or_else(|| hal_error("binding", "the trace module's group needs the acceleration structure"))?;
                    let (buffer, _, _) = cache(name).ok_or_else(|| RuntimeError::Gpu(format!("the rt-pipeline back-end has no binding `{name}`")))?;
                    buffers.push(raw_buffer(&buffer)?);
                }
                RtResource::Sampler(_) | RtResource::Accel(_) => {}
            }
        }
        with_hal(&self.device, |d| {
            let mut extra = HalObjects::default();
            let made = (|| -> Result<hal::vulkan::BindGroup, RuntimeError> {
                for (image, texture, dimension, uses) in &images {
                    let size = texture.size();
                    // SAFETY: `image` is the wgpu texture's, described as wgpu made it; the hal
                    // texture neither owns the image nor its memory (a no-op drop callback,
                    // external memory) and is dropped once the view is made. The view is ours
                    // and destroyed with the bind group (`HalObjects`).
                    let view = unsafe {
                        let hal_texture = d.texture_from_raw(
                            *image,
                            &hal::TextureDescriptor {
                                label: None,
                                size,
                                mip_level_count: texture.mip_level_count(),
                                sample_count: texture.sample_count(),
                                dimension: texture.dimension(),
                                format: texture.format(),
                                usage: *uses,
                                memory_flags: hal::MemoryFlags::empty(),
                                view_formats: Vec::new(),
                            },
                            Some(Box::new(|| {})),
                            hal::vulkan::TextureMemory::External,
                        );
                        d.create_texture_view(
                            &hal_texture,
                            &hal::TextureViewDescriptor {
                                label: Some(&self.label),
                                format: texture.format(),
                                dimension: *dimension,
                                usage: *uses,
                                range: wgpu::ImageSubresourceRange::default(),
                            },
                        )
                    }
                    .map(count_made)
                    .map_err(|e| hal_error("creating a texture view", e))?;
                    extra.texture_views.push(view);
                }
                // SAFETY: handles of live wgpu buffers, not owned by the hal objects (which are
                // dropped, never destroyed, after the bind group is made).
                let hal_wgpu_buffers: Vec<HalBuffer> = buffers.iter().map(|&b| unsafe { HalBuffer::from_raw(b) }).collect();
                for b in &bindings {
                    if let RtResource::Sampler(desc) = &b.resource {
                        // SAFETY: a sampler from a plain descriptor, destroyed with the group.
                        let sampler = unsafe {
                            d.create_sampler(&hal::SamplerDescriptor {
                                label: desc.label,
                                address_modes: [desc.address_mode_u, desc.address_mode_v, desc.address_mode_w],
                                mag_filter: desc.mag_filter,
                                min_filter: desc.min_filter,
                                mipmap_filter: desc.mipmap_filter,
                                lod_clamp: desc.lod_min_clamp..desc.lod_max_clamp,
                                compare: desc.compare,
                                anisotropy_clamp: desc.anisotropy_clamp,
                                border_color: desc.border_color,
                            })
                        }
                        .map(count_made)
                        .map_err(|e| hal_error("creating a sampler", e))?;
                        extra.samplers.push(sampler);
                    }
                }
                let mut hal_buffers = Vec::new();
                let mut hal_textures = Vec::new();
                let mut hal_accels = Vec::new();
                let mut entries = Vec::new();
                let (mut vi, mut bi, mut si) = (0, 0, 0);
                for b in &bindings {
                    let (resource_index, count) = match &b.resource {
                        RtResource::Texture { uses, .. } => {
                            hal_textures.push(hal::TextureBinding { view: &extra.texture_views[vi], usage: *uses });
                            vi += 1;
                            (hal_textures.len() - 1, 1)
                        }
                        RtResource::Textures(list) => {
                            let start = hal_textures.len();
                            for _ in list {
                                hal_textures.push(hal::TextureBinding { view: &extra.texture_views[vi], usage: wgpu::TextureUses::RESOURCE });
                                vi += 1;
                            }
                            (start, list.len())
                        }
                        RtResource::Buffer { offset, size, .. } => {
                            // Offset and size as the executor binds the same buffer for a compute pass.
                            hal_buffers.push(hal::BufferBinding::new_unchecked(&hal_wgpu_buffers[bi], *offset, *size));
                            bi += 1;
                            (hal_buffers.len() - 1, 1)
                        }
                        RtResource::Sampler(_) => {
                            si += 1;
                            (si - 1, 1)
                        }
                        RtResource::Accel(name) => {
                            let (rt, cache) = accel.ok_or_else(|| hal_error("binding", "the trace module's group needs the acceleration structure"))?;
                            match name.as_str() {
                                "accel_tlas" => {
                                    hal_accels.push(rt.tlas().ok_or_else(|| hal_error("binding", "the TLAS is not built"))?);
                                    (hal_accels.len() - 1, 1)
                                }
                                other => {
                                    let buffer = match RtAccel::GEOMETRY_BINDINGS.iter().position(|n| *n == other) {
                                        Some(i) => {
                                            let buffer = rt.geometry.get(i).ok_or_else(|| hal_error("binding", "the geometry arrays are not built"))?;
                                            hal::BufferBinding::new_unchecked(buffer, 0, None)
                                        }
                                        // The cache's buffers (counters, alpha records), found above.
                                        None => {
                                            let (_, offset, size) = cache(other).expect("found when the handles were read");
                                            bi += 1;
                                            hal::BufferBinding::new_unchecked(&hal_wgpu_buffers[bi - 1], offset, size)
                                        }
                                    };
                                    hal_buffers.push(buffer);
                                    (hal_buffers.len() - 1, 1)
                                }
                            }
                        }
                    };
                    entries.push(hal::BindGroupEntry { binding: b.entry.binding, resource_index: resource_index as u32, count: count as u32 });
                }
                let sampler_refs: Vec<&hal::vulkan::Sampler> = extra.samplers.iter().collect();
                // SAFETY: every resource outlives the bind group (wgpu objects kept in
                // `self.bindings` or by the caller, views and samplers in `extra`, the
                // acceleration structures in the caller's `RtAccel`), and every entry matches
                // its layout entry (same list, same order).
                unsafe {
                    d.create_bind_group(&hal::BindGroupDescriptor {
                        label: Some(&self.label),
                        layout: &self.objects.bind_group_layouts[self.groups[g as usize].0],
                        buffers: &hal_buffers,
                        samplers: &sampler_refs,
                        textures: &hal_textures,
                        entries: &entries,
                        acceleration_structures: &hal_accels,
                        external_textures: &[],
                    })
                }
                .map(count_made)
                .map_err(|e| hal_error("creating a bind group", e))
            })();
            match made {
                Ok(bg) => Ok((bg, extra)),
                Err(e) => {
                    destroyed(extra.texture_views.len() + extra.samplers.len());
                    // SAFETY: objects made above for a bind group that was not made.
                    unsafe {
                        for v in extra.texture_views.drain(..) {
                            d.destroy_texture_view(v);
                        }
                        for s in extra.samplers.drain(..) {
                            d.destroy_sampler(s);
                        }
                    }
                    Err(e)
                }
            }
        })
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
