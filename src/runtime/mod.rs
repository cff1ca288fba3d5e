//! The GPU runtime: device context ([`gpu`]), plan executor ([`exec`]), pass timing
//! ([`profiler`]), per-pass statistics ([`report`]) and rays traced outside any graph
//! ([`batch`]).

pub mod batch;
pub mod exec;
pub mod gpu;
pub mod profiler;
pub mod raster;
pub mod report;
pub mod warm_up;

pub use exec::Executor;
pub use gpu::Gpu;
