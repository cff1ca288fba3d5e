//! `Rust` passes: an instance of the registered [`RustPass`] per pass, built with the
//! resources its layer file declares, and recorded between the pass's timestamps.

use super::{Executor, PassRuntime, Physical, Pipeline};
use crate::error::{ErrorKind, GraphError, RuntimeError};
use crate::graph::compile::PlannedPass;
use crate::graph::desc::ResourceDecl;
use crate::runtime::gpu::Gpu;
use crate::runtime::rust_pass::{RustPassError, RustPassIo, RustPassTexture};

/// A Rust pass's error, with the pass, its registered name and its layer file.
fn rust_pass_failed(pass: &PlannedPass, step: &str, e: RustPassError) -> RuntimeError {
    RuntimeError::Gpu(format!("{}: pass `{}` (Rust pass `{}`) failed to {step}: {e}", pass.location, pass.name, pass.entry))
}

impl Executor {
    /// An instance of the Rust pass that `pass` names, built over the pass's resources.
    pub(super) fn build_rust_pass(&self, gpu: &Gpu, pass: &PlannedPass) -> Result<PassRuntime, RuntimeError> {
        let Some(mut rust) = self.rust_passes.make(&pass.entry) else { return Err(self.unregistered_rust_pass(pass).into()) };
        let io = self.rust_pass_io(pass);
        rust.build(gpu, &io).map_err(|e| rust_pass_failed(pass, "build", e))?;
        Ok(PassRuntime::bare(Pipeline::Rust { pass: rust, io: Box::new(io) }))
    }

    /// The error of a layer file whose Rust pass was not registered with the executor.
    fn unregistered_rust_pass(&self, pass: &PlannedPass) -> GraphError {
        let registered = self.rust_passes.names();
        let message = if pass.entry.is_empty() {
            format!("pass `{}` is `kind: Rust` but names no Rust pass", pass.name)
        } else {
            format!("pass `{}` runs Rust pass `{}`, which is not registered with the executor", pass.name, pass.entry)
        };
        GraphError::new(ErrorKind::Unsupported, pass.location.clone(), message).help(format!(
            "set `entry: Some(\"NAME\")` to a name registered with `RustPasses::with` and make the executor with `Executor::with_rust_passes`; registered: {}",
            if registered.is_empty() { "none".to_string() } else { registered.join(", ") }
        ))
    }

    /// The resources `pass` reads and writes, by the names its layer file gives them.
    fn rust_pass_io(&self, pass: &PlannedPass) -> RustPassIo {
        let mut io = RustPassIo {
            name: pass.name.clone(),
            frame_size: self.plan.frame_size,
            textures: Default::default(),
            buffers: Default::default(),
            params: pass.params.iter().map(|(k, (_, v))| (k.clone(), *v)).collect(),
        };
        for (local, r) in pass.reads.iter().chain(&pass.writes) {
            let resource = &self.plan.resources[*r];
            match (&resource.decl, self.slot_of(*r).and_then(|s| self.slots.get(s))) {
                (ResourceDecl::Texture(t), Some(Physical::Texture(texture))) => {
                    io.textures.insert(local.clone(), RustPassTexture { texture: texture.clone(), format: t.format });
                }
                (ResourceDecl::Buffer(_), Some(Physical::Buffer(buffer))) => {
                    io.buffers.insert(local.clone(), buffer.clone());
                }
                _ => {}
            }
        }
        io
    }

    /// Records Rust pass `i` with its current parameter values, between its timestamps.
    pub(super) fn record_rust_pass(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, i: usize) -> Result<(), RuntimeError> {
        let planned = &self.plan.passes[i];
        let Pipeline::Rust { pass, io } = &mut self.passes[i].pipeline else { unreachable!("record_rust_pass is called for Rust passes") };
        io.params = planned.params.iter().map(|(k, (_, v))| (k.clone(), *v)).collect();
        if let Some(t) = &self.timer {
            drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&format!("{} begin", planned.name)),
                timestamp_writes: t.begin_writes(i as u32),
            }));
        }
        pass.record(gpu, encoder, io).map_err(|e| rust_pass_failed(planned, "record", e))?;
        if let Some(t) = &self.timer {
            drop(
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(&format!("{} end", planned.name)),
                    timestamp_writes: t.end_writes(i as u32),
                }),
            );
        }
        Ok(())
    }
}
