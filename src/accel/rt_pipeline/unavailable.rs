//! Back-end `rt-pipeline` where wgpu has no Vulkan back-end (the web build): the same types,
//! and every constructor's error says why. Start-up never selects this back-end there (a device
//! without `EXPERIMENTAL_RAY_TRACING_PIPELINES` does not offer it); a program that forces it
//! gets the error, never a pass that does nothing.

mod bindings;

pub use bindings::{AccelBuffers, RtBinding, RtResource};

use crate::error::RuntimeError;
use crate::scene::Scene;

fn unavailable() -> RuntimeError {
    RuntimeError::Gpu("the rt-pipeline back-end needs wgpu's Vulkan back-end, which this build (WebAssembly) has not".into())
}

/// Objects made through wgpu-hal and still alive: none here.
pub fn live_hal_objects() -> isize {
    0
}

/// Acceleration structures of the `rt-pipeline` back-end: never built here.
pub struct RtAccel {}

impl RtAccel {
    /// An empty set; [`RtAccel::update`] fails.
    pub fn new(_device: &wgpu::Device) -> Self {
        Self {}
    }

    /// Fails: there is no Vulkan device to build on.
    pub fn update(
        &mut self,
        _scene: &Scene,
        _unit_meshes: &[usize],
        _unit_of_instance: &dyn Fn(usize) -> usize,
        _changed: &[usize],
        _merged: bool,
    ) -> Result<(usize, wgpu::CommandBuffer), RuntimeError> {
        Err(unavailable())
    }

    /// BLAS geometries without the OPAQUE flag: none.
    pub fn non_opaque_geometries(&self) -> usize {
        0
    }
}

/// A trace pass as a ray-tracing pipeline: none can be made here ([`RtPass::new`] fails), so
/// no value of this type exists.
pub(crate) enum RtPass {}

impl RtPass {
    /// Fails: there is no Vulkan device to make the pipeline on.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        _device: &wgpu::Device,
        _queue: &wgpu::Queue,
        _label: &str,
        _module: &crate::graph::reflect::RayTracingModule,
        _entry: &str,
        _constants: &naga::back::PipelineConstants,
        _bindings: Vec<RtBinding>,
        _accel_group: u32,
    ) -> Result<Self, RuntimeError> {
        Err(unavailable())
    }

    /// Unreachable: no `RtPass` exists.
    pub(crate) fn set_group(&mut self, _g: u32, _bindings: Vec<RtBinding>) -> Result<(), RuntimeError> {
        match *self {}
    }

    /// Unreachable: no `RtPass` exists.
    pub(crate) fn bind_accel(&mut self, _accel: &RtAccel, _cache: &AccelBuffers) -> Result<(), RuntimeError> {
        match *self {}
    }

    /// Unreachable: no `RtPass` exists.
    pub(crate) fn transition(&self, _encoder: &mut wgpu::CommandEncoder, _stats: &wgpu::Buffer) {
        match *self {}
    }

    /// Unreachable: no `RtPass` exists.
    pub fn record(&self, _launch: [u32; 3]) -> Result<wgpu::CommandBuffer, RuntimeError> {
        match *self {}
    }
}
