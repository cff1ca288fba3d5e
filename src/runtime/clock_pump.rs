//! Raising the GPU's clocks before a measurement: a compute kernel that keeps every SM busy,
//! submission after submission, for a set time.
//!
//! Frames alone do not always do it. A frame waits for the GPU before the next is recorded, so
//! a short frame leaves the GPU idle part of the time, and at that load the clock governor can
//! hold an intermediate clock for seconds: on the H200, `bench rays` on a 1.93M-triangle file
//! covering 2% of the frame (3 ms frames) measured executors at 1170-1260 MHz after 0.5 s of
//! warm-up frames, 1.5-1.6x slow, and at 345-540 MHz 2.8x slow, while the frame time had
//! "settled" (nvidia-smi sampled every 100 ms, BENCHMARKS.md "The row that did not repeat").
//! Under full load the same GPU went from 345 to 1980 MHz within 0.2 s.

use super::gpu::Gpu;
use crate::error::RuntimeError;
use web_time::Instant;

const SHADER: &str = r#"
struct Pump { iterations: u32 }
@group(0) @binding(0) var<storage, read_write> sink: array<f32>;
@group(0) @binding(1) var<uniform> pump: Pump;

// A chain of dependent multiply-adds per invocation; the result is stored so that the loop is
// not removed.
@compute @workgroup_size(256)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var x = f32(id.x & 1023u) * 1e-3;
    for (var i = 0u; i < pump.iterations; i++) {
        x = fma(x, 0.9999, 1e-4);
    }
    sink[id.x & 1023u] = x;
}
"#;

/// Workgroups a submission dispatches: 512k invocations, several waves on any GPU.
const WORKGROUPS: u32 = 2048;
/// A submission's length once calibrated: long enough that the gaps between submissions
/// (one wait and one submit) are a small share of the time.
const SUBMISSION_MS: f64 = 10.0;
/// Loop iterations of the first submission, doubled until a submission lasts SUBMISSION_MS.
const FIRST_ITERATIONS: u32 = 256;
/// Loop iterations at most (far beyond SUBMISSION_MS on any GPU).
const MAX_ITERATIONS: u32 = 1 << 22;

/// Keeps `gpu` busy for `seconds` of wall time (at least one submission).
pub(crate) fn raise_clocks(gpu: &Gpu, seconds: f64) -> Result<(), RuntimeError> {
    let device = gpu.device();
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("clock pump"), source: wgpu::ShaderSource::Wgsl(SHADER.into()) });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("clock pump"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let sink = crate::gpu_util::storage_buffer(device, "clock pump sink", 4096);
    let params = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("clock pump iterations"),
        size: 16,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("clock pump"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: sink.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: params.as_entire_binding() },
        ],
    });
    let start = Instant::now();
    let mut iterations = FIRST_ITERATIONS;
    loop {
        gpu.queue().write_buffer(&params, 0, bytemuck::bytes_of(&[iterations, 0, 0, 0]));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("clock pump") });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("clock pump"), timestamp_writes: None });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(WORKGROUPS, 1, 1);
        }
        let submitted = Instant::now();
        gpu.queue().submit([encoder.finish()]);
        gpu.wait_for(|| format!("the clock pump's kernel ({iterations} iterations, {WORKGROUPS} workgroups of 256)"))?;
        let ms = submitted.elapsed().as_secs_f64() * 1e3;
        if start.elapsed().as_secs_f64() >= seconds {
            return Ok(());
        }
        if ms < SUBMISSION_MS && iterations < MAX_ITERATIONS {
            iterations *= 2;
        }
    }
}
