//! Acceleration structures for ray tracing.
//!
//! The CPU side of the `compute` back-end's own two-level BVH, and the ground truth it is tested
//! against:
//!
//! - [`bvh`]: the parallel binned-SAH builder ([`bvh::Bvh`]: build, SAH cost, refit), the
//!   bottom level per mesh ([`bvh::Blas`], over object-space triangles; degenerate and
//!   non-finite triangles are left out and counted), the top level over instances
//!   ([`bvh::Tlas`]) and both together for a scene ([`bvh::SceneAccel`], with or without BLAS
//!   de-duplication, refit after instances or vertices moved).
//! - [`layout`]: the `#[repr(C)]` GPU layout that the WGSL traversal reads ([`layout::GpuBvhNode`],
//!   [`layout::GpuTriangle`], [`layout::GpuInstance`], [`layout::GpuAccel`]) and
//!   [`layout::flatten`], including the never-hit placeholders that keep every array non-empty.
//! - [`cpu_traverse`]: an f32 traversal of [`layout::GpuAccel`] that does what the WGSL does
//!   (robust slab test, nearer-first stack traversal, watertight ray-triangle test), so the
//!   layout and numerics are tested before any GPU runs.
//! - [`reference`](mod@reference): the brute-force f64 ray caster that tests use as ground truth for both GPU
//!   back-ends, with each hit's distance to the nearest edge to classify disagreements.
//! - [`alpha`]: which instances are alpha-tested, the trace module's `accel_alpha` data, and the
//!   alpha test on the CPU (level-0 bilinear texel read) for both CPU traversals.
//! - [`reference_render`]: the ray-traced channels (visibility, shadow mask, AO, mirror rays)
//!   per pixel from that caster, each ray built as the layers' shaders build it.
//!
//! The remaining modules (the acceleration-structure cache behind a graph's `Accel` node, the
//! `rt-pipeline` back-end, the GPU refit and the GPU builder of the merged layout) are the GPU
//! side and document themselves.

pub mod alpha;
pub mod bvh;
pub mod cache;
pub mod cpu_traverse;
pub mod deform;
pub mod gpu_build;
pub mod gpu_records;
pub mod layout;
pub mod packed;
pub mod radix_sort;
pub mod reference;
pub mod reference_render;
pub mod refit;
pub(crate) mod reinsert;
// Vulkan through wgpu-hal; on the web a stand-in whose constructors fail.
#[cfg_attr(target_arch = "wasm32", path = "rt_pipeline/unavailable.rs")]
pub mod rt_pipeline;
