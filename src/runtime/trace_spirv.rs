//! The compute back-end's trace modules as SPIR-V without the zero initialiser of the traversal
//! stack.
//!
//! WGSL zero-initialises every variable, so naga gives `trace_stack` (`shaders/trace/compute.wgsl`,
//! 64 words) an `OpConstantNull` initialiser and every invocation of a trace pass clears it when
//! it starts: sky pixels and pixels without a ray pay it too. The traversal reads an entry only
//! after pushing it (a pop never goes below the entries of the current call), so the clear is
//! dead work; naga's writer cannot leave it out. Here the module is written with naga's SPIR-V
//! writer, the initialiser is removed from that one variable, and wgpu gets the words as a
//! passthrough module (`Features::PASSTHROUGH_SHADERS`, Vulkan). The writer's options are those
//! of wgpu-hal's own compilation of the module: the device's SPIR-V version, the bounds-check
//! policies its robustness features give, the binding numbers of wgpu-hal's layouts, and the
//! pipeline constants resolved into the module.
//!
//! Where the device has no passthrough shaders, the module has no traversal stack (the
//! ray-query and rt-pipeline trace modules), or `RAYGRAPH_CLEARED_STACK=1` is set (to measure the
//! difference in one binary), wgpu compiles the WGSL as it compiles every other module.

use crate::spirv_words::{binding_map, instructions, named, word0};
use spirv::Op;
#[cfg(not(target_arch = "wasm32"))]
use wgpu::hal;

/// The WGSL name of the traversal stack (`shaders/trace/compute.wgsl`).
pub(crate) const TRAVERSAL_STACK: &str = "trace_stack";

/// A trace kernel as the executor compiled it: the module's label, its entry point, its
/// SPIR-V words and its pipeline's bind group layouts (group `g` is `groups[g]`).
#[derive(Debug, Clone)]
pub struct TraceKernel {
    /// The module's label (its pass's name).
    pub label: String,
    /// The entry point.
    pub entry: String,
    /// The SPIR-V given to wgpu.
    pub words: Vec<u32>,
    /// The pipeline's bind group layouts, each with its entries sorted by binding
    /// ([`sorted_by_binding`]: entry `i` is Vulkan binding `i`).
    pub groups: Vec<Vec<wgpu::BindGroupLayoutEntry>>,
}

/// `groups` with each layout's entries sorted by binding, as wgpu-core hands them to wgpu-hal,
/// which numbers the Vulkan bindings in that order (`crate::spirv_words::binding_map`).
pub(crate) fn sorted_by_binding(groups: &[Vec<wgpu::BindGroupLayoutEntry>]) -> Vec<Vec<wgpu::BindGroupLayoutEntry>> {
    groups
        .iter()
        .map(|g| {
            let mut g = g.clone();
            g.sort_by_key(|e| e.binding);
            g
        })
        .collect()
}

/// How trace modules are written for one device.
#[derive(Debug, Clone)]
pub(crate) struct TraceSpirv {
    lang_version: (u8, u8),
    policies: naga::proc::BoundsCheckPolicies,
}

impl TraceSpirv {
    /// The writer's options for `device`, or `None` where trace modules are compiled from WGSL
    /// by wgpu (no Vulkan device, no passthrough shaders, or `RAYGRAPH_CLEARED_STACK=1`).
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn for_device(device: &wgpu::Device) -> Option<Self> {
        if !device.features().contains(wgpu::Features::PASSTHROUGH_SHADERS) || std::env::var("RAYGRAPH_CLEARED_STACK").is_ok_and(|v| v == "1") {
            return None;
        }
        // SAFETY: the guard is used only to read the physical device's properties and the
        // device's enabled extensions, within this call.
        let hal_device = unsafe { device.as_hal::<hal::api::Vulkan>() }?;
        Some(Self::from_hal(&hal_device))
    }

    /// On the web: never (WebGPU takes WGSL only).
    #[cfg(target_arch = "wasm32")]
    pub(crate) fn for_device(_device: &wgpu::Device) -> Option<Self> {
        None
    }

    /// As wgpu-hal's `Adapter::open` chooses them: SPIR-V 1.0/1.3/1.5/1.6 by the device's API
    /// version, and bounds checks left to the driver where its robustness features make
    /// out-of-bounds accesses safe (buffers: `robustBufferAccess2`; image loads:
    /// `robustImageAccess2`, or `robustImageAccess` without `VK_EXT_robustness2`).
    #[cfg(not(target_arch = "wasm32"))]
    fn from_hal(device: &hal::vulkan::Device) -> Self {
        let instance = device.shared_instance().raw_instance();
        let phd = device.raw_physical_device();
        // SAFETY: queries of the physical device the hal device was opened on.
        let api = unsafe { instance.get_physical_device_properties(phd) }.api_version;
        let lang_version = match api {
            v if v >= ash::vk::API_VERSION_1_3 => (1, 6),
            v if v >= ash::vk::API_VERSION_1_2 => (1, 5),
            v if v >= ash::vk::API_VERSION_1_1 => (1, 3),
            _ => (1, 0),
        };
        let robustness2_enabled = device.enabled_device_extensions().contains(&ash::ext::robustness2::NAME);
        let mut robustness2 = ash::vk::PhysicalDeviceRobustness2FeaturesEXT::default();
        let mut image_robustness = ash::vk::PhysicalDeviceImageRobustnessFeatures::default();
        let mut features = ash::vk::PhysicalDeviceFeatures2::default();
        if robustness2_enabled {
            features = features.push_next(&mut robustness2);
        }
        if api >= ash::vk::API_VERSION_1_3 || device.enabled_device_extensions().contains(&ash::ext::image_robustness::NAME) {
            features = features.push_next(&mut image_robustness);
        }
        // SAFETY: the chained structs outlive the call.
        unsafe { instance.get_physical_device_features2(phd, &mut features) };
        let buffer_safe = robustness2_enabled && robustness2.robust_buffer_access2 != 0;
        let image_safe = if robustness2_enabled { robustness2.robust_image_access2 != 0 } else { image_robustness.robust_image_access != 0 };
        let checked = |safe: bool| if safe { naga::proc::BoundsCheckPolicy::Unchecked } else { naga::proc::BoundsCheckPolicy::Restrict };
        let policies = naga::proc::BoundsCheckPolicies {
            index: naga::proc::BoundsCheckPolicy::Restrict,
            buffer: checked(buffer_safe),
            image_load: checked(image_safe),
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        };
        Self { lang_version, policies }
    }

    /// Whether `wgsl` declares the traversal stack (the compute back-end's trace modules do).
    pub(crate) fn applies_to(wgsl: &str) -> bool {
        wgsl.contains(&format!("var<private> {TRAVERSAL_STACK}"))
    }

    /// `entry` of `wgsl` as SPIR-V for a pipeline whose bind group layouts have `groups`
    /// (group `g` is `groups[g]`, entries in any order), with `constants` resolved and the
    /// traversal stack's initialiser removed; and the entry point's workgroup size.
    pub fn words(
        &self,
        wgsl: &str,
        entry: &str,
        constants: &[(&str, f64)],
        groups: &[Vec<wgpu::BindGroupLayoutEntry>],
    ) -> Result<(Vec<u32>, [u32; 3]), String> {
        let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
        let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .map_err(|e| e.emit_to_string(wgsl))?;
        let constants: naga::back::PipelineConstants = constants.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        let (module, info) = naga::back::pipeline_constants::process_overrides(&module, &info, Some((naga::ShaderStage::Compute, entry)), &constants)
            .map_err(|e| format!("resolving the pipeline constants: {e}"))?;
        let sorted = sorted_by_binding(groups);
        let options = naga::back::spv::Options {
            lang_version: self.lang_version,
            // DEBUG for the OpName that finds the stack.
            flags: naga::back::spv::WriterFlags::DEBUG,
            binding_map: binding_map(&sorted),
            bounds_check_policies: self.policies,
            // Trace modules go without loop bounding (`ShaderOrigin::TracePass`).
            force_loop_bounding: crate::gpu_util::ShaderOrigin::TracePass.checks().force_loop_bounding,
            fake_missing_bindings: false,
            ..Default::default()
        };
        let pipeline = naga::back::spv::PipelineOptions { shader_stage: naga::ShaderStage::Compute, entry_point: entry.to_string() };
        let words = naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| format!("writing SPIR-V: {e}"))?;
        let workgroup_size =
            module.entry_points.iter().find(|e| e.name == entry).map(|e| e.workgroup_size).ok_or_else(|| format!("no entry point `{entry}`"))?;
        Ok((without_initializer(&words, TRAVERSAL_STACK)?, workgroup_size))
    }

    /// The words of [`TraceSpirv::words`] (with their entry point's workgroup size) as a wgpu
    /// shader module.
    pub fn module_from_words(device: &wgpu::Device, label: &str, entry: &str, words: Vec<u32>, workgroup_size: [u32; 3]) -> wgpu::ShaderModule {
        let entry_point = wgpu::PassthroughShaderEntryPoint { name: entry.into(), workgroup_size: workgroup_size.into() };
        let desc = wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(label),
            entry_points: std::borrow::Cow::Owned(vec![entry_point]),
            spirv: Some(std::borrow::Cow::Owned(words)),
            ..Default::default()
        };
        // SAFETY: SPIR-V written by naga from a module the graph compiler validated, with the
        // bindings of the pipeline layout it is used with and wgpu-hal's bounds-check policies;
        // the one change, a variable without its initialiser, leaves it valid SPIR-V, and the
        // traversal writes each stack entry before reading it (module docs).
        unsafe { device.create_shader_module_passthrough(desc) }
    }
}

/// `words` with the initialiser of the variable named `name` removed (its `OpVariable` loses
/// its fourth operand). An error if there is no such variable or it has no initialiser.
pub(crate) fn without_initializer(words: &[u32], name: &str) -> Result<Vec<u32>, String> {
    let list = instructions(words)?;
    let id = named(&list, name)?;
    let mut out: Vec<u32> = words[..5].to_vec();
    let mut removed = false;
    for (op, w) in &list {
        if *op == Op::Variable as u16 && w[2] == id {
            if w.len() != 5 {
                return Err(format!("`{name}` has no initialiser"));
            }
            out.extend([word0(Op::Variable, 4), w[1], w[2], w[3]]);
            removed = true;
        } else {
            out.extend_from_slice(w);
        }
    }
    if !removed {
        return Err(format!("no declaration of `{name}`"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const STACKED: &str = "
var<private> trace_stack: array<u32, 8>;
var<private> other: array<u32, 8>;
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@compute @workgroup_size(1)
fn main() {
    trace_stack[0] = 3u;
    out[0] = trace_stack[0] + other[1];
}
";

    fn spirv(wgsl: &str) -> Vec<u32> {
        let module = naga::front::wgsl::parse_str(wgsl).unwrap();
        let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all()).validate(&module).unwrap();
        let options = naga::back::spv::Options { flags: naga::back::spv::WriterFlags::DEBUG, ..Default::default() };
        naga::back::spv::write_vec(&module, &info, &options, None).unwrap()
    }

    /// The `OpVariable` of `name` in `words`.
    fn variable(words: &[u32], name: &str) -> Vec<u32> {
        let list = instructions(words).unwrap();
        let id = named(&list, name).unwrap();
        list.iter().find(|(op, w)| *op == Op::Variable as u16 && w[2] == id).unwrap().1.to_vec()
    }

    #[test]
    fn only_the_named_variable_loses_its_initializer() {
        let words = spirv(STACKED);
        assert_eq!(variable(&words, "trace_stack").len(), 5, "naga initialises private variables");
        let patched = without_initializer(&words, "trace_stack").unwrap();
        assert_eq!(patched.len(), words.len() - 1);
        assert_eq!(variable(&patched, "trace_stack").len(), 4);
        assert_eq!(variable(&patched, "other"), variable(&words, "other"));
        // Everything but that one instruction is word for word the same.
        let list = instructions(&patched).unwrap();
        assert_eq!(list.len(), instructions(&words).unwrap().len());
        assert!(patched[..5] == words[..5]);
    }

    #[test]
    fn a_module_without_the_variable_is_an_error() {
        let words = spirv(&STACKED.replace("trace_stack", "renamed"));
        assert!(without_initializer(&words, "trace_stack").unwrap_err().contains("no variable `trace_stack`"));
        assert!(without_initializer(&[1, 2, 3], "trace_stack").unwrap_err().contains("not a SPIR-V module"));
    }

    #[test]
    fn applies_only_to_modules_with_the_stack() {
        assert!(TraceSpirv::applies_to(STACKED));
        assert!(!TraceSpirv::applies_to("var<private> trace_hit_attribute: vec2<f32>;"));
    }
}
