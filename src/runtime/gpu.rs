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
}

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
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("raygraph"),
            required_features,
            required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| RuntimeError::Device { adapter: info.name.clone(), message: e.to_string() })?;
        log::info!("adapter: {} ({:?}, {:?}, driver {} {})", info.name, info.device_type, info.backend, info.driver, info.driver_info);
        if !timestamps {
            log::warn!("adapter has no timestamp queries: GPU pass times are not available");
        }
        Ok(Self { adapter, device, queue, info, timestamps })
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
