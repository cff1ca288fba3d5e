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
//!
//! The code is in steps, one file each under `rt_pipeline/`: `hal_objects.rs` (the wgpu-hal
//! plumbing: object count, hal command buffers and their barriers, alignments, the objects
//! destroyed once the device is idle, staged device buffers), `packing.rs` (the scene's
//! triangles as the builds read them), `structures.rs` ([`RtAccel`] and its update),
//! `pipeline.rs` (a pass's pipeline and shader binding table), `bind_group.rs` (a pass's hal
//! bind groups) and `pass.rs` (`RtPass`).

mod any_hit;
mod bind_group;
mod bindings;
mod hal_objects;
mod packing;
mod pass;
mod pipeline;
mod structures;

pub use any_hit::{any_hit_spirv, binding_map as any_hit_binding_map, entry_calls};
pub use bindings::{AccelBuffers, RtBinding, RtResource};
pub use hal_objects::live_hal_objects;
pub(crate) use pass::RtPass;
pub use structures::RtAccel;
