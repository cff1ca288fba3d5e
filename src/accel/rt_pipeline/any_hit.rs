//! The any-hit shader of the alpha-tested hit group, as SPIR-V made here (wgpu-hal's Vulkan
//! back-end takes it as `ShaderInput::SpirV`).
//!
//! naga 30's any-hit stage can neither reject a candidate (no `ignoreIntersection`) nor read
//! the hit attributes (no such address space), so `trace_any_hit_shader` of
//! `shaders/trace/rt_pipeline.wgsl` is written with two stand-ins, compiled to SPIR-V with
//! naga's writer, and patched:
//! - `var<private> trace_hit_attribute: vec2<f32>` becomes the `HitAttributeKHR` variable (a
//!   triangle's barycentrics): a new `OpTypePointer HitAttributeKHR`, and its `OpVariable`
//!   takes that type and storage class and loses naga's null initializer;
//! - each `OpStore` to `var<private> trace_ignore_intersection` becomes
//!   `OpIgnoreIntersectionKHR`, which ends its block, so the block's own end that followed the
//!   store (a branch, or a return where the `if` ends the function) goes.
//!
//! The variables are found by their `OpName` (the writer's debug names). The compilation uses
//! the descriptor sets and bindings wgpu-hal gives the other stages of the pipeline: its
//! Vulkan bind group layouts number bindings in the order of their entries, and binding arrays
//! get their layout's count (`wgpu-hal/src/vulkan/device.rs`, `create_bind_group_layout`
//! and `create_pipeline_layout`).

use crate::spirv_words::{instructions, named, word0};
use spirv::{Op, StorageClass};

/// The WGSL names of the two stand-ins (shaders/trace/rt_pipeline.wgsl).
const HIT_ATTRIBUTE: &str = "trace_hit_attribute";
const IGNORE_MARKER: &str = "trace_ignore_intersection";

pub use crate::spirv_words::binding_map;

/// The trace module's pipeline constant that keeps the any-hit shader's branch for closest-hit
/// rays passing BLEND surfaces (shaders/trace/rt_pipeline.wgsl), and the function whose call
/// decides it: a pass whose ray-generation shader never calls it traces no closest-hit rays.
const CLOSEST_RAYS_CONSTANT: &str = "TRACE_CLOSEST_RAYS";
const CLOSEST_TRACE_FUNCTION: &str = "trace_closest_flags";

/// The any-hit entry point `entry` of `module` as patched SPIR-V (see the module docs), for the
/// pipeline whose ray-generation shader is entry point `ray_generation`.
pub fn any_hit_spirv(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    ray_generation: &str,
    binding_map: naga::back::spv::BindingMap,
) -> Result<Vec<u32>, String> {
    let checks = crate::gpu_util::ShaderOrigin::TracePass.checks();
    let restrict = naga::proc::BoundsCheckPolicy::Restrict;
    let options = naga::back::spv::Options {
        // SPIR-V 1.4, the least VK_KHR_ray_tracing_pipeline takes (it requires VK_KHR_spirv_1_4).
        lang_version: (1, 4),
        // DEBUG for the OpName of the two stand-ins.
        flags: naga::back::spv::WriterFlags::DEBUG,
        binding_map,
        // As wgpu-hal compiles the other stages (`Adapter::open`'s naga options).
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: restrict,
            buffer: restrict,
            image_load: restrict,
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        },
        force_loop_bounding: checks.force_loop_bounding,
        fake_missing_bindings: false,
        ..Default::default()
    };
    // The trace module's pipeline constants keep their defaults here (TRACE_ALPHA_TEST: the
    // any-hit shader is the alpha test), but for TRACE_CLOSEST_RAYS.
    let closest = if entry_calls(module, ray_generation, CLOSEST_TRACE_FUNCTION) { 1.0 } else { 0.0 };
    let constants = naga::back::PipelineConstants::from([(CLOSEST_RAYS_CONSTANT.to_string(), closest)]);
    let (module, info) = naga::back::pipeline_constants::process_overrides(module, info, None, &constants)
        .map_err(|e| format!("resolving the pipeline constants of `{entry}`: {e}"))?;
    let pipeline = naga::back::spv::PipelineOptions { shader_stage: naga::ShaderStage::AnyHit, entry_point: entry.to_string() };
    let words = naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| format!("writing `{entry}` as SPIR-V: {e}"))?;
    patch(&words).map_err(|e| format!("patching `{entry}`: {e}"))
}

/// Whether entry point `entry` of `module` calls the function named `function`, directly or
/// through the functions it calls.
pub fn entry_calls(module: &naga::Module, entry: &str, function: &str) -> bool {
    let Some(ep) = module.entry_points.iter().find(|e| e.name == entry) else { return false };
    let mut seen = std::collections::HashSet::new();
    let mut pending = Vec::new();
    block_calls(&ep.function.body, &mut pending);
    while let Some(handle) = pending.pop() {
        if !seen.insert(handle) {
            continue;
        }
        let called = &module.functions[handle];
        if called.name.as_deref() == Some(function) {
            return true;
        }
        block_calls(&called.body, &mut pending);
    }
    false
}

/// Pushes the function of every call in `block` and its nested blocks onto `calls`.
fn block_calls(block: &naga::Block, calls: &mut Vec<naga::Handle<naga::Function>>) {
    for statement in block.iter() {
        match statement {
            naga::Statement::Call { function, .. } => calls.push(*function),
            naga::Statement::Block(inner) => block_calls(inner, calls),
            naga::Statement::If { accept, reject, .. } => {
                block_calls(accept, calls);
                block_calls(reject, calls);
            }
            naga::Statement::Switch { cases, .. } => cases.iter().for_each(|case| block_calls(&case.body, calls)),
            naga::Statement::Loop { body, continuing, .. } => {
                block_calls(body, calls);
                block_calls(continuing, calls);
            }
            _ => {}
        }
    }
}

/// Applies the two patches of the module docs to a SPIR-V module naga wrote.
pub(crate) fn patch(words: &[u32]) -> Result<Vec<u32>, String> {
    let list = instructions(words)?;
    let attribute = named(&list, HIT_ATTRIBUTE)?;
    let marker = named(&list, IGNORE_MARKER)?;
    let mut bound = words[3];
    let mut out: Vec<u32> = words[..5].to_vec();
    let mut ignores = 0;
    let mut attribute_made = false;
    let mut drop_branch = false;
    for (op, w) in &list {
        let op = *op;
        if drop_branch {
            // The block that stored the marker now ends with OpIgnoreIntersectionKHR: its own
            // terminator goes (debug line instructions may come first; anything else would be
            // code after the store, which the patch would lose).
            if op == Op::Line as u16 || op == Op::NoLine as u16 {
                continue;
            }
            if op != Op::Branch as u16 && op != Op::Return as u16 {
                return Err(format!("the store to `{IGNORE_MARKER}` is followed by opcode {op}, not the end of its block"));
            }
            drop_branch = false;
            continue;
        }
        if op == Op::Variable as u16 && w[2] == attribute {
            let pointee = list
                .iter()
                .find(|(o, p)| *o == Op::TypePointer as u16 && p[1] == w[1])
                .map(|(_, p)| p[3])
                .ok_or_else(|| format!("`{HIT_ATTRIBUTE}` has no pointer type"))?;
            let pointer = bound;
            bound += 1;
            out.extend([word0(Op::TypePointer, 4), pointer, StorageClass::HitAttributeKHR as u32, pointee]);
            out.extend([word0(Op::Variable, 4), pointer, attribute, StorageClass::HitAttributeKHR as u32]);
            attribute_made = true;
            continue;
        }
        if op == Op::Store as u16 && w[1] == marker {
            out.push(word0(Op::IgnoreIntersectionKHR, 1));
            ignores += 1;
            drop_branch = true;
            continue;
        }
        // The attribute may only be loaded whole: a store or an access chain would still name
        // its old (Private) pointer type.
        let chains = [Op::AccessChain, Op::InBoundsAccessChain, Op::PtrAccessChain].map(|o| o as u16);
        if (op == Op::Store as u16 && w[1] == attribute) || (chains.contains(&op) && w[3] == attribute) {
            return Err(format!("`{HIT_ATTRIBUTE}` is used other than by a whole load (opcode {op})"));
        }
        out.extend_from_slice(w);
    }
    if !attribute_made {
        return Err(format!("no declaration of `{HIT_ATTRIBUTE}`"));
    }
    if ignores == 0 {
        return Err(format!("no store to `{IGNORE_MARKER}`"));
    }
    out[3] = bound;
    Ok(out)
}
