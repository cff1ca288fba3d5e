//! Small wgpu helpers shared by the accelerator, the runtime and the viewer: the runtime
//! checks compiled into every shader, compute pipelines, storage buffers with their read-back
//! buffers, and waiting for a mapped read.

use crate::error::RuntimeError;

/// Where a shader module's source comes from, which decides its runtime checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ShaderOrigin {
    /// A file of a project that is not a trace pass: every layer pass's shader, and anything
    /// else read from a shaders directory a user can edit. All of wgpu's runtime checks,
    /// naga's loop bounding included.
    Project,
    /// A trace pass's module: its layer's code together with raygraph's traversal
    /// (`shaders/trace/`). Loop bounding, a 64-bit counter decremented and tested on every loop
    /// iteration so that a driver cannot treat an endless loop as unreachable, costs the BVH
    /// traversal 5-9% on an H100 (PERF.md, step 3), and is compiled per module, not per loop: these
    /// modules go without it. The executor's frame deadline (`Gpu::gpu_timeout`) still ends a
    /// frame whose trace pass loops forever.
    TracePass,
    /// A layer's shader whose files are all raygraph's built-in copies, byte for byte
    /// (`ShaderSource::is_builtin`): part of the program, its loops bounded by what it loops
    /// over (the scene's lights, a PCF radius clamped to 4). No loop bounding: in the fragment
    /// stage it kept the driver from unrolling the shadow-map filter (PERF.md, step 20). A
    /// user's edited copy is [`ShaderOrigin::Project`]; the frame deadline covers both.
    BuiltInLayer,
    /// One of raygraph's own traversal kernels, a fixed part of the program rather than of a
    /// project (the batch tracer of tests and benches): no loop bounding, as for trace passes.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    BuiltInTraversal,
}

impl ShaderOrigin {
    /// All of wgpu's runtime checks; loop bounding only for [`ShaderOrigin::Project`], unless
    /// `RAYGRAPH_SHADER_CHECKS=all` asks for it everywhere.
    pub fn checks(self) -> wgpu::ShaderRuntimeChecks {
        let mut checks = wgpu::ShaderRuntimeChecks::checked();
        checks.force_loop_bounding = self == ShaderOrigin::Project || std::env::var("RAYGRAPH_SHADER_CHECKS").is_ok_and(|v| v == "all");
        checks
    }
}

/// A compute pipeline running `entry` of `module` with an explicit layout.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    compute_pipeline_with(device, label, layout, module, entry, &[])
}

/// [`compute_pipeline`] with values for the module's pipeline-overridable constants.
pub(crate) fn compute_pipeline_with(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
        cache: None,
    })
}

/// A storage buffer that shaders write, that can be cleared and copied out.
pub(crate) fn storage_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A buffer to copy GPU data into and map for reading.
pub(crate) fn readback_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A [`storage_buffer`] and a [`readback_buffer`] of the same size (labelled `LABEL readback`).
pub(crate) fn storage_with_readback(device: &wgpu::Device, label: &str, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
    (storage_buffer(device, label, size), readback_buffer(device, &format!("{label} readback"), size))
}

/// Maps a buffer slice for reading; the future resolves once the map is done. Native: waits
/// for it at once ([`map_read`]). In a browser, which cannot block: awaits the map's callback,
/// which the browser runs from its event loop.
pub(crate) async fn map_read_async<'a>(device: &wgpu::Device, slice: wgpu::BufferSlice<'a>) -> Result<wgpu::BufferView, RuntimeError> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        map_read(device, slice)
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = device;
        web_map::mapped(slice).await
    }
}

/// The browser's side of [`map_read_async`]: a future over the map's callback.
#[cfg(target_arch = "wasm32")]
mod web_map {
    use crate::error::RuntimeError;
    use std::cell::RefCell;
    use std::rc::Rc;
    use std::task::{Poll, Waker};

    #[derive(Default)]
    struct MapState {
        result: Option<Result<(), wgpu::BufferAsyncError>>,
        waker: Option<Waker>,
    }

    pub(super) async fn mapped<'a>(slice: wgpu::BufferSlice<'a>) -> Result<wgpu::BufferView, RuntimeError> {
        let state = Rc::new(RefCell::new(MapState::default()));
        let callback_state = state.clone();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let mut s = callback_state.borrow_mut();
            s.result = Some(r);
            if let Some(w) = s.waker.take() {
                w.wake();
            }
        });
        let result = std::future::poll_fn(|cx| {
            let mut s = state.borrow_mut();
            match s.result.take() {
                Some(r) => Poll::Ready(r),
                None => {
                    s.waker = Some(cx.waker().clone());
                    Poll::Pending
                }
            }
        })
        .await;
        match result {
            Ok(()) => slice.get_mapped_range().map_err(|e| RuntimeError::Gpu(format!("buffer map failed: {e}"))),
            Err(e) => Err(RuntimeError::Gpu(format!("buffer map failed: {e}"))),
        }
    }
}

/// Maps a buffer slice for reading and waits for it.
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn map_read<'a>(device: &wgpu::Device, slice: wgpu::BufferSlice<'a>) -> Result<wgpu::BufferView, RuntimeError> {
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(std::time::Duration::from_secs(120)) })
        .map_err(|e| RuntimeError::Gpu(e.to_string()))?;
    match rx.recv() {
        Ok(Ok(())) => slice.get_mapped_range().map_err(|e| RuntimeError::Gpu(format!("buffer map failed: {e}"))),
        Ok(Err(e)) => Err(RuntimeError::Gpu(format!("buffer map failed: {e}"))),
        Err(_) => Err(RuntimeError::Gpu("buffer map callback was dropped".into())),
    }
}
