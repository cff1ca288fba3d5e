//! The compute back-end's arrays packed into one storage buffer, for devices that allow fewer
//! storage buffers per shader stage than a trace pass with separate arrays binds (a browser's
//! WebGPU: 8 by default; `runtime::gpu::Gpu::packed_accel_arrays`). The cache keeps its four
//! arrays and the alpha words as they are (built, uploaded, refitted on the GPU) and copies
//! them here, on the GPU, after every update that wrote them: `shaders/trace/compute_arrays_packed.wgsl` reads
//! them. Word 0 (16 bytes) holds where each array starts, in 16-byte words: instances, BLAS
//! nodes, triangles, alpha words; the TLAS nodes start at word 1.

use crate::error::RuntimeError;

/// The packed buffer and the layout last written into its header.
#[derive(Default)]
pub(crate) struct PackedArrays {
    buffer: Option<wgpu::Buffer>,
    bases: [u32; 4],
}

/// Bytes of the header.
const HEADER: u64 = 16;

impl PackedArrays {
    /// The packed buffer, once [`PackedArrays::record`] made it.
    pub fn buffer(&self) -> Option<&wgpu::Buffer> {
        self.buffer.as_ref()
    }

    /// Records the copies of `arrays` (TLAS nodes, instances, BLAS nodes, triangles, alpha
    /// words: whole buffers, each a multiple of 16 bytes) into the packed buffer when `written`
    /// (they changed since the last copy) or a larger buffer was needed. Returns whether the
    /// buffer was replaced (bind groups made before must be made again). Arrays that together
    /// exceed the device's storage binding size are an error naming both sizes.
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        arrays: [&wgpu::Buffer; 5],
        written: bool,
    ) -> Result<bool, RuntimeError> {
        let mut starts = [0u64; 5];
        let mut end = HEADER;
        for (start, array) in starts.iter_mut().zip(arrays) {
            *start = end;
            end += array.size().next_multiple_of(16);
        }
        let limit = device.limits().max_storage_buffer_binding_size;
        if end > limit {
            return Err(RuntimeError::Gpu(format!(
                "the scene's acceleration structure needs {:.1} MiB in one storage buffer (its arrays are packed on this device, which binds {} storage buffers per stage); the device binds at most {:.1} MiB: use a smaller scene",
                end as f64 / 1048576.0,
                device.limits().max_storage_buffers_per_shader_stage,
                limit as f64 / 1048576.0
            )));
        }
        let replaced = self.buffer.as_ref().is_none_or(|b| b.size() < end);
        if !written && !replaced {
            return Ok(false);
        }
        if replaced {
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accel packed arrays"),
                size: end,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let Some(buffer) = &self.buffer else { unreachable!("made above") };
        // Words of 16 bytes: a u32 reaches 64 GiB, past any device's buffer size.
        let bases = [starts[1], starts[2], starts[3], starts[4]].map(|s| (s / 16) as u32);
        if replaced || bases != self.bases {
            queue.write_buffer(buffer, 0, bytemuck::cast_slice(&bases));
            self.bases = bases;
        }
        for (start, array) in starts.iter().zip(arrays) {
            encoder.copy_buffer_to_buffer(array, 0, buffer, *start, array.size());
        }
        Ok(replaced)
    }

    /// Bytes of the packed buffer (0 before the first [`PackedArrays::record`]).
    pub fn size(&self) -> u64 {
        self.buffer.as_ref().map_or(0, wgpu::Buffer::size)
    }
}
