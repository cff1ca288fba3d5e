//! The GPU runtime: device context ([`gpu`]) and how it waits ([`gpu_wait`]), the scene's
//! upload ([`scene_upload`]), plan executor ([`exec`]), GPU skinning and morphing ([`deform`]),
//! pass timing ([`profiler`]), per-pass statistics ([`report`]), what the driver compiled the trace
//! kernels into ([`kernel_stats`]), pass kinds written in Rust
//! ([`rust_pass`]), the warm-up before timed frames ([`warm_up`]) and rays traced outside any
//! graph ([`batch`]).

// The batch tracer waits for its rays, which a browser's main thread cannot.
#[cfg(not(target_arch = "wasm32"))]
pub mod batch;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod clock_pump;
pub mod deform;
pub mod environment_upload;
pub mod exec;
pub mod gpu;
pub mod gpu_wait;
#[cfg(not(target_arch = "wasm32"))]
pub mod kernel_stats;
pub(crate) mod light_records;
pub mod present;
pub mod profiler;
pub(crate) mod raster;
pub mod report;
pub mod rust_pass;
pub mod scene_upload;
pub(crate) mod trace_spirv;
pub mod warm_up;

pub use exec::Executor;
pub use gpu::Gpu;
pub use rust_pass::{RustPass, RustPassError, RustPassIo, RustPassTexture, RustPasses};
