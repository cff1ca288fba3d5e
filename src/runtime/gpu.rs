//! The GPU context: instance, adapter and device, with the optional features the runtime
//! uses (timestamp queries) requested only where the adapter has them.

use crate::error::RuntimeError;

pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Timestamp queries at pass boundaries are available.
    pub timestamps: bool,
    /// Texture binding arrays with non-uniform indexing are enabled: scene textures are bound
    /// one texture per element instead of as one resampled texture array.
    pub texture_binding_arrays: bool,
}

/// Features that scene texture binding arrays need.
const BINDLESS: wgpu::Features = wgpu::Features::TEXTURE_BINDING_ARRAY.union(wgpu::Features::SAMPLED_TEXTURE_AND_STORAGE_BUFFER_ARRAY_NON_UNIFORM_INDEXING);
/// Most scene textures in a binding array.
pub const MAX_BINDLESS_TEXTURES: u32 = 4096;

impl Gpu {
    /// Opens the first Vulkan adapter (set `WGPU_BACKEND` to choose another backend, and
    /// `WGPU_ADAPTER_NAME` to pick an adapter by name).
    pub fn new() -> Result<Self, RuntimeError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::VULKAN;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None))
            .map_err(|e| RuntimeError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let mut required_limits = wgpu::Limits::default().using_resolution(adapter.limits());
        let texture_binding_arrays = adapter.features().contains(BINDLESS)
            && adapter.limits().max_binding_array_elements_per_shader_stage >= 256
            && std::env::var_os("RAYGRAPH_NO_BINDLESS").is_none();
        if texture_binding_arrays {
            required_features |= BINDLESS;
            required_limits.max_binding_array_elements_per_shader_stage = adapter.limits().max_binding_array_elements_per_shader_stage.min(MAX_BINDLESS_TEXTURES);
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("raygraph"),
            required_features,
            required_limits,
            ..Default::default()
        }))
        .map_err(|e| RuntimeError::Device { adapter: info.name.clone(), message: e.to_string() })?;
        log::info!("adapter: {} ({:?}, {:?}, driver {} {})", info.name, info.device_type, info.backend, info.driver, info.driver_info);
        if !timestamps {
            log::warn!("adapter has no timestamp queries: GPU pass times are not available");
        }
        log::info!(
            "scene textures: {}",
            if texture_binding_arrays { "binding array (one texture per element)" } else { "one 256x256 texture array (set by RAYGRAPH_NO_BINDLESS or missing features)" }
        );
        Ok(Self { adapter, device, queue, info, timestamps, texture_binding_arrays })
    }

    /// Compiler options for this device: the include substitutions its features select.
    pub fn compile_options(&self) -> crate::graph::compile::CompileOptions {
        let mut options = crate::graph::compile::CompileOptions::default();
        options.includes = include_aliases(self.texture_binding_arrays);
        options
    }

    /// One line naming the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        format!("{} ({:?}, {:?}, {} {})", self.info.name, self.info.device_type, self.info.backend, self.info.driver, self.info.driver_info)
    }

    /// Waits for all submitted work; device loss becomes an error, never a hang.
    pub fn wait(&self) -> Result<(), RuntimeError> {
        self.device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(std::time::Duration::from_secs(120)) })
            .map(|_| ())
            .map_err(|e| RuntimeError::Gpu(e.to_string()))
    }
}

/// The include substitutions for a device with or without texture binding arrays.
pub fn include_aliases(texture_binding_arrays: bool) -> crate::graph::reflect::IncludeAliases {
    let mut a = crate::graph::reflect::IncludeAliases::new();
    if texture_binding_arrays {
        a.insert("common/scene_textures.wgsl".into(), "common/scene_textures_bindless.wgsl".into());
    }
    a
}

/// Every set of include substitutions a device can select (tests validate each).
pub fn all_include_variants() -> Vec<crate::graph::reflect::IncludeAliases> {
    vec![include_aliases(false), include_aliases(true)]
}
