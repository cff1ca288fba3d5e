//! Pass kinds written in Rust: the [`RustPass`] trait a program implements, what such a pass
//! sees ([`RustPassIo`]: the resources its layer file declares, by name, the frame size, its
//! parameters), and the registry of them by name ([`RustPasses`]) that an executor is made
//! with ([`crate::runtime::Executor::with_rust_passes`]).
//!
//! A layer file makes a pass one with `kind: Rust` and the registered name in `entry`; its
//! `reads` and `writes` name the layer's declared inputs, outputs and transients (there is no
//! shader to reflect). The executor records the pass at its place in the schedule, between a
//! pair of GPU timestamps, like every other pass.

use super::gpu::Gpu;
use crate::graph::desc::{Format, ParamValue};
use std::collections::BTreeMap;

/// The error a Rust pass returns; the executor reports it with the pass's name and layer file.
pub type RustPassError = Box<dyn std::error::Error + Send + Sync>;

/// A pass kind written in Rust. One instance is made (by the factory it was registered with)
/// for every pass of the plan that names it, and made again whenever the executor builds its
/// passes again (a scene change that uploads the scene anew).
pub trait RustPass: Send {
    /// Makes the pass's GPU objects (pipelines, bind group layouts) once its resources exist,
    /// before the first frame. The default makes none.
    fn build(&mut self, gpu: &Gpu, io: &RustPassIo) -> Result<(), RustPassError> {
        let _ = (gpu, io);
        Ok(())
    }

    /// Records the pass's GPU work for one frame into `encoder`, reading the textures and
    /// buffers of `io` that the layer file lists in `reads` and writing those in `writes`.
    /// The executor writes the pass's timestamps around what it records.
    fn record(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, io: &RustPassIo) -> Result<(), RustPassError>;
}

/// A declared texture of a Rust pass: the texture and the format the layer file declares.
#[derive(Debug, Clone)]
pub struct RustPassTexture {
    /// The texture (every usage its format allows).
    pub texture: wgpu::Texture,
    /// Its format as the layer file declares it.
    pub format: Format,
}

/// What a Rust pass works on: the resources its layer file names in `reads` and `writes` (by
/// those names), the frame size and the pass's parameter values.
#[derive(Debug, Clone)]
pub struct RustPassIo {
    pub(crate) name: String,
    pub(crate) frame_size: (u32, u32),
    pub(crate) textures: BTreeMap<String, RustPassTexture>,
    pub(crate) buffers: BTreeMap<String, wgpu::Buffer>,
    pub(crate) params: BTreeMap<String, ParamValue>,
}

impl RustPassIo {
    /// The pass's name in the plan, `node/pass`.
    pub fn pass_name(&self) -> &str {
        &self.name
    }

    /// The frame size in pixels.
    pub fn frame_size(&self) -> (u32, u32) {
        self.frame_size
    }

    /// The texture the layer file declares as `name` (an input, output or transient the pass
    /// reads or writes).
    pub fn texture(&self, name: &str) -> Result<&RustPassTexture, RustPassError> {
        self.textures.get(name).ok_or_else(|| self.unknown("texture", name, self.textures.keys()))
    }

    /// The buffer the layer file declares as `name` (an input, output or transient the pass
    /// reads or writes).
    pub fn buffer(&self, name: &str) -> Result<&wgpu::Buffer, RustPassError> {
        self.buffers.get(name).ok_or_else(|| self.unknown("buffer", name, self.buffers.keys()))
    }

    /// The current value of parameter `name` (the layer's default, the graph file's value, or
    /// the last [`crate::runtime::Executor::set_param`]).
    pub fn param(&self, name: &str) -> Option<ParamValue> {
        self.params.get(name).copied()
    }

    fn unknown<'a>(&self, what: &str, name: &str, known: impl Iterator<Item = &'a String>) -> RustPassError {
        let known: Vec<&str> = known.map(String::as_str).collect();
        format!("pass {} reads or writes no {what} `{name}` (its {what}s: {})", self.name, if known.is_empty() { "none".into() } else { known.join(", ") })
            .into()
    }
}

type Factory = Box<dyn Fn() -> Box<dyn RustPass> + Send + Sync>;

/// The Rust passes an executor can run, by the name a layer file's `entry` gives them.
#[derive(Default)]
pub struct RustPasses {
    factories: BTreeMap<String, Factory>,
}

impl RustPasses {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers `make` under `name`: every pass of kind `Rust` whose `entry` is `name` runs an
    /// instance it makes.
    pub fn with<P: RustPass + 'static>(mut self, name: impl Into<String>, make: impl Fn() -> P + Send + Sync + 'static) -> Self {
        self.factories.insert(name.into(), Box::new(move || -> Box<dyn RustPass> { Box::new(make()) }));
        self
    }

    /// The registered names, sorted.
    pub fn names(&self) -> Vec<&str> {
        self.factories.keys().map(String::as_str).collect()
    }

    /// A new instance of the pass registered as `name`.
    pub(crate) fn make(&self, name: &str) -> Option<Box<dyn RustPass>> {
        self.factories.get(name).map(|make| make())
    }
}
