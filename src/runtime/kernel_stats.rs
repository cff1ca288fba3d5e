//! What the driver's compiler made of the compute back-end's trace kernels: registers,
//! instruction counts, spills, as the driver reports them through
//! `VK_KHR_pipeline_executable_properties` (`raygraph render --kernel-stats FILE`).
//!
//! The executor's own device is opened by wgpu, which neither enables that extension nor lets
//! a pipeline's Vulkan handle out, so the kernels are compiled a second time here, on a Vulkan
//! device of their own on the same adapter: the same SPIR-V words the executor gave wgpu
//! ([`super::trace_spirv`]), with descriptor set layouts numbered as wgpu-hal numbers them, and
//! with every feature the adapter has enabled (robustness among them, as wgpu enables it).
//! What a driver reports is its own: NVIDIA's include the register count, lavapipe's the
//! LLVM passes' sizes.

pub use super::trace_spirv::TraceKernel;
use ash::vk;
use std::ffi::CString;

/// One executable of a compiled kernel and the driver's statistics for it, as (name, value).
#[derive(Debug, Clone)]
pub struct KernelStatistics {
    /// The kernel's module label (its pass).
    pub label: String,
    /// The executable's name as the driver gives it (one per shader stage).
    pub executable: String,
    /// The driver's statistics, in its order.
    pub statistics: Vec<(String, String)>,
}

/// A Vulkan device of its own on the adapter named `adapter`, with
/// `VK_KHR_pipeline_executable_properties`.
struct StatsDevice {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    executables: ash::khr::pipeline_executable_properties::Device,
}

impl Drop for StatsDevice {
    fn drop(&mut self) {
        // SAFETY: every object made on the device was destroyed by `compile_and_query`.
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// The driver's statistics for each of `kernels`, compiled on the adapter named `adapter`.
pub fn kernel_statistics(adapter: &str, kernels: &[TraceKernel]) -> Result<Vec<KernelStatistics>, String> {
    let stats = StatsDevice::open(adapter)?;
    let mut out = Vec::new();
    for kernel in kernels {
        out.extend(stats.compile_and_query(kernel).map_err(|e| format!("{}: {e}", kernel.label))?);
    }
    Ok(out)
}

impl StatsDevice {
    fn open(adapter: &str) -> Result<Self, String> {
        // SAFETY: loading the system's Vulkan loader, as wgpu-hal does.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        // SAFETY: a plain instance; destroyed by Drop (or below, on failure).
        let instance =
            unsafe { entry.create_instance(&vk::InstanceCreateInfo::default().application_info(&app), None) }.map_err(|e| format!("vkCreateInstance: {e}"))?;
        match Self::device_on(&instance, adapter) {
            Ok(device) => {
                let executables = ash::khr::pipeline_executable_properties::Device::new(&instance, &device);
                Ok(Self { _entry: entry, instance, device, executables })
            }
            Err(e) => {
                // SAFETY: nothing else was made on the instance.
                unsafe { instance.destroy_instance(None) };
                Err(e)
            }
        }
    }

    /// A device on the physical device named `adapter`, with every feature it has.
    fn device_on(instance: &ash::Instance, adapter: &str) -> Result<ash::Device, String> {
        // SAFETY: queries of a live instance and its physical devices.
        let physical = unsafe { instance.enumerate_physical_devices() }.map_err(|e| format!("vkEnumeratePhysicalDevices: {e}"))?;
        let named = |pd: &vk::PhysicalDevice| {
            let props = unsafe { instance.get_physical_device_properties(*pd) };
            props.device_name_as_c_str().is_ok_and(|n| n.to_string_lossy() == adapter)
        };
        let pd = *physical.iter().find(|pd| named(pd)).ok_or_else(|| format!("no Vulkan physical device named `{adapter}`"))?;
        let extensions = unsafe { instance.enumerate_device_extension_properties(pd) }.map_err(|e| format!("vkEnumerateDeviceExtensionProperties: {e}"))?;
        let has = |name: &std::ffi::CStr| extensions.iter().any(|e| e.extension_name_as_c_str() == Ok(name));
        let wanted = ash::khr::pipeline_executable_properties::NAME;
        if !has(wanted) {
            return Err(format!("`{adapter}` has no {}", wanted.to_string_lossy()));
        }
        let robustness2 = has(ash::ext::robustness2::NAME);
        let mut names = vec![wanted.as_ptr()];
        if robustness2 {
            names.push(ash::ext::robustness2::NAME.as_ptr());
        }
        let api = unsafe { instance.get_physical_device_properties(pd) }.api_version;
        let mut executable = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default();
        let mut robust = vk::PhysicalDeviceRobustness2FeaturesEXT::default();
        let mut v11 = vk::PhysicalDeviceVulkan11Features::default();
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut executable);
        if robustness2 {
            features = features.push_next(&mut robust);
        }
        if api >= vk::API_VERSION_1_3 {
            features = features.push_next(&mut v11).push_next(&mut v12).push_next(&mut v13);
        }
        // SAFETY: the chained structs outlive both calls; the features queried are the ones
        // enabled, so every one is supported.
        unsafe { instance.get_physical_device_features2(pd, &mut features) };
        let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
        let family = families.iter().position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE)).ok_or("no compute queue family")? as u32;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
        let info = vk::DeviceCreateInfo::default().queue_create_infos(&queues).enabled_extension_names(&names).push_next(&mut features);
        unsafe { instance.create_device(pd, &info, None) }.map_err(|e| format!("vkCreateDevice: {e}"))
    }

    /// Compiles `kernel` with statistics captured, reads them, and destroys what it made.
    fn compile_and_query(&self, kernel: &TraceKernel) -> Result<Vec<KernelStatistics>, String> {
        let d = &self.device;
        let set_layouts = kernel.groups.iter().map(|g| self.set_layout(g)).collect::<Result<Vec<_>, _>>()?;
        let entry = CString::new(kernel.entry.as_str()).map_err(|e| e.to_string())?;
        // SAFETY: objects made on a live device from valid create infos, each destroyed below
        // whatever happens between.
        let result = unsafe {
            let layout = d
                .create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts), None)
                .map_err(|e| format!("vkCreatePipelineLayout: {e}"));
            let module =
                d.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&kernel.words), None).map_err(|e| format!("vkCreateShaderModule: {e}"));
            let result = match (&layout, &module) {
                (Ok(layout), Ok(module)) => self.pipeline_statistics(kernel, *layout, *module, &entry),
                (Err(e), _) | (_, Err(e)) => Err(e.clone()),
            };
            if let Ok(layout) = layout {
                d.destroy_pipeline_layout(layout, None);
            }
            if let Ok(module) = module {
                d.destroy_shader_module(module, None);
            }
            result
        };
        for l in set_layouts {
            // SAFETY: made above; nothing uses it any more.
            unsafe { d.destroy_descriptor_set_layout(l, None) };
        }
        result
    }

    /// Creates the compute pipeline, reads its executables' statistics and destroys it.
    unsafe fn pipeline_statistics(
        &self,
        kernel: &TraceKernel,
        layout: vk::PipelineLayout,
        module: vk::ShaderModule,
        entry: &std::ffi::CStr,
    ) -> Result<Vec<KernelStatistics>, String> {
        let stage = vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::COMPUTE).module(module).name(entry);
        let info = vk::ComputePipelineCreateInfo::default().flags(vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR).stage(stage).layout(layout);
        let pipeline =
            self.device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None).map_err(|(_, e)| format!("vkCreateComputePipelines: {e}"))?[0];
        let read = || -> Result<Vec<KernelStatistics>, String> {
            let executables = self
                .executables
                .get_pipeline_executable_properties(&vk::PipelineInfoKHR::default().pipeline(pipeline))
                .map_err(|e| format!("executables: {e}"))?;
            let mut out = Vec::new();
            for (index, exe) in executables.iter().enumerate() {
                let which = vk::PipelineExecutableInfoKHR::default().pipeline(pipeline).executable_index(index as u32);
                let stats = self.executables.get_pipeline_executable_statistics(&which).map_err(|e| format!("statistics: {e}"))?;
                let name = exe.name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let statistics = stats.iter().map(statistic).collect();
                out.push(KernelStatistics { label: kernel.label.clone(), executable: name, statistics });
            }
            Ok(out)
        };
        let result = read();
        self.device.destroy_pipeline(pipeline, None);
        result
    }

    /// Group `sorted` (entries sorted by binding, [`TraceKernel::groups`]) as wgpu-hal lays it
    /// out: entry `i` is binding `i` (`crate::spirv_words::binding_map`).
    fn set_layout(&self, sorted: &[wgpu::BindGroupLayoutEntry]) -> Result<vk::DescriptorSetLayout, String> {
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = sorted
            .iter()
            .enumerate()
            .map(|(i, e)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(descriptor_type(&e.ty))
                    .descriptor_count(e.count.map_or(1, |c| c.get()))
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        // SAFETY: a layout made on a live device; the caller destroys it.
        unsafe { self.device.create_descriptor_set_layout(&vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings), None) }
            .map_err(|e| format!("vkCreateDescriptorSetLayout: {e}"))
    }
}

/// The Vulkan descriptor type wgpu-hal gives a binding of type `ty`.
fn descriptor_type(ty: &wgpu::BindingType) -> vk::DescriptorType {
    match ty {
        wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, .. } => vk::DescriptorType::UNIFORM_BUFFER,
        wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, .. } => vk::DescriptorType::UNIFORM_BUFFER_DYNAMIC,
        wgpu::BindingType::Buffer { has_dynamic_offset: false, .. } => vk::DescriptorType::STORAGE_BUFFER,
        wgpu::BindingType::Buffer { .. } => vk::DescriptorType::STORAGE_BUFFER_DYNAMIC,
        wgpu::BindingType::Sampler(_) => vk::DescriptorType::SAMPLER,
        wgpu::BindingType::Texture { .. } | wgpu::BindingType::ExternalTexture => vk::DescriptorType::SAMPLED_IMAGE,
        wgpu::BindingType::StorageTexture { .. } => vk::DescriptorType::STORAGE_IMAGE,
        wgpu::BindingType::AccelerationStructure { .. } => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
    }
}

/// A statistic as (name, value), the value in its own format.
fn statistic(s: &vk::PipelineExecutableStatisticKHR) -> (String, String) {
    let name = s.name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    // SAFETY: the union member read is the one `format` names.
    let value = unsafe {
        match s.format {
            vk::PipelineExecutableStatisticFormatKHR::BOOL32 => (s.value.b32 != 0).to_string(),
            vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => format!("{:.3}", s.value.f64),
            other => format!("(format {other:?})"),
        }
    };
    (name, value)
}
