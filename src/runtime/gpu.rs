//! The GPU context: instance, adapter and device, with the optional features the runtime
//! uses (timestamp queries) requested only where the adapter has them, the GPU deadline every
//! wait runs under, and the runtime checks of each shader module by its origin.

use super::gpu_wait::{GpuWait, WaitMode};
use crate::backend::{self, Backend, Selection};
use crate::error::RuntimeError;
use crate::gpu_util::ShaderOrigin;
use crate::runtime::trace_spirv::{sorted_by_binding, TraceKernel, TraceSpirv};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How long one submission may run before the run ends with [`RuntimeError::GpuTimeout`].
pub(crate) const DEFAULT_GPU_TIMEOUT: Duration = Duration::from_secs(10);
/// The default on a software adapter (lavapipe), which runs a frame a hundred times slower.
pub(crate) const DEFAULT_CPU_ADAPTER_TIMEOUT: Duration = Duration::from_secs(120);

/// The default GPU deadline of `info`'s adapter.
pub(crate) fn default_gpu_timeout(info: &wgpu::AdapterInfo) -> Duration {
    if info.device_type == wgpu::DeviceType::Cpu {
        DEFAULT_CPU_ADAPTER_TIMEOUT
    } else {
        DEFAULT_GPU_TIMEOUT
    }
}

/// The wgpu device raygraph renders with, and what it found out about it: open one with
/// [`Gpu::new`], or wrap a device of the program's own with [`Gpu::from_wgpu`].
pub struct Gpu {
    /// The instance (surfaces are made from it; [`wgpu::Instance::generate_report`] counts
    /// live objects).
    instance: wgpu::Instance,
    /// The adapter the device is on.
    adapter: wgpu::Adapter,
    /// The device.
    device: wgpu::Device,
    /// The device's queue.
    queue: wgpu::Queue,
    /// The adapter's name, type, back-end and driver.
    info: wgpu::AdapterInfo,
    /// Timestamp queries at pass boundaries are available.
    timestamps: bool,
    /// Consecutive compute nodes of a frame are recorded into one compute pass, each between
    /// timestamps written inside it ([`Gpu::merges_compute_passes`]).
    merge_compute_passes: bool,
    /// Texture binding arrays with non-uniform indexing are enabled: scene textures are bound
    /// at their own sizes, pooled (`crate::scene::texture_pool`), instead of as one resampled
    /// texture array.
    texture_binding_arrays: bool,
    /// The compute back-end's arrays are bound as one packed storage buffer
    /// (`shaders/trace/compute_arrays_packed.wgsl`): the device allows fewer storage buffers
    /// per stage than a trace pass with separate arrays binds (`SEPARATE_ARRAYS_STORAGE_BUFFERS`;
    /// a browser's WebGPU allows 8 by default).
    packed_accel_arrays: bool,
    /// The traversal back-end chosen at start-up, and why.
    selection: Selection,
    /// Back-ends the device can run (ray queries are enabled whenever the adapter has them).
    backends: Vec<Backend>,
    /// Device loss and errors raised outside any error scope, as wgpu reported them.
    faults: Arc<Mutex<Faults>>,
    /// Test hook (`RAYGRAPH_INJECT_DEVICE_LOSS=N`): the device is destroyed, a real loss as far
    /// as wgpu and the driver are concerned, when frame N of an executor starts.
    inject_device_loss_at: Option<u32>,
    /// The GPU deadline: the longest a wait for submitted work may take (`--gpu-timeout`;
    /// `default_gpu_timeout`). A wait that runs past it fails with
    /// [`RuntimeError::GpuTimeout`], and so does every later [`Gpu::check`].
    gpu_timeout: Duration,
    /// Called with the error of a wait that ran past the deadline, before it is returned.
    /// Releasing a GPU object after that can block in the driver (lavapipe waits for the stuck
    /// work), so a program that only reports the error and stops ends the process here; the
    /// command line does. Without it the caller must not drop its GPU objects (leak them).
    on_gpu_timeout: Option<fn(&RuntimeError)>,
    /// How the compute back-end's trace modules are written without their traversal stack's
    /// clear ([`super::trace_spirv`]); `None` where wgpu compiles them from WGSL.
    trace_spirv: Option<TraceSpirv>,
    /// How a wait for submitted work waits ([`super::gpu_wait`]).
    wait: GpuWait,
    /// Every trace module written as SPIR-V from now on, once [`Gpu::record_trace_kernels`]
    /// has been called (`render --kernel-stats`, [`super::kernel_stats`]).
    trace_kernels: Option<Mutex<Vec<TraceKernel>>>,
}

impl Gpu {
    /// The instance (surfaces are made from it; [`wgpu::Instance::generate_report`] counts
    /// live objects).
    pub fn instance(&self) -> &wgpu::Instance {
        &self.instance
    }

    /// The adapter the device is on.
    pub fn adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    /// The device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The device's queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter's name, type, back-end and driver.
    pub(crate) fn info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// Timestamp queries at pass boundaries are available.
    pub fn timestamps(&self) -> bool {
        self.timestamps
    }

    /// Whether executors record consecutive compute nodes (compute passes, trace passes
    /// dispatched as compute) into one wgpu compute pass, each node between timestamps written
    /// inside it, and the timestamps of nodes recorded outside a pass straight into the encoder.
    /// On wherever the device writes timestamps inside passes and encoders; off on a device
    /// without timestamp queries (the browser's), and with `RAYGRAPH_PASS_PER_NODE` set: every node is a pass of its own
    /// with the timestamps of its descriptor. The GPU time of every node is measured either way.
    pub fn merges_compute_passes(&self) -> bool {
        self.merge_compute_passes
    }

    /// Turns [`Gpu::merges_compute_passes`] on (where the device can) or off, for executors'
    /// frames from now on: tests record both ways.
    pub fn set_merge_compute_passes(&mut self, on: bool) {
        self.merge_compute_passes = on && can_merge_compute_passes(self.device.features());
    }

    /// Texture binding arrays with non-uniform indexing are enabled: scene textures are bound
    /// at their own sizes, pooled (`crate::scene::texture_pool`), instead of as one resampled
    /// texture array.
    pub fn texture_binding_arrays(&self) -> bool {
        self.texture_binding_arrays
    }

    /// Binds scene textures as a binding array (`true`) or as one resampled texture array
    /// (`false`, which every device can): tests render both ways. `true` only on a device with
    /// the features [`Gpu::device_descriptor`] asks for binding arrays.
    pub fn set_texture_binding_arrays(&mut self, on: bool) {
        self.texture_binding_arrays = on;
    }

    /// The compute back-end's arrays are bound as one packed storage buffer
    /// (`shaders/trace/compute_arrays_packed.wgsl`): the device allows fewer storage buffers
    /// per stage than a trace pass with separate arrays binds (`SEPARATE_ARRAYS_STORAGE_BUFFERS`;
    /// a browser's WebGPU allows 8 by default).
    pub fn packed_accel_arrays(&self) -> bool {
        self.packed_accel_arrays
    }

    /// The traversal back-end chosen at start-up, and why.
    pub fn selection(&self) -> &Selection {
        &self.selection
    }

    /// Back-ends the device can run (ray queries are enabled whenever the adapter has them).
    pub fn backends(&self) -> &[Backend] {
        &self.backends
    }

    /// Test hook (`RAYGRAPH_INJECT_DEVICE_LOSS=N`): the device is destroyed, a real loss as far
    /// as wgpu and the driver are concerned, when frame N of an executor starts.
    pub(crate) fn inject_device_loss_at(&self) -> Option<u32> {
        self.inject_device_loss_at
    }

    /// The GPU deadline: the longest a wait for submitted work may take (`--gpu-timeout`;
    /// `default_gpu_timeout`). A wait that runs past it fails with
    /// [`RuntimeError::GpuTimeout`], and so does every later [`Gpu::check`].
    pub fn gpu_timeout(&self) -> Duration {
        self.gpu_timeout
    }

    /// Sets the GPU deadline ([`Gpu::gpu_timeout`]).
    pub fn set_gpu_timeout(&mut self, timeout: Duration) {
        self.gpu_timeout = timeout;
    }

    /// Sets what is called with the error of a wait that ran past the deadline, before it is
    /// returned. Releasing a GPU object after that can block in the driver (lavapipe waits for
    /// the stuck work), so a program that only reports the error and stops ends the process
    /// here; the command line does. Without it the caller must not drop its GPU objects (leak
    /// them).
    pub fn set_on_gpu_timeout(&mut self, on_timeout: fn(&RuntimeError)) {
        self.on_gpu_timeout = Some(on_timeout);
    }
}

#[derive(Debug, Default)]
struct Faults {
    lost: Option<String>,
    uncaptured: Option<String>,
    /// A wait that ran past the deadline: (seconds, the work it waited for).
    timed_out: Option<(f64, String)>,
}

impl Faults {
    /// Faults of `device` as they happen: its loss, and errors outside every error scope
    /// (wgpu's default handler panics on one; recorded, the next check reports it instead).
    fn watch(device: &wgpu::Device) -> Arc<Mutex<Faults>> {
        let faults = Arc::new(Mutex::new(Faults::default()));
        let on_lost = faults.clone();
        device.set_device_lost_callback(move |reason, message| {
            let reason = match reason {
                wgpu::DeviceLostReason::Destroyed => "the device was destroyed",
                wgpu::DeviceLostReason::Unknown => "the driver reported the device lost",
            };
            let text = if message.is_empty() { reason.to_string() } else { format!("{reason}: {message}") };
            if let Ok(mut f) = on_lost.lock() {
                f.lost.get_or_insert(text);
            }
        });
        let on_error = faults.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            log::error!("GPU error outside an error scope: {e}");
            if let Ok(mut f) = on_error.lock() {
                f.uncaptured.get_or_insert(e.to_string());
            }
        }));
        faults
    }
}

/// Timestamps written inside passes and command encoders (Vulkan has both or neither).
const TIMESTAMPS_INSIDE: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// Whether a device with `features` records consecutive compute nodes into one pass, each
/// node timed inside it: it writes timestamps inside passes and encoders. A device without
/// timestamps (the browser's) keeps one pass per node, the path its page was checked on.
fn can_merge_compute_passes(features: wgpu::Features) -> bool {
    features.contains(wgpu::Features::TIMESTAMP_QUERY) && features.contains(TIMESTAMPS_INSIDE)
}

/// Features that scene texture binding arrays need.
const BINDLESS: wgpu::Features = wgpu::Features::TEXTURE_BINDING_ARRAY.union(wgpu::Features::SAMPLED_TEXTURE_AND_STORAGE_BUFFER_ARRAY_NON_UNIFORM_INDEXING);
/// Storage buffers per shader stage that the built-in trace passes bind with the compute
/// back-end's arrays separate: six of the scene's (instances, materials, meshes, indices,
/// vertices, lights: `shaders/rt/reflection.wgsl`, `gi.wgsl`, `forward/shade.wgsl`), four arrays,
/// the ray counters and the alpha words. Packed, the four arrays and the alpha words are one
/// buffer: 8, WebGPU's default limit.
pub(crate) const SEPARATE_ARRAYS_STORAGE_BUFFERS: u32 = 12;

/// Storage textures per stage of a compute pass that writes the whole G-buffer
/// (`shaders/common/gbuffer_store.wgsl`: position, normal, geometric normal, albedo, material,
/// emissive, lobes).
pub(crate) const GBUFFER_STORAGE_TEXTURES: u32 = 7;

/// Bytes per sample of the fragment-stage G-buffer's colour attachments
/// (`layers/deferred_fragment.ron`), as WebGPU counts them: 16 + 8 + 8 for position and the two
/// normals, 8 for each 8-bit RGBA target (albedo, material), 8 for emission, 16 for the lobes.
pub const GBUFFER_ATTACHMENT_BYTES: u32 = 72;

/// Most scene textures in a binding array.
pub(crate) const MAX_BINDLESS_TEXTURES: u32 = 4096;

/// Whether scene textures are bound as a binding array on a device with `features` and
/// `limits` (never with `RAYGRAPH_NO_BINDLESS` set).
fn bindless_allowed(features: wgpu::Features, limits: &wgpu::Limits) -> bool {
    features.contains(BINDLESS) && limits.max_binding_array_elements_per_shader_stage >= 256 && std::env::var_os("RAYGRAPH_NO_BINDLESS").is_none()
}

impl Gpu {
    /// Compiles a WGSL module with the runtime checks its origin gets ([`ShaderOrigin::checks`]).
    pub(crate) fn shader_module(&self, label: &str, wgsl: &str, origin: ShaderOrigin) -> wgpu::ShaderModule {
        let desc = wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(wgsl.into()) };
        let checks = origin.checks();
        if checks.force_loop_bounding {
            return self.device.create_shader_module(desc);
        }
        // SAFETY: only naga's loop bounding is dropped, and only for modules built on the
        // project's traversal (`ShaderOrigin::TracePass`, `ShaderOrigin::BuiltInTraversal`):
        // traversal loops pop a finite stack; a layer's own endless loop is ended by the frame
        // deadline. Bounds checks and the rest stay.
        unsafe { self.device.create_shader_module_trusted(desc, checks) }
    }

    /// Whether trace passes on the compute back-end clear their traversal stack when each
    /// invocation starts (compiled from WGSL, which zero-initialises it) rather than being
    /// written without that clear (`runtime::trace_spirv`; not on this device, or
    /// `RAYGRAPH_CLEARED_STACK=1`).
    pub fn traversal_stack_cleared(&self) -> bool {
        self.trace_spirv.is_none()
    }

    /// Keeps the SPIR-V of every trace module written from now on, for
    /// [`Gpu::recorded_trace_kernels`]. Only modules written as SPIR-V are kept (the compute
    /// back-end's, where the device takes SPIR-V: [`Gpu::traversal_stack_cleared`] is false).
    pub fn record_trace_kernels(&mut self) {
        self.trace_kernels.get_or_insert_with(|| Mutex::new(Vec::new()));
    }

    /// The trace modules kept since [`Gpu::record_trace_kernels`], in the order they were made.
    pub fn recorded_trace_kernels(&self) -> Vec<TraceKernel> {
        self.trace_kernels.as_ref().map(|log| log.lock().unwrap_or_else(|e| e.into_inner()).clone()).unwrap_or_default()
    }

    /// Compiles the trace modules of executors and batch tracers made from now on from WGSL,
    /// their traversal stack cleared per invocation: the reference the modules without the
    /// clear are tested against.
    pub fn clear_traversal_stack(&mut self) {
        self.trace_spirv = None;
    }

    /// A module built on the compute traversal (a trace pass's, the batch tracer's) for a
    /// pipeline over bind group layouts `groups`, to be made with pipeline `constants`: written
    /// without the traversal stack's clear where the device allows it ([`super::trace_spirv`]),
    /// else compiled from WGSL with `origin`'s checks. Returns the module and the constants
    /// still to give the pipeline (none where they were resolved into the module).
    pub(crate) fn traversal_module<'c>(
        &self,
        label: &str,
        wgsl: &str,
        entry: &str,
        origin: ShaderOrigin,
        constants: &[(&'c str, f64)],
        groups: &[Vec<wgpu::BindGroupLayoutEntry>],
    ) -> (wgpu::ShaderModule, Vec<(&'c str, f64)>) {
        if let Some(spirv) = self.trace_spirv.as_ref().filter(|_| TraceSpirv::applies_to(wgsl)) {
            match spirv.words(wgsl, entry, constants, groups) {
                Ok((words, workgroup_size)) => {
                    if let Some(log) = &self.trace_kernels {
                        let kernel =
                            TraceKernel { label: label.to_string(), entry: entry.to_string(), words: words.clone(), groups: sorted_by_binding(groups) };
                        log.lock().unwrap_or_else(|e| e.into_inner()).push(kernel);
                    }
                    return (TraceSpirv::module_from_words(&self.device, label, entry, words, workgroup_size), Vec::new());
                }
                Err(e) => log::warn!("{label}: compiled from WGSL, its traversal stack cleared per invocation ({e})"),
            }
        }
        (self.shader_module(label, wgsl, origin), constants.to_vec())
    }

    /// Opens the first Vulkan adapter (set `WGPU_BACKEND` to choose another backend, and
    /// `WGPU_ADAPTER_NAME` to pick an adapter by name).
    pub fn new() -> Result<Self, RuntimeError> {
        Self::with_backend(None)
    }

    /// [`Gpu::new`] with the traversal back-end forced (`--backend`); `None` selects one.
    pub fn with_backend(requested: Option<Backend>) -> Result<Self, RuntimeError> {
        Self::open(requested, None)
    }

    /// [`Gpu::with_backend`] for presenting to windows of `display` (the viewer passes winit's
    /// display handle; Vulkan does not need it, other wgpu back-ends may).
    pub fn open(requested: Option<Backend>, display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>) -> Result<Self, RuntimeError> {
        let mut desc = match display {
            Some(display) => wgpu::InstanceDescriptor::new_with_display_handle_from_env(display),
            None => wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
        };
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::VULKAN;
        }
        // wgpu checks every indirect draw's arguments on the GPU, with CPU work per draw when
        // the pass is recorded (80 ns a draw on the H200's host: 2.5 ms a frame at 29,952
        // instances, BENCHMARKS.md "Scale"). raygraph's indirect calls are the scene draws
        // (`exec::draws`), made on the CPU from the upload's index ranges, and the GPU
        // builder's rounds (`accel::gpu_build`: at most 32768 workgroups in x, 1 in y and z), so
        // their arguments are in range by construction; `WGPU_VALIDATION_INDIRECT_CALL=1` turns
        // the check on.
        if std::env::var_os("WGPU_VALIDATION_INDIRECT_CALL").is_none() {
            desc.flags.remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
        }
        let instance = wgpu::Instance::new(desc);
        let adapter =
            pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None)).map_err(|e| RuntimeError::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&Self::device_descriptor(&adapter)))
            .map_err(|e| RuntimeError::Device { adapter: adapter.get_info().name, message: e.to_string() })?;
        Self::from_wgpu(instance, adapter, device, queue, requested)
    }

    /// What raygraph asks of a device on `adapter`: timestamp queries, texture binding arrays
    /// and the ray-tracing features where the adapter has them, and the adapter's own limits
    /// where WebGPU's defaults are too low (G-buffer attachments, storage buffers and
    /// textures per stage, buffer sizes, workgroup memory). A program that opens its own
    /// device requests it with this descriptor and hands it to [`Gpu::from_wgpu`].
    ///
    /// Where the adapter has ray queries or ray-tracing pipelines, the descriptor enables
    /// wgpu's experimental features: raygraph checks every ray it traces (no NaN/Inf or zero
    /// directions, ordered t range); the program's own use of those features is its own.
    pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
        let mut required_features = wgpu::Features::empty();
        if adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
            // Consecutive compute nodes timed inside one pass (`Gpu::merges_compute_passes`).
            if adapter.features().contains(TIMESTAMPS_INSIDE) {
                required_features |= TIMESTAMPS_INSIDE;
            }
        }
        let mut required_limits = wgpu::Limits::default().using_resolution(adapter.limits());
        // G-buffers write more than WebGPU's default 32 bytes per pixel.
        required_limits.max_color_attachment_bytes_per_sample = adapter.limits().max_color_attachment_bytes_per_sample;
        required_limits.max_color_attachments = adapter.limits().max_color_attachments;
        // Trace passes bind the scene's geometry, the back-end's arrays and several G-buffer
        // targets at once: more than WebGPU's defaults (8 storage buffers, 4 storage textures).
        required_limits.max_storage_buffers_per_shader_stage = adapter.limits().max_storage_buffers_per_shader_stage;
        required_limits.max_storage_textures_per_shader_stage = adapter.limits().max_storage_textures_per_shader_stage;
        // Large scenes: the compute back-end binds each BVH array as one storage buffer.
        required_limits.max_storage_buffer_binding_size = adapter.limits().max_storage_buffer_binding_size;
        required_limits.max_buffer_size = adapter.limits().max_buffer_size;
        // The GPU builder's finish keeps its clusters in workgroup memory (accel::gpu_build).
        required_limits.max_compute_workgroup_storage_size = adapter.limits().max_compute_workgroup_storage_size;
        required_limits.max_compute_invocations_per_workgroup = adapter.limits().max_compute_invocations_per_workgroup;
        required_limits.max_compute_workgroup_size_x = adapter.limits().max_compute_workgroup_size_x;
        if bindless_allowed(adapter.features(), &adapter.limits()) {
            required_features |= BINDLESS;
            required_limits.max_binding_array_elements_per_shader_stage =
                adapter.limits().max_binding_array_elements_per_shader_stage.min(MAX_BINDLESS_TEXTURES);
        }
        // Forward shading over a visibility buffer (`layers/forward.ron`) needs the triangle of
        // each fragment.
        required_features |= adapter.features() & wgpu::Features::PRIMITIVE_INDEX;
        // Scene draws as indirect commands (`exec::draws`); without it, drawn one by one.
        required_features |= adapter.features() & wgpu::Features::INDIRECT_FIRST_INSTANCE;
        // The compute back-end's trace modules without their traversal stack's clear
        // (`runtime::trace_spirv`), on Vulkan.
        if adapter.get_info().backend == wgpu::Backend::Vulkan {
            required_features |= adapter.features() & wgpu::Features::PASSTHROUGH_SHADERS;
        }
        let ray_features = adapter.features() & (wgpu::Features::EXPERIMENTAL_RAY_QUERY | wgpu::Features::EXPERIMENTAL_RAY_TRACING_PIPELINES);
        let mut experimental_features = wgpu::ExperimentalFeatures::disabled();
        if !ray_features.is_empty() {
            required_features |= ray_features;
            required_limits = required_limits.using_acceleration_structure_values(adapter.limits());
            // SAFETY: ray queries and ray-tracing pipelines are experimental wgpu features;
            // raygraph checks every ray it traces (no NaN/Inf or zero directions, ordered t
            // range) before tracing.
            experimental_features = unsafe { wgpu::ExperimentalFeatures::enabled() };
        }
        wgpu::DeviceDescriptor {
            label: Some("raygraph"),
            required_features,
            required_limits,
            experimental_features,
            memory_hints: memory_hints_from_env(),
            ..Default::default()
        }
    }

    /// A `Gpu` over a device the program opened itself (best with
    /// [`Gpu::device_descriptor`]), for rendering into its own windows and surfaces. What
    /// raygraph uses is read from the device: timestamps and texture binding arrays where it
    /// has their features, the back-ends its features allow (`requested` forces one; `None`
    /// selects one). A device with lower limits than the descriptor's fails on the first
    /// graph that needs more, with the validation error.
    ///
    /// raygraph installs its device-lost and uncaptured-error callbacks on `device` (they
    /// replace the program's): [`Gpu::check`] reports what they record.
    pub fn from_wgpu(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        requested: Option<Backend>,
    ) -> Result<Self, RuntimeError> {
        let info = adapter.get_info();
        let timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let merge_compute_passes = can_merge_compute_passes(device.features()) && std::env::var_os("RAYGRAPH_PASS_PER_NODE").is_none();
        let texture_binding_arrays = bindless_allowed(device.features(), &device.limits());
        let packed_accel_arrays = device.limits().max_storage_buffers_per_shader_stage < SEPARATE_ARRAYS_STORAGE_BUFFERS;
        let selection = backend::select(device.features(), requested).map_err(|message| RuntimeError::Device { adapter: info.name.clone(), message })?;
        let backends: Vec<Backend> = Backend::ALL.into_iter().filter(|b| device.features().contains(b.features())).collect();
        let faults = Faults::watch(&device);
        let inject_device_loss_at = std::env::var("RAYGRAPH_INJECT_DEVICE_LOSS").ok().and_then(|v| v.parse().ok());
        log::info!("adapter: {} ({:?}, {:?}, driver {} {})", info.name, info.device_type, info.backend, info.driver, info.driver_info);
        if !timestamps {
            log::warn!("adapter has no timestamp queries: GPU pass times are not available");
        }
        log::info!(
            "scene textures: {}",
            if texture_binding_arrays {
                "binding array (one array texture per texture size and encoding)"
            } else {
                "one 256x256 texture array (set by RAYGRAPH_NO_BINDLESS or missing features)"
            }
        );
        log::info!("traversal back-end: {} ({})", selection.backend, selection.reason);
        if packed_accel_arrays {
            log::info!(
                "compute back-end arrays: packed into one storage buffer (the device allows {} storage buffers per stage; separate arrays need {SEPARATE_ARRAYS_STORAGE_BUFFERS})",
                device.limits().max_storage_buffers_per_shader_stage
            );
        }
        let gpu_timeout = default_gpu_timeout(&info);
        let wait = GpuWait::new(WaitMode::from_env(info.device_type).map_err(RuntimeError::Gpu)?);
        log::info!("waiting for the GPU: {:?} (RAYGRAPH_GPU_WAIT)", wait.mode());
        let trace_spirv = TraceSpirv::for_device(&device);
        log::info!(
            "traversal stack: {}",
            if trace_spirv.is_some() { "not cleared (trace modules as SPIR-V)" } else { "cleared per invocation (trace modules from WGSL)" }
        );
        let gpu = Self {
            instance,
            adapter,
            device,
            queue,
            info,
            timestamps,
            merge_compute_passes,
            texture_binding_arrays,
            packed_accel_arrays,
            selection,
            backends,
            faults,
            inject_device_loss_at,
            gpu_timeout,
            on_gpu_timeout: None,
            trace_spirv,
            wait,
            trace_kernels: None,
        };
        gpu.log_layer_aliases();
        Ok(gpu)
    }

    /// Logs the layers this device runs in another form, if any.
    fn log_layer_aliases(&self) {
        let replaced: Vec<String> = self.layer_aliases().iter().map(|(from, to)| format!("{from} -> {to}")).collect();
        if !replaced.is_empty() {
            log::info!("layers in the form this device runs: {}", replaced.join(", "));
        }
    }

    /// Compiler options for this device and its selected back-end.
    pub fn compile_options(&self) -> crate::graph::compile::CompileOptions {
        self.compile_options_for(self.selection.backend)
    }

    /// Compiler options for this device and `backend`.
    pub fn compile_options_for(&self, backend: Backend) -> crate::graph::compile::CompileOptions {
        crate::graph::compile::CompileOptions {
            includes: {
                let mut includes = include_aliases(self.texture_binding_arrays);
                if self.packed_accel_arrays && backend == Backend::Compute {
                    includes.extend(packed_arrays_aliases());
                }
                includes
            },
            layers: self.layer_aliases(),
            backend,
            ..Default::default()
        }
    }

    /// Layers this device runs in another form ([`crate::graph::compile::CompileOptions::layers`]):
    /// without primitive indices in fragment shaders, forward shading over a visibility buffer
    /// (`layers/forward.ron`) becomes forward shading in the fragment stage
    /// (`layers/forward_fragment.ron`).
    ///
    /// With fewer than `GBUFFER_STORAGE_TEXTURES` storage textures per stage (a browser's
    /// WebGPU allows four by default), the G-buffer is not written by one compute pass: the
    /// rasterized one comes from the fragment stage (`layers/deferred_fragment.ron`), and
    /// primary rays write it in two passes (`layers/primary_split.ron`). Where the fragment
    /// stage writes it and the colour attachments take fewer than [`GBUFFER_ATTACHMENT_BYTES`]
    /// per sample (WebGPU's default is 32), it is drawn in three parts (`layers/deferred_split.ron`).
    pub fn layer_aliases(&self) -> std::collections::BTreeMap<String, String> {
        let mut aliases = std::collections::BTreeMap::new();
        let few_storage_textures = self.device.limits().max_storage_textures_per_shader_stage < GBUFFER_STORAGE_TEXTURES;
        if !self.device.features().contains(wgpu::Features::PRIMITIVE_INDEX) {
            aliases.insert("forward".to_string(), "forward_fragment".to_string());
            aliases.insert("deferred".to_string(), "deferred_fragment".to_string());
        }
        if few_storage_textures {
            aliases.insert("deferred".to_string(), "deferred_fragment".to_string());
            aliases.insert("primary".to_string(), "primary_split".to_string());
        }
        if aliases.get("deferred").is_some_and(|l| l == "deferred_fragment")
            && self.device.limits().max_color_attachment_bytes_per_sample < GBUFFER_ATTACHMENT_BYTES
        {
            aliases.insert("deferred".to_string(), "deferred_split".to_string());
        }
        aliases
    }

    /// `back-end (reason)`, for reports.
    pub fn describe_backend(&self) -> String {
        format!("{} ({})", self.selection.backend, self.selection.reason)
    }

    /// One line naming the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        format!("{} ({:?}, {:?}, {} {})", self.info.name, self.info.device_type, self.info.backend, self.info.driver, self.info.driver_info)
    }

    /// Waits for all submitted work; device loss becomes an error, never a hang.
    pub fn wait(&self) -> Result<(), RuntimeError> {
        self.wait_for(|| "the submitted work".into())
    }

    /// Waits for all submitted work for at most [`Gpu::gpu_timeout`]; past it, the error
    /// names the work as `work()` describes it ("frame 3: passes ..."). The device stays busy
    /// after a timeout: end the run without releasing GPU objects ([`Gpu::set_on_gpu_timeout`]).
    pub fn wait_for(&self, work: impl FnOnce() -> String) -> Result<(), RuntimeError> {
        let waited = self.wait.wait(&self.device, self.gpu_timeout);
        if let Err(wgpu::PollError::Timeout) = waited {
            let (seconds, work) = (self.gpu_timeout.as_secs_f64(), work());
            if let Ok(mut f) = self.faults.lock() {
                f.timed_out.get_or_insert((seconds, work.clone()));
            }
            let error = RuntimeError::GpuTimeout { seconds, work };
            if let Some(hook) = self.on_gpu_timeout {
                hook(&error);
            }
            return Err(error);
        }
        self.check()?;
        waited.map(|_| ()).map_err(|e| RuntimeError::Gpu(e.to_string()))
    }

    /// Whether a wait ran past the GPU deadline (the device is still busy with that work).
    pub fn timed_out(&self) -> bool {
        self.faults.lock().is_ok_and(|f| f.timed_out.is_some())
    }

    /// Reports a wait past the deadline, a lost device, then an error wgpu raised outside
    /// every error scope (once).
    pub fn check(&self) -> Result<(), RuntimeError> {
        let Ok(mut f) = self.faults.lock() else { return Ok(()) };
        if let Some((seconds, work)) = &f.timed_out {
            return Err(RuntimeError::GpuTimeout { seconds: *seconds, work: work.clone() });
        }
        if let Some(reason) = &f.lost {
            return Err(RuntimeError::DeviceLost { adapter: self.info.name.clone(), reason: reason.clone() });
        }
        match f.uncaptured.take() {
            Some(e) => Err(RuntimeError::Gpu(e)),
            None => Ok(()),
        }
    }

    /// Opens error scopes for out-of-memory and validation errors around GPU work; close them
    /// with [`GpuScopes::finish`].
    pub fn scopes(&self) -> GpuScopes {
        GpuScopes { oom: self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory), validation: self.device.push_error_scope(wgpu::ErrorFilter::Validation) }
    }

    /// Turns an error caught by an error scope into the error to report: the device's loss if
    /// it is lost (every later call fails with it), out of memory as such, else `context: e`.
    pub(crate) fn scope_error(&self, context: &str, e: wgpu::Error) -> RuntimeError {
        if let Err(lost @ RuntimeError::DeviceLost { .. }) = self.check() {
            return lost;
        }
        match e {
            wgpu::Error::OutOfMemory { source } => {
                RuntimeError::OutOfMemory { adapter: self.info.name.clone(), what: format!("while {context}"), message: source.to_string() }
            }
            e => RuntimeError::Gpu(format!("{context} failed: {e}")),
        }
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // wgpu's queue waits for the queue to go idle when it is dropped, and the device's
        // destruction joins the driver's threads: after a timeout both would wait for the
        // stuck work forever. Their last references are leaked instead; the run is ending.
        if self.timed_out() {
            std::mem::forget(self.queue.clone());
            std::mem::forget(self.device.clone());
        }
    }
}

/// The error scopes of [`Gpu::scopes`] (dropped unfinished, they are popped and forgotten).
pub struct GpuScopes {
    // Fields drop in declaration order and scopes must be popped in reverse order of their
    // push: the validation scope, pushed last, comes first.
    validation: wgpu::ErrorScopeGuard,
    oom: wgpu::ErrorScopeGuard,
}

impl GpuScopes {
    /// Closes the scopes: an error caught while `context` ("creating ...") ran, a lost device
    /// or an earlier uncaptured error becomes the `Err`.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn finish(self, gpu: &Gpu, context: &str) -> Result<(), RuntimeError> {
        pollster::block_on(self.finish_async(gpu, context))
    }

    /// In a browser, which cannot wait for the scopes here: their errors are reported by the
    /// next [`Gpu::check`] (every frame's [`GpuScopes::finish_async`] makes one), as errors
    /// raised outside a scope are; `context` names the work.
    #[cfg(target_arch = "wasm32")]
    pub fn finish(self, gpu: &Gpu, context: &str) -> Result<(), RuntimeError> {
        let (faults, context) = (gpu.faults.clone(), context.to_string());
        // Popped now, in reverse order of their push (later scopes may be pushed before the
        // errors arrive); only the results are awaited later.
        let Self { validation, oom } = self;
        let (validation, oom) = (validation.pop(), oom.pop());
        wasm_bindgen_futures::spawn_local(async move {
            let validation = validation.await;
            if let Some(e) = oom.await.or(validation) {
                if let Ok(mut f) = faults.lock() {
                    f.uncaptured.get_or_insert(format!("{context} failed: {e}"));
                }
            }
        });
        gpu.check()
    }

    /// [`GpuScopes::finish`] as a future (the frame's; it resolves at once natively).
    pub(crate) async fn finish_async(self, gpu: &Gpu, context: &str) -> Result<(), RuntimeError> {
        let Self { validation, oom } = self;
        let (validation, oom) = (validation.pop(), oom.pop());
        let (validation, oom) = (validation.await, oom.await);
        // An error recorded earlier (in a browser, one from a scope popped after its work) is
        // the cause of what this scope caught: it is reported first.
        gpu.check()?;
        match oom.or(validation) {
            Some(e) => Err(gpu.scope_error(context, e)),
            None => Ok(()),
        }
    }
}

/// The include substitutions for a device with or without texture binding arrays.
pub fn include_aliases(texture_binding_arrays: bool) -> crate::graph::reflect::IncludeAliases {
    let mut a = crate::graph::reflect::IncludeAliases::new();
    if texture_binding_arrays {
        a.insert("common/scene_textures.wgsl".into(), "common/scene_textures_bindless.wgsl".into());
        a.insert("common/scene_textures_texels.wgsl".into(), "common/scene_textures_texels_bindless.wgsl".into());
    }
    a
}

/// The include substitutions of the compute back-end's packed arrays
/// ([`Gpu::packed_accel_arrays`]).
pub(crate) fn packed_arrays_aliases() -> crate::graph::reflect::IncludeAliases {
    let mut a = crate::graph::reflect::IncludeAliases::new();
    a.insert("trace/compute_arrays.wgsl".into(), "trace/compute_arrays_packed.wgsl".into());
    a.insert("trace/alpha_words.wgsl".into(), "trace/alpha_words_packed.wgsl".into());
    a
}

/// Every set of include substitutions a device and back-end can select (tests validate each).
pub fn all_include_variants() -> Vec<crate::graph::reflect::IncludeAliases> {
    let mut out = Vec::new();
    for bindless in [false, true] {
        for backend in Backend::ALL {
            out.push(crate::graph::compile::CompileOptions { includes: include_aliases(bindless), backend, ..Default::default() }.all_includes());
        }
        let mut packed = include_aliases(bindless);
        packed.extend(packed_arrays_aliases());
        out.push(crate::graph::compile::CompileOptions { includes: packed, backend: Backend::Compute, ..Default::default() }.all_includes());
    }
    out
}

/// wgpu's device-memory placement policy, `RAYGRAPH_MEMORY_HINTS`, for measuring how placement
/// moves GPU timings: `performance` (wgpu's default), `memory`, or `MIN-MAX` in MiB (the range of
/// sub-allocation block sizes; resources larger than a block get memory of their own). An
/// unreadable value keeps the default, with a warning.
fn memory_hints_from_env() -> wgpu::MemoryHints {
    let Ok(value) = std::env::var("RAYGRAPH_MEMORY_HINTS") else { return wgpu::MemoryHints::Performance };
    let block_range = || {
        let (min, max) = value.split_once('-')?;
        let (min, max): (u64, u64) = (min.trim().parse().ok()?, max.trim().parse().ok()?);
        (min >= 1 && min <= max).then_some((min << 20)..(max << 20))
    };
    match value.trim() {
        "performance" => wgpu::MemoryHints::Performance,
        "memory" => wgpu::MemoryHints::MemoryUsage,
        _ => match block_range() {
            Some(range) => wgpu::MemoryHints::Manual { suballocated_device_memory_block_size: range },
            None => {
                log::warn!("RAYGRAPH_MEMORY_HINTS={value}: expected `performance`, `memory` or MIN-MAX in MiB; using `performance`");
                wgpu::MemoryHints::Performance
            }
        },
    }
}
