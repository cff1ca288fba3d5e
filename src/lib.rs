//! raygraph: a render-graph framework for hybrid ray tracing on wgpu.
//!
//! Modules, lowest layer first (`docs/ARCHITECTURE.md`, "Layers"; `tests/layering.rs` checks it):
//!
//! - [`util`]: atomic file writes, sRGB conversion, the content hash of plain data.
//! - `uniforms`: `#[repr(C)]` mirrors of the uniform and record structs shared with WGSL.
//! - [`backend`]: the traversal back-ends (`compute`, `ray-query`, `rt-pipeline`), selection.
//! - [`scene`]: the CPU scene (no GPU), its loaders and exporter.
//! - [`error`]: located diagnostics of graph files and the runtime's errors.
//! - `gpu_util`: small wgpu helpers (compute pipelines, read-back buffers, mapped reads).
//! - [`graph`]: graph and layer files, shader reflection, the compiler (no GPU).
//! - [`accel`]: BVHs, the CPU traversal, the f64 reference, the GPU cache and back-ends.
//! - [`runtime`]: the wgpu device, the scene's upload, the plan executor, pass timing and batch tracing.
//!
//! With the `cli` feature (on by default), the modules behind the `raygraph` command too; they
//! are not part of the embedding API (`default-features = false` leaves them out):
//!
//! - `bench`: the experiments behind the paper's tables and figures.
//! - `selftest`: the correctness suites on whatever adapter is present.
//! - `soak`: the long-running stability check.
//! - `fuzz`: the user-file entry points shared by the fuzz targets and their tests.
//! - `viewer`: the interactive window with hot reload.

#![warn(missing_docs)]

pub mod accel;
pub mod backend;
#[cfg(feature = "cli")]
pub mod bench;
pub mod error;
#[cfg(feature = "cli")]
pub mod fuzz;
pub(crate) mod gpu_util;
pub mod graph;
pub mod runtime;
pub mod scene;
#[cfg(feature = "cli")]
pub mod selftest;
#[cfg(feature = "cli")]
pub mod soak;
pub(crate) mod spirv_words;
pub(crate) mod uniforms;
pub mod util;
#[cfg(feature = "cli")]
pub mod viewer;
