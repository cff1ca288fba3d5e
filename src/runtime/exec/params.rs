//! Layer parameters on the GPU: the bytes of a pass's `params` uniform, the buffer made for it,
//! and [`Executor::set_param`], which changes a parameter of the running plan in place.

use super::Executor;
use crate::graph::compile::PlannedPass;
use crate::graph::desc::{ParamDecl, ParamValue, PassKind};
use crate::graph::reflect::UniformMember;
use crate::runtime::gpu::Gpu;
use std::collections::BTreeMap;

/// The bytes of a `params` uniform of `size` bytes: each member named after a parameter gets
/// that parameter's value in the member's type.
fn encode_params(params: &BTreeMap<String, (ParamDecl, ParamValue)>, members: &[UniformMember], size: u64) -> Vec<u8> {
    let mut bytes = vec![0u8; (size as usize).max(16)];
    for m in members {
        let Some((decl, value)) = params.get(&m.name) else { continue };
        let word: [u8; 4] = match (decl, *value, m.scalar) {
            (_, ParamValue::Float(v), _) => (v as f32).to_le_bytes(),
            (_, ParamValue::Int(v), Some(naga::ScalarKind::Uint)) => (v as u32).to_le_bytes(),
            (_, ParamValue::Int(v), _) => (v as i32).to_le_bytes(),
            (_, ParamValue::Bool(v), _) => (v as u32).to_le_bytes(),
        };
        let o = m.offset as usize;
        bytes[o..o + 4].copy_from_slice(&word);
    }
    bytes
}

/// The `params` uniform buffer of `pass`, holding its parameter values.
pub(super) fn create_params_buffer(device: &wgpu::Device, pass: &PlannedPass, members: &[UniformMember], size: u64) -> wgpu::Buffer {
    let bytes = encode_params(&pass.params, members, size);
    wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{} params", pass.name)),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        },
    )
}

impl Executor {
    /// Changes parameter `name` of node `node` in the running plan: the value is checked against
    /// its declaration and written into the `params` uniform of every pass of the node, ready
    /// for the next frame. `Ok(false)`: the plan must be compiled again with the value, because
    /// the parameter is read when an executor is made (the `Accel` node's settings) or no kept
    /// pass has it (the node's passes are culled; the compiler checks the name then).
    pub fn set_param(&mut self, gpu: &Gpu, node: &str, name: &str, value: ParamValue) -> Result<bool, String> {
        // Checked on every pass first, so that nothing is written when a compile is needed.
        let mut found = false;
        for pass in self.plan.passes.iter().filter(|p| p.node == node) {
            let Some((decl, _)) = pass.params.get(name) else { continue };
            crate::graph::compile::check_param(decl, value).map_err(|(_, msg, help)| format!("parameter `{name}` of node `{node}`: {msg} ({help})"))?;
            if pass.kind == PassKind::AccelBuild {
                return Ok(false);
            }
            found = true;
        }
        if !found {
            return Ok(false);
        }
        for (i, pass) in self.plan.passes.iter_mut().enumerate() {
            if pass.node != node {
                continue;
            }
            let Some((decl, current)) = pass.params.get_mut(name) else { continue };
            *current = crate::graph::compile::check_param(decl, value).map_err(|(_, msg, _)| msg)?;
            if let Some((buf, size, members)) = &self.passes[i].params {
                gpu.queue().write_buffer(buf, 0, &encode_params(&pass.params, members, *size));
            }
        }
        Ok(true)
    }
}
