//! The GPU runtime: device context ([`gpu`]), plan executor ([`exec`]), pass timing
//! ([`profiler`]) and the uniform structs shared with WGSL ([`uniforms`]).

pub mod exec;
pub mod gpu;
pub mod profiler;
pub mod raster;
pub mod report;
pub mod uniforms;

pub use exec::Executor;
pub use gpu::Gpu;
