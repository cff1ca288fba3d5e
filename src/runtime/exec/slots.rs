//! The plan's slots on the device: one texture or buffer per slot (labelled with the resources
//! it holds), the constant textures' texel, the built-in buffers every pass may bind, and the
//! texture, view or buffer a kept resource lives in (this frame: the textures of history pairs
//! trade places, `history`).

use super::{Executor, Physical};
use crate::error::RuntimeError;
use crate::gpu_util::storage_buffer;
use crate::graph::builtins;
use crate::graph::compile::{Plan, PlannedPass, ResourceId, Slot};
use crate::graph::desc::{PassKind, ResourceDecl, TextureDecl};
use crate::runtime::gpu::Gpu;
use crate::uniforms::FrameUniforms;

/// The label of slot `i`: the resources it holds and its size, so that an allocation error
/// names them (`slot 4: gbuffer.position, 2197 MiB`).
fn slot_label(plan: &Plan, i: usize) -> String {
    let slot = &plan.slots[i];
    let names: Vec<&str> = slot.members.iter().filter_map(|r| plan.resources.get(*r).map(|r| r.name.as_str())).collect();
    format!("slot {i}: {}, {}", names.join(" + "), crate::graph::compile::fmt_bytes(slot.bytes))
}

/// Whether a `Rust` pass reads or writes a resource of slot `s`: Rust code may use it in any
/// way its format allows.
fn used_by_rust_pass(plan: &Plan, s: &Slot) -> bool {
    let rust_passes = plan.passes.iter().filter(|p| p.kind == PassKind::Rust);
    rust_passes.flat_map(|p| p.reads.iter().chain(&p.writes)).any(|(_, r)| s.members.contains(r))
}

/// Whether a resource of slot `s` is a buffer declared `zeroed`.
fn has_zeroed_member(plan: &Plan, s: &Slot) -> bool {
    s.members.iter().any(|r| matches!(&plan.resources[*r].decl, ResourceDecl::Buffer(b) if b.zeroed))
}

/// The usages of a texture slot: those of its resources, read back by anyone (tests, the
/// viewer's pass inspector), written by copies where it is constant or traced into by the
/// rt-pipeline back-end; every usage its format allows where a Rust pass uses it.
fn texture_usage(plan: &Plan, s: &Slot, format: wgpu::TextureFormat, features: wgpu::Features) -> wgpu::TextureUsages {
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
    if used_by_rust_pass(plan, s) {
        let any = wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::RENDER_ATTACHMENT;
        usage |= any & format.guaranteed_format_features(features).allowed_usages;
    }
    usage
}

fn create_slot_texture(device: &wgpu::Device, plan: &Plan, i: usize, t: &TextureDecl) -> wgpu::Texture {
    let s = &plan.slots[i];
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&slot_label(plan, i)),
        size: wgpu::Extent3d { width: s.extent.0, height: s.extent.1, depth_or_array_layers: t.layers },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: t.format.to_wgpu(),
        usage: texture_usage(plan, s, t.format.to_wgpu(), device.features()),
        view_formats: &[],
    })
}

fn create_slot_buffer(device: &wgpu::Device, plan: &Plan, i: usize, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(&slot_label(plan, i)),
        size: size.max(4),
        // The rt-pipeline back-end zeroes what its traces write once through the
        // queue (RtPass::transition); a Rust pass may copy into its buffers; `zeroed` buffers
        // are cleared every frame (Executor::zero_buffers_written).
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | if plan.backend == crate::backend::Backend::RtPipeline || used_by_rust_pass(plan, &plan.slots[i]) || has_zeroed_member(plan, &plan.slots[i]) {
                wgpu::BufferUsages::COPY_DST
            } else {
                wgpu::BufferUsages::empty()
            },
        mapped_at_creation: false,
    })
}

impl Executor {
    /// One texture or buffer per slot of `plan`, constant textures holding their value.
    pub(super) fn allocate_slots(gpu: &Gpu, plan: &Plan) -> Result<Vec<Physical>, RuntimeError> {
        let device = gpu.device();
        let slots = plan
            .slots
            .iter()
            .enumerate()
            .map(|(i, s)| match &s.decl {
                ResourceDecl::Texture(t) => Physical::Texture(create_slot_texture(device, plan, i, t)),
                ResourceDecl::Accel => Physical::Accel,
                ResourceDecl::Buffer(b) => Physical::Buffer(create_slot_buffer(device, plan, i, b.size)),
            })
            .collect::<Vec<_>>();
        for (slot, physical) in plan.slots.iter().zip(&slots) {
            if let (Some(value), ResourceDecl::Texture(t), Physical::Texture(texture)) = (slot.constant, &slot.decl, physical) {
                let texel = t.format.encode_texel(value).ok_or_else(|| RuntimeError::Gpu(format!("a {:?} input cannot have a fallback value", t.format)))?;
                for layer in 0..t.layers {
                    gpu.queue().write_texture(
                        wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d { x: 0, y: 0, z: layer }, aspect: wgpu::TextureAspect::All },
                        &texel,
                        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(texel.len() as u32), rows_per_image: Some(1) },
                        wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                    );
                }
            }
        }
        Ok(slots)
    }

    /// The buffers behind the `frame` and `debug_counters` built-ins.
    pub(super) fn builtin_buffers(device: &wgpu::Device) -> (wgpu::Buffer, wgpu::Buffer) {
        let frame_uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let debug_counters = storage_buffer(device, "debug counters", builtins::DEBUG_COUNTER_COUNT as u64 * 4);
        (frame_uniforms, debug_counters)
    }

    /// The slot that holds resource `r` when the history pairs are `swapped` or not
    /// (`history`).
    pub(super) fn slot_at(&self, r: ResourceId, swapped: bool) -> Option<usize> {
        self.plan.resources.get(r)?.slot.map(|s| self.history.map(s, swapped))
    }

    /// The slot that holds resource `r` this frame (the frame being recorded, or the last one
    /// rendered).
    pub(super) fn slot_of(&self, r: ResourceId) -> Option<usize> {
        self.slot_at(r, self.history.swapped)
    }

    /// Whether `pass` binds a texture of a history pair (it then has a second set of bind
    /// groups).
    pub(super) fn binds_history(&self, pass: &PlannedPass) -> bool {
        pass.reads.iter().chain(&pass.writes).any(|(_, r)| self.plan.resources[*r].slot.is_some_and(|s| self.history.holds(s)))
    }

    /// A view of the texture that holds `r` this frame.
    pub(super) fn texture_view(&self, r: ResourceId) -> wgpu::TextureView {
        self.texture_view_at(r, self.history.swapped)
    }

    /// A view of the texture that holds `r` when the history pairs are `swapped` or not (of
    /// all its layers: a texture of several is viewed as an array).
    pub(super) fn texture_view_at(&self, r: ResourceId, swapped: bool) -> wgpu::TextureView {
        self.texture_at(r, swapped).create_view(&wgpu::TextureViewDescriptor::default())
    }

    /// The texture that holds `r` when the history pairs are `swapped` or not.
    fn texture_at(&self, r: ResourceId, swapped: bool) -> &wgpu::Texture {
        match &self.slots[self.slot_at(r, swapped).expect("kept resource has a slot")] {
            Physical::Texture(t) => t,
            Physical::Buffer(_) | Physical::Accel => unreachable!("texture resource mapped to a buffer slot"),
        }
    }

    /// A view of `r` as a render pass's attachment: array layer `layer` of a layered texture
    /// (the pass's `layer`, checked by the compiler), the texture itself otherwise.
    pub(super) fn attachment_view_at(&self, r: ResourceId, swapped: bool, layer: Option<u32>) -> wgpu::TextureView {
        let texture = self.texture_at(r, swapped);
        match layer.filter(|_| texture.depth_or_array_layers() > 1) {
            Some(layer) => texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            }),
            None => texture.create_view(&wgpu::TextureViewDescriptor::default()),
        }
    }

    pub(super) fn slot_texture(&self, r: ResourceId) -> &wgpu::Texture {
        self.texture_at(r, self.history.swapped)
    }

    /// Clears the `zeroed` buffers pass `i` writes (`BufferDecl::zeroed`), before the pass.
    pub(super) fn zero_buffers_written(&self, encoder: &mut wgpu::CommandEncoder, i: usize) {
        for (_, r) in &self.plan.passes[i].writes {
            if matches!(&self.plan.resources[*r].decl, ResourceDecl::Buffer(b) if b.zeroed) {
                encoder.clear_buffer(self.buffer(*r), 0, None);
            }
        }
    }

    pub(super) fn buffer(&self, r: ResourceId) -> &wgpu::Buffer {
        match &self.slots[self.slot_of(r).expect("kept resource has a slot")] {
            Physical::Buffer(b) => b,
            Physical::Texture(_) | Physical::Accel => unreachable!("buffer resource mapped to a texture slot"),
        }
    }

    /// The texture a kept texture resource lives in this frame (shared with the resources of
    /// its slot).
    pub fn texture(&self, r: ResourceId) -> Option<&wgpu::Texture> {
        match self.slot_of(r).and_then(|s| self.slots.get(s))? {
            Physical::Texture(t) => Some(t),
            _ => None,
        }
    }

    /// The pixels a `PerPixel` pass covers: its first written texture, else the frame.
    pub(super) fn per_pixel_extent(&self, pass: &PlannedPass) -> (u32, u32) {
        pass.writes
            .iter()
            .find(|(_, r)| matches!(self.plan.resources[*r].decl, ResourceDecl::Texture(_)))
            .map(|(_, r)| self.plan.resources[*r].extent)
            .unwrap_or(self.plan.frame_size)
    }

    /// The textures `pass` writes: its colour attachments (storage textures of a compute pass)
    /// and its depth attachment; buffers it writes are neither.
    pub(super) fn attachments(&self, pass: &PlannedPass) -> (Vec<ResourceId>, Option<ResourceId>) {
        let is_texture = |r: &ResourceId| matches!(self.plan.resources[*r].decl, ResourceDecl::Texture(_));
        let colors = pass.writes.iter().map(|(_, r)| *r).filter(|r| is_texture(r) && !self.is_depth(*r)).collect();
        let depth = pass.writes.iter().map(|(_, r)| *r).find(|r| self.is_depth(*r));
        (colors, depth)
    }

    pub(super) fn is_depth(&self, r: ResourceId) -> bool {
        self.plan.resources[r].decl.is_depth_texture()
    }
}
