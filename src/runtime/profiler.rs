//! GPU and CPU timing of passes: a timestamp query pair around every pass (when the adapter
//! has timestamp queries), CPU time of recording each pass, and medians over frames.

use crate::error::RuntimeError;
use crate::gpu_util::{map_read_async, readback_buffer};

/// Timestamp queries for up to `capacity` passes per frame.
pub(crate) struct GpuTimer {
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    capacity: u32,
    period_ns: f32,
    /// This frame's query pair of each pass (`None`: the pass records nothing and reads 0 ms),
    /// set by [`GpuTimer::skip`]; empty: pass i has pair i.
    pairs: std::sync::Mutex<Vec<Option<u32>>>,
}

impl GpuTimer {
    /// Timestamp queries for up to `capacity` passes.
    pub(crate) fn new(device: &wgpu::Device, queue: &wgpu::Queue, capacity: u32) -> Self {
        let count = capacity.max(1) * 2;
        let query_set = device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("pass timestamps"), ty: wgpu::QueryType::Timestamp, count });
        let size = count as u64 * 8;
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamp resolve"),
            size,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = readback_buffer(device, "timestamp readback", size);
        Self { query_set, resolve, readback, capacity: capacity.max(1), period_ns: queue.get_timestamp_period(), pairs: Default::default() }
    }

    /// Leaves the passes `skipped[i]` (nothing to record this frame) out of the frame's
    /// queries: the others take the query pairs in order, so that one resolve reads them all.
    pub(crate) fn skip(&self, skipped: &[bool]) {
        *self.pairs.lock().unwrap_or_else(|e| e.into_inner()) = compact_pairs(skipped);
    }

    /// The query pair of `pass` this frame (`None` past the capacity or for a skipped pass).
    fn pair(&self, pass: u32) -> Option<u32> {
        let pairs = self.pairs.lock().unwrap_or_else(|e| e.into_inner());
        let pair = if pairs.is_empty() { Some(pass) } else { pairs.get(pass as usize).copied().flatten() };
        pair.filter(|p| *p < self.capacity)
    }

    /// How many query pairs the frame of `passes` passes writes.
    fn pairs_written(&self, passes: u32) -> u32 {
        let pairs = self.pairs.lock().unwrap_or_else(|e| e.into_inner());
        let written = if pairs.is_empty() { passes } else { pairs.iter().flatten().count() as u32 };
        written.min(self.capacity)
    }

    /// The timestamp writes around compute pass `pass` (`None` past the capacity).
    pub(crate) fn compute_writes(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.pair(pass).map(|p| wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(p * 2),
            end_of_pass_write_index: Some(p * 2 + 1),
        })
    }

    /// Only the start of `pass` (for work recorded outside a pass: an empty compute pass
    /// writes it).
    pub(crate) fn begin_writes(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.pair(pass).map(|p| wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(p * 2),
            end_of_pass_write_index: None,
        })
    }

    /// Only the end of `pass`.
    pub(crate) fn end_writes(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.pair(pass).map(|p| wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(p * 2 + 1),
        })
    }

    /// The timestamp writes around render pass `pass` (`None` past the capacity).
    pub(crate) fn render_writes(&self, pass: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.pair(pass).map(|p| wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(p * 2),
            end_of_pass_write_index: Some(p * 2 + 1),
        })
    }

    /// The query of the start (`end` false) or the end of `pass` (`None` past the capacity).
    fn query(&self, pass: u32, end: bool) -> Option<u32> {
        self.pair(pass).map(|p| p * 2 + end as u32)
    }

    /// Writes the start (`end` false) or the end of `pass` inside compute pass `cp`, for nodes
    /// recorded together in one pass (`Gpu::merges_compute_passes`).
    pub(crate) fn write_in_pass(&self, cp: &mut wgpu::ComputePass<'_>, pass: u32, end: bool) {
        if let Some(query) = self.query(pass, end) {
            cp.write_timestamp(&self.query_set, query);
        }
    }

    /// Writes the start (`end` false) or the end of `pass` into `encoder`, outside any pass.
    pub(crate) fn write_in_encoder(&self, encoder: &mut wgpu::CommandEncoder, pass: u32, end: bool) {
        if let Some(query) = self.query(pass, end) {
            encoder.write_timestamp(&self.query_set, query);
        }
    }

    /// Marks the start (`end` false) or the end of `pass` for work recorded outside a pass:
    /// a timestamp written into `encoder` where `in_encoder` (the device writes them there),
    /// else an empty compute pass `label` that writes it.
    pub(crate) fn mark(&self, encoder: &mut wgpu::CommandEncoder, pass: u32, end: bool, in_encoder: bool, label: &str) {
        if in_encoder {
            self.write_in_encoder(encoder, pass, end);
            return;
        }
        let timestamp_writes = if end { self.end_writes(pass) } else { self.begin_writes(pass) };
        drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes }));
    }

    /// Records the resolve of the query pairs a frame of `passes` passes wrote into the
    /// readback buffer.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, passes: u32) {
        let n = self.pairs_written(passes) * 2;
        if n == 0 {
            return;
        }
        encoder.resolve_query_set(&self.query_set, 0..n, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, n as u64 * 8);
    }

    /// Reads the GPU milliseconds of each pass (after the frame's submission completed; 0 for
    /// a skipped pass).
    pub async fn read(&self, device: &wgpu::Device, passes: u32) -> Result<Vec<f64>, RuntimeError> {
        let n = self.pairs_written(passes) as usize;
        let shown = passes.min(self.capacity);
        if n == 0 {
            return Ok(vec![0.0; shown as usize]);
        }
        let slice = self.readback.slice(..(n as u64 * 16));
        let data = map_read_async(device, slice).await?;
        let ticks: &[u64] = bytemuck::cast_slice(&data);
        let pair_ms = |p: u32| ticks[2 * p as usize + 1].saturating_sub(ticks[2 * p as usize]) as f64 * self.period_ns as f64 / 1e6;
        let ms = (0..shown).map(|pass| self.pair(pass).filter(|p| (*p as usize) < n).map_or(0.0, pair_ms)).collect();
        drop(data);
        self.readback.unmap();
        Ok(ms)
    }
}

/// The query pair of each pass when the passes `skipped[i]` take none: the others' in order.
fn compact_pairs(skipped: &[bool]) -> Vec<Option<u32>> {
    let mut next = 0;
    skipped
        .iter()
        .map(|&skip| {
            let pair = (!skip).then_some(next);
            next += u32::from(!skip);
            pair
        })
        .collect()
}

/// Where a frame's wall time went outside the passes' recording, in milliseconds of the CPU's
/// clock: what `render --report`, its table and the viewer's overlay show beside the passes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FramePhases {
    /// Following the scene: change detection, uploads, passes built again, the bounds.
    pub scene_ms: f64,
    /// The frame uniforms and lights written, the draw classes and attachment views made.
    pub uniforms_ms: f64,
    /// Resolving the timestamps, submitting, and the error scopes' answer.
    pub submit_ms: f64,
    /// Waiting for the GPU to finish the frame.
    pub wait_ms: f64,
    /// Reading back the timestamps, the ray counters and the SAH probe.
    pub readback_ms: f64,
    /// Of `submit`: finishing the frame's command encoder, where wgpu encodes its passes
    /// (validation, resource tracking, the driver's commands).
    pub finish_ms: f64,
}

impl FramePhases {
    /// The parts with their names, in frame order.
    pub fn parts(&self) -> [(&'static str, f64); 5] {
        [("scene update", self.scene_ms), ("uniforms", self.uniforms_ms), ("submit", self.submit_ms), ("wait", self.wait_ms), ("read-back", self.readback_ms)]
    }

    /// "scene update 0.012, uniforms ..., read-back ... ms" from per-part values.
    fn describe(parts: &[(&str, f64)]) -> String {
        let list: Vec<String> = parts.iter().map(|(name, ms)| format!("{name} {ms:.3}")).collect();
        format!("{} ms", list.join(", "))
    }

    /// The medians over `frames` of every part, and of the finishing inside `submit`, in a line.
    pub fn describe_frames(frames: &[FrameTimings]) -> String {
        let finish = median(&mut frames.iter().map(|f| f.phases.finish_ms).collect::<Vec<_>>());
        format!("{}; of submit, finishing the command encoder {finish:.3} ms", Self::describe(&Self::medians(frames)))
    }

    /// The median of each part over `frames`.
    fn medians(frames: &[FrameTimings]) -> [(&'static str, f64); 5] {
        let names = FramePhases::default().parts().map(|(name, _)| name);
        std::array::from_fn(|k| (names[k], median(&mut frames.iter().map(|f| f.phases.parts()[k].1).collect::<Vec<_>>())))
    }
}

/// Per-pass timings of one frame.
#[derive(Debug, Clone)]
pub struct FrameTimings {
    /// GPU milliseconds per pass (None without timestamp queries).
    pub gpu_ms: Option<Vec<f64>>,
    /// CPU milliseconds spent recording each pass.
    pub cpu_ms: Vec<f64>,
    /// Wall-clock milliseconds from the start of recording to the end of GPU work.
    pub frame_ms: f64,
    /// Ray counts from the GPU counters (graphs with an `Accel` node), all trace passes.
    pub rays: Option<crate::accel::cache::RayStats>,
    /// Ray counts per pass (`Some` for trace passes).
    pub pass_rays: Vec<Option<crate::accel::cache::RayStats>>,
    /// What the acceleration-structure node built this frame.
    pub accel: Option<crate::accel::cache::BuildReport>,
    /// The frame's time outside the passes' recording, by part.
    pub phases: FramePhases,
    /// Per pass: whether the frame left it out (its `runs_when` did not hold, or it had
    /// nothing to draw); such a pass's GPU time reads 0.
    pub skipped: Vec<bool>,
}

/// The median of `values` (sorts them; NaN for none).
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// Median per-pass table over several frames. Trace passes also show rays per pixel and
/// GigaRays/s, from the rays counted on the GPU and the pass's GPU time (`pixels` per frame).
pub fn pass_table(names: &[(String, &'static str)], frames: &[FrameTimings], pixels: u64) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{:<30} {:<12} {:>10} {:>10} {:>10} {:>10}", "pass", "kind", "GPU ms", "CPU ms", "rays/px", "GRays/s");
    let mut gpu_total = 0.0;
    let mut cpu_total = 0.0;
    for (i, (name, kind)) in names.iter().enumerate() {
        let mut cpu: Vec<f64> = frames.iter().map(|f| f.cpu_ms[i]).collect();
        let cpu = median(&mut cpu);
        cpu_total += cpu;
        let mut gpu_median = None;
        let gpu = if frames.iter().all(|f| f.gpu_ms.is_some()) {
            let mut g: Vec<f64> = frames.iter().filter_map(|f| f.gpu_ms.as_ref().map(|v| v[i])).collect();
            let m = median(&mut g);
            gpu_total += m;
            gpu_median = Some(m);
            format!("{m:>10.3}")
        } else {
            format!("{:>10}", "n/a")
        };
        let mut rays: Vec<f64> = frames.iter().filter_map(|f| f.pass_rays.get(i).copied().flatten().map(|r| r.traced() as f64)).collect();
        let (per_px, grays) = if rays.is_empty() {
            (String::new(), String::new())
        } else {
            let r = median(&mut rays);
            let g = gpu_median.filter(|ms| *ms > 0.0).map(|ms| format!("{:>10.4}", r / (ms * 1e-3) / 1e9)).unwrap_or_else(|| format!("{:>10}", "n/a"));
            (format!("{:>10.2}", r / pixels.max(1) as f64), g)
        };
        let line = format!("{name:<30} {kind:<12} {gpu} {cpu:>10.3} {per_px} {grays}");
        let _ = writeln!(s, "{}", line.trim_end());
    }
    let mut frame: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
    let gpu_total = if frames.iter().all(|f| f.gpu_ms.is_some()) { format!("{gpu_total:>10.3}") } else { format!("{:>10}", "n/a") };
    let _ = writeln!(s, "{:<30} {:<12} {gpu_total} {cpu_total:>10.3}", "total (passes)", "");
    let _ = writeln!(s, "frame wall time (median of {}): {:.3} ms", frames.len(), median(&mut frame));
    let _ = writeln!(s, "outside the passes (medians): {}", FramePhases::describe_frames(frames));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skipped_passes_take_no_query_pair_and_the_others_take_theirs_in_order() {
        assert_eq!(compact_pairs(&[false, true, true, false, false, true]), [Some(0), None, None, Some(1), Some(2), None]);
        assert_eq!(compact_pairs(&[false; 3]), [Some(0), Some(1), Some(2)]);
        assert_eq!(compact_pairs(&[true; 2]), [None, None]);
    }
}
