//! Reading the GPU back: the graph output and any kept texture (as RGBA8 or f32 texels), the
//! debug counters, a whole texture's texels; and the atomic PNG and OpenEXR writes of an image.

use super::{Executor, Physical};
use crate::error::RuntimeError;
#[cfg(not(target_arch = "wasm32"))]
use crate::gpu_util::map_read;
use crate::gpu_util::{map_read_async, readback_buffer};

use crate::graph::compile::ResourceId;
use crate::graph::desc::ResourceDecl;
use crate::runtime::gpu::Gpu;

impl Executor {
    /// Reads back the graph output as tightly packed RGBA8 rows.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_output(&self, gpu: &Gpu) -> Result<image::RgbaImage, RuntimeError> {
        pollster::block_on(self.read_output_async(gpu))
    }

    /// [`Executor::read_output`] as a future (a browser's page shows the output through it).
    pub async fn read_output_async(&self, gpu: &Gpu) -> Result<image::RgbaImage, RuntimeError> {
        self.read_texture_rgba8_async(gpu, self.plan.output).await
    }

    /// Reads back any kept RGBA8 texture resource.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_texture_rgba8(&self, gpu: &Gpu, r: ResourceId) -> Result<image::RgbaImage, RuntimeError> {
        pollster::block_on(self.read_texture_rgba8_async(gpu, r))
    }

    /// [`Executor::read_texture_rgba8`] as a future.
    pub(crate) async fn read_texture_rgba8_async(&self, gpu: &Gpu, r: ResourceId) -> Result<image::RgbaImage, RuntimeError> {
        let (w, h, format, data) = self.read_texture_bytes(gpu, r).await?;
        if format.bytes_per_texel() != 4 || format.is_uint() {
            return Err(RuntimeError::Gpu(format!("{} is {format:?}, not an 8-bit RGBA texture", self.plan.resources[r].name)));
        }
        image::RgbaImage::from_raw(w, h, data).ok_or_else(|| RuntimeError::Gpu("readback size mismatch".into()))
    }

    /// Reads back any kept colour texture as RGBA f32 per texel (row-major; missing channels
    /// 0, alpha 1); float, half and 8-bit unorm formats.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_texture_f32(&self, gpu: &Gpu, r: ResourceId) -> Result<(u32, u32, Vec<[f32; 4]>), RuntimeError> {
        let (w, h, format, data) = pollster::block_on(self.read_texture_bytes(gpu, r))?;
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
    async fn read_texture_bytes(&self, gpu: &Gpu, r: ResourceId) -> Result<(u32, u32, crate::graph::desc::Format, Vec<u8>), RuntimeError> {
        let (w, h) = self.plan.resources[r].extent;
        let ResourceDecl::Texture(t) = &self.plan.resources[r].decl else {
            return Err(RuntimeError::Gpu(format!("{} is not a texture", self.plan.resources[r].name)));
        };
        let Physical::Texture(texture) = &self.slots[self.slot_of(r).ok_or_else(|| RuntimeError::Gpu("resource is not allocated".into()))?] else {
            return Err(RuntimeError::Gpu("resource is not a texture".into()));
        };
        Ok((w, h, t.format, read_texture_async(gpu, texture, t.format.bytes_per_texel() as u32).await?))
    }

    /// Reads the `debug_counters` buffer (shaders may count events into it).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_debug_counters(&self, gpu: &Gpu) -> Result<Vec<u32>, RuntimeError> {
        let size = crate::graph::builtins::DEBUG_COUNTER_COUNT as u64 * 4;
        let buf = readback_buffer(gpu.device(), "counter readback", size);
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.debug_counters, 0, &buf, 0, size);
        gpu.queue().submit([encoder.finish()]);
        let data = map_read(gpu.device(), buf.slice(..))?;
        let v = bytemuck::cast_slice::<u8, u32>(&data).to_vec();
        drop(data);
        buf.unmap();
        Ok(v)
    }
}

/// Reads back the whole of `texture` (`texel_bytes` bytes per texel; it needs `COPY_SRC`) as
/// tightly packed rows.
#[cfg(not(target_arch = "wasm32"))]
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, texel_bytes: u32) -> Result<Vec<u8>, RuntimeError> {
    pollster::block_on(read_texture_async(gpu, texture, texel_bytes))
}

/// [`read_texture`] as a future.
pub(crate) async fn read_texture_async(gpu: &Gpu, texture: &wgpu::Texture, texel_bytes: u32) -> Result<Vec<u8>, RuntimeError> {
    let (w, h) = (texture.width(), texture.height());
    let row = w * texel_bytes;
    let padded = row.div_ceil(256) * 256;
    let buf = readback_buffer(gpu.device(), "texture readback", padded as u64 * h as u64);
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo { buffer: &buf, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: Some(h) } },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    gpu.queue().submit([encoder.finish()]);
    let data = map_read_async(gpu.device(), buf.slice(..)).await?;
    let mut bytes = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        bytes.extend_from_slice(&data[y * padded as usize..y * padded as usize + row as usize]);
    }
    drop(data);
    buf.unmap();
    Ok(bytes)
}

#[cfg(not(target_arch = "wasm32"))]
/// Writes an image as PNG atomically (temporary file, then rename): a failed write never
/// leaves a truncated file behind.
pub fn write_png(path: &std::path::Path, img: &image::RgbaImage) -> Result<(), RuntimeError> {
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| RuntimeError::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    crate::util::write_atomic(path, &png).map_err(|source| RuntimeError::Output { path: path.to_path_buf(), source })
}

#[cfg(not(target_arch = "wasm32"))]
/// Writes `width` x `height` RGBA texels (row-major, as [`Executor::read_texture_f32`] gives
/// them) as an OpenEXR file of 32-bit float channels, atomically as [`write_png`] does.
pub fn write_exr(path: &std::path::Path, width: u32, height: u32, texels: &[[f32; 4]]) -> Result<(), RuntimeError> {
    let encode_error = |message: String| RuntimeError::Encode { path: path.to_path_buf(), message };
    let img = image::Rgba32FImage::from_raw(width, height, texels.iter().flatten().copied().collect())
        .ok_or_else(|| encode_error(format!("{} texels for a {width}x{height} image", texels.len())))?;
    let mut exr = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut exr), image::ImageFormat::OpenExr).map_err(|e| encode_error(e.to_string()))?;
    crate::util::write_atomic(path, &exr).map_err(|source| RuntimeError::Output { path: path.to_path_buf(), source })
}
