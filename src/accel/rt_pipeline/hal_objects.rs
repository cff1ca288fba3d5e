//! The wgpu-hal plumbing of the `rt-pipeline` back-end: the count of objects made through
//! wgpu-hal, the Vulkan hal device behind a wgpu device, hal command buffers recorded between
//! the two memory barriers of the module docs ([`super`]), the device's ray-tracing alignments,
//! [`HalObjects`] (destroyed once the device is idle) and device buffers filled by staged copies.

use crate::error::RuntimeError;
use std::num::NonZeroU64;
use wgpu::hal;
use wgpu::hal::{CommandEncoder as _, Device as _};

pub(super) type Vk = hal::api::Vulkan;
pub(super) type HalDevice = hal::vulkan::Device;
pub(super) type HalBuffer = hal::vulkan::Buffer;
pub(super) type HalAccel = hal::vulkan::AccelerationStructure;

/// Objects this module has made through wgpu-hal and not yet destroyed (tests check that it
/// returns to where it was once everything is dropped).
static LIVE_OBJECTS: std::sync::atomic::AtomicIsize = std::sync::atomic::AtomicIsize::new(0);

/// The number of objects made through wgpu-hal by this back-end and still alive.
pub fn live_hal_objects() -> isize {
    LIVE_OBJECTS.load(std::sync::atomic::Ordering::SeqCst)
}

/// Counts an object just made (see [`live_hal_objects`]).
pub(super) fn count_made<T>(object: T) -> T {
    LIVE_OBJECTS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    object
}

/// Counts `n` objects destroyed.
pub(super) fn destroyed(n: usize) {
    LIVE_OBJECTS.fetch_sub(n as isize, std::sync::atomic::Ordering::SeqCst);
}

pub(super) fn hal_error(what: &str, e: impl std::fmt::Display) -> RuntimeError {
    RuntimeError::Gpu(format!("rt-pipeline back-end: {what}: {e}"))
}

/// Runs `f` with the wgpu device's Vulkan hal device.
pub(super) fn with_hal<R>(device: &wgpu::Device, f: impl FnOnce(&HalDevice) -> Result<R, RuntimeError>) -> Result<R, RuntimeError> {
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
pub(super) fn record_raw(
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

pub(super) fn vk_all_commands() -> ash::vk::PipelineStageFlags {
    ash::vk::PipelineStageFlags::ALL_COMMANDS
}

pub(super) fn vk_rt_and_build() -> ash::vk::PipelineStageFlags {
    ash::vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR | ash::vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR | ash::vk::PipelineStageFlags::TRANSFER
}

/// A global memory barrier: every write of `src` stages visible to every access of `dst`.
pub(super) fn memory_barrier(
    device: &HalDevice,
    encoder: &mut hal::vulkan::CommandEncoder,
    src: ash::vk::PipelineStageFlags,
    dst: ash::vk::PipelineStageFlags,
) {
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
pub(super) struct Alignments {
    pub(super) handle_size: u64,
    pub(super) handle_alignment: u64,
    pub(super) base_alignment: u64,
    pub(super) scratch_alignment: u64,
}

pub(super) fn alignments(device: &HalDevice) -> Alignments {
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
pub(super) struct HalObjects {
    pub(super) buffers: Vec<HalBuffer>,
    pub(super) accels: Vec<HalAccel>,
    pub(super) bind_groups: Vec<hal::vulkan::BindGroup>,
    pub(super) bind_group_layouts: Vec<hal::vulkan::BindGroupLayout>,
    pub(super) pipeline_layouts: Vec<hal::vulkan::PipelineLayout>,
    pub(super) shader_modules: Vec<hal::vulkan::ShaderModule>,
    pub(super) pipelines: Vec<hal::vulkan::RayTracingPipeline>,
    pub(super) samplers: Vec<hal::vulkan::Sampler>,
    pub(super) texture_views: Vec<hal::vulkan::TextureView>,
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
    pub(super) fn destroy(&mut self, device: &wgpu::Device) {
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
pub(super) fn device_buffer(
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
pub(super) fn empty_device_buffer(d: &HalDevice, label: &str, size: u64, usage: wgpu::BufferUses) -> Result<HalBuffer, RuntimeError> {
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
pub(super) fn upload(
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
