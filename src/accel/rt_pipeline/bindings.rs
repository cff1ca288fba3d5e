//! What a trace pass of the `rt-pipeline` back-end binds: the executor's and the batch
//! tracer's wgpu objects, described for the hal bind groups `RtPass` makes (shared by the
//! Vulkan module and the web build's stand-in, which has no such pass).

use std::num::NonZeroU64;

/// What a binding of a trace pass is bound to (the executor's and the batch tracer's wgpu
/// objects, bound through hal bind groups).
#[derive(Clone)]
pub enum RtResource {
    /// `initialize`: a buffer the pass writes that wgpu has never seen written (see
    /// `RtPass::transition`).
    Buffer {
        /// The buffer.
        buffer: wgpu::Buffer,
        /// Byte offset of the binding.
        offset: u64,
        /// Bytes bound (`None`: to the end).
        size: Option<NonZeroU64>,
        /// How the pass uses it.
        uses: wgpu::BufferUses,
        /// The pass writes it and wgpu has never seen it written.
        initialize: bool,
    },
    /// A storage or sampled texture.
    Texture {
        /// The texture.
        texture: wgpu::Texture,
        /// The view bound.
        view: wgpu::TextureView,
        /// How the pass uses it.
        uses: wgpu::TextureUses,
    },
    /// A binding array of sampled textures (the scene's).
    Textures(Vec<(wgpu::Texture, wgpu::TextureView)>),
    /// A sampler, made by the pass.
    Sampler(wgpu::SamplerDescriptor<'static>),
    /// A binding of the trace module (`accel_*`), bound by `RtPass::bind_accel`.
    Accel(String),
}

/// One binding of a trace pass: its layout entry (visibility is replaced by the ray-tracing
/// stages) and what it is bound to.
#[derive(Clone)]
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
pub struct RtBinding {
    /// The bind group.
    pub(crate) group: u32,
    /// The layout entry.
    pub(crate) entry: wgpu::BindGroupLayoutEntry,
    /// What it is bound to.
    pub(crate) resource: RtResource,
}

/// The trace module's bindings that the acceleration-structure cache holds in wgpu buffers
/// (`accel_stats`'s counter window, `accel_alpha`; `crate::accel::cache::cache_buffers`):
/// by name, the buffer, offset and size, or `None`.
pub type AccelBuffers<'a> = dyn Fn(&str) -> Option<(wgpu::Buffer, u64, Option<NonZeroU64>)> + 'a;
