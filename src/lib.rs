//! raygraph: a render-graph framework for hybrid ray tracing on wgpu.
//!
//! - [`graph`]: graph and layer files, shader reflection, the compiler (no GPU).
//! - [`runtime`]: the wgpu device, the plan executor and pass timing.
//! - [`scene`]: the CPU scene, the built-in scene and its GPU upload.
//! - [`error`]: located diagnostics.

pub mod accel;
pub mod bench;
pub mod error;
pub mod fuzz;
pub mod graph;
pub mod runtime;
pub mod scene;
pub mod soak;
pub mod util;
pub mod viewer;
