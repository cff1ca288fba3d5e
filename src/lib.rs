//! raygraph: a render-graph framework for hybrid ray tracing on wgpu.
//!
//! Modules, lowest layer first (`docs/ARCHITECTURE.md`, "Layers"; `tests/layering.rs` checks it):
//!
//! - [`util`]: atomic file writes, sRGB conversion, the content hash of plain data.
//! - [`uniforms`]: `#[repr(C)]` mirrors of the uniform and record structs shared with WGSL.
//! - [`backend`]: the traversal back-ends (`compute`, `ray-query`, `rt-pipeline`), selection.
//! - [`scene`]: the CPU scene, its loaders and exporter, and its GPU upload.
//! - [`error`]: located diagnostics of graph files and the runtime's errors.
//! - [`gpu_util`]: small wgpu helpers (compute pipelines, read-back buffers, mapped reads).
//! - [`graph`]: graph and layer files, shader reflection, the compiler (no GPU).
//! - [`accel`]: BVHs, the CPU traversal, the f64 reference, the GPU cache and back-ends.
//! - [`runtime`]: the wgpu device, the plan executor, pass timing and batch tracing.
//! - [`bench`]: the experiments behind the paper's tables and figures.
//! - [`soak`]: the long-running stability check.
//! - [`fuzz`]: the user-file entry points shared by the fuzz targets and their tests.
//! - [`viewer`]: the interactive window with hot reload.

pub mod accel;
pub mod backend;
pub mod bench;
pub mod error;
pub mod fuzz;
pub mod gpu_util;
pub mod graph;
pub mod runtime;
pub mod scene;
pub mod soak;
pub mod uniforms;
pub mod util;
pub mod viewer;
