//! Warming the GPU up before timed frames: untimed frames are rendered until the GPU has been
//! busy for a minimum time and the frame time has settled.
//!
//! A GPU lowers its clocks while it idles, for example while the CPU opens a scene or builds a
//! BVH between two measurements: on the H100 the SM clock fell from 1980 to 975 MHz within a
//! second of such a gap ("GPU idle" throttling), and a fixed count of two warm-up frames (about
//! 15 ms of work) then left the timed frames to measure the climb back, 1.7-2.3x slow
//! (BENCHMARKS.md, "The slow executors were idle clocks"). Whether a warm-up is enough is read
//! from the frames themselves: the median of the last three frame times against the median of
//! the three before. Short frames leave the GPU idle between them, which can hold the clocks at
//! an intermediate level whose frame times look settled: so on a hardware GPU warm-up starts
//! with a kernel that keeps it fully busy (`clock_pump`).

use super::gpu::Gpu;
use super::profiler::FrameTimings;
#[cfg(not(target_arch = "wasm32"))]
use {super::exec::Executor, crate::error::RuntimeError, crate::scene::Camera, crate::scene::Scene, web_time::Instant};

/// When warm-up may stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarmUp {
    /// Frames rendered at least.
    pub min_frames: u32,
    /// Seconds of rendering at least (a clock ramp takes a few hundred milliseconds of load).
    pub min_seconds: f64,
    /// Seconds after which warm-up stops, settled or not.
    pub max_seconds: f64,
    /// Settled: the last three frames' median within this fraction of the three before.
    pub tolerance: f64,
    /// Seconds of a full-load kernel before the first frame (0: none).
    pub pump_seconds: f64,
}

/// Frames compared to decide whether the frame time has settled: two windows of three.
const WINDOW: usize = 3;

impl WarmUp {
    /// For a hardware GPU: 0.3 s of full load, then at least 0.5 s of frames, settled within 3%,
    /// at most 5 s.
    pub const GPU: WarmUp = WarmUp { min_frames: 2 * WINDOW as u32, min_seconds: 0.5, max_seconds: 5.0, tolerance: 0.03, pump_seconds: 0.3 };
    /// For a software adapter (lavapipe): no clocks to raise, so only the settling test, within
    /// 10% (CPU frame times are noisier), at most 1 s.
    pub(crate) const SOFTWARE: WarmUp = WarmUp { min_frames: 2 * WINDOW as u32, min_seconds: 0.0, max_seconds: 1.0, tolerance: 0.10, pump_seconds: 0.0 };

    /// The policy for `gpu`'s adapter, with at least `min_frames` frames.
    pub fn for_gpu(gpu: &Gpu, min_frames: u32) -> WarmUp {
        let base = if gpu.info().device_type == wgpu::DeviceType::Cpu { WarmUp::SOFTWARE } else { WarmUp::GPU };
        WarmUp { min_frames: base.min_frames.max(min_frames), ..base }
    }

    /// Whether warm-up may stop after frames that took `frame_ms` (in order), `elapsed` seconds
    /// after it began.
    pub fn settled(&self, frame_ms: &[f64], elapsed: f64) -> bool {
        if elapsed >= self.max_seconds {
            return true;
        }
        let n = frame_ms.len();
        if n < (self.min_frames as usize).max(2 * WINDOW) || elapsed < self.min_seconds {
            return false;
        }
        let last = median_of(&frame_ms[n - WINDOW..]);
        let before = median_of(&frame_ms[n - 2 * WINDOW..n - WINDOW]);
        (last - before).abs() <= self.tolerance * before.abs().max(f64::MIN_POSITIVE)
    }

    /// Renders untimed frames of `exec` with `camera` until [`Self::settled`]; returns how many.
    /// With a pump, one frame is rendered before it: an executor's first frame builds what it
    /// needs on the CPU (the BVH: 1.9 s for 1.93M triangles on a 2-core machine), an idle
    /// gap that undid the pump's clocks (PERF.md step 28).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn run(&self, gpu: &Gpu, exec: &mut Executor, scene: &Scene, camera: &Camera) -> Result<u32, RuntimeError> {
        let first = if self.pump_seconds > 0.0 {
            exec.render(gpu, camera, scene)?;
            1
        } else {
            0
        };
        Ok(first + self.until_settled(gpu, || exec.render(gpu, camera, scene).map(|frame| gpu_ms(&frame)))?)
    }

    /// Runs untimed repetitions of any measured work on `gpu` (`measure` returns its
    /// milliseconds: a build's kernels, a rebuild's wall time) until [`Self::settled`], after
    /// `pump_seconds` of full load; returns how many.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn until_settled<E: From<RuntimeError>>(&self, gpu: &Gpu, mut measure: impl FnMut() -> Result<f64, E>) -> Result<u32, E> {
        if self.pump_seconds > 0.0 {
            super::clock_pump::raise_clocks(gpu, self.pump_seconds)?;
        }
        let start = Instant::now();
        let mut times = Vec::new();
        loop {
            times.push(measure()?);
            if self.settled(&times, start.elapsed().as_secs_f64()) {
                return Ok(times.len() as u32);
            }
        }
    }
}

/// A frame's GPU milliseconds (the sum over its passes), or its wall time without timestamps.
pub fn gpu_ms(frame: &FrameTimings) -> f64 {
    frame.gpu_ms.as_ref().map(|v| v.iter().sum()).unwrap_or(frame.frame_ms)
}

fn median_of(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clock_ramp_is_not_settled_until_the_frame_time_stops_falling() {
        // Frame times of a GPU whose clock climbs from half speed: 13.4 ms down to 6.7.
        let ramp = [13.4, 13.0, 12.1, 10.8, 9.5, 8.3, 7.4, 6.9, 6.75, 6.72, 6.74, 6.73, 6.71];
        let policy = WarmUp { min_seconds: 0.0, ..WarmUp::GPU };
        let first = (1..=ramp.len()).find(|&n| policy.settled(&ramp[..n], 0.1)).expect("the ramp settles");
        // Settled once the median of the last three (6.72, 6.74, 6.73) is within 3% of the
        // three before (7.4, 6.9, 6.75): 6.73 against 6.9, at the 12th frame.
        assert_eq!(first, 12, "settled after {first} frames");
    }

    #[test]
    fn steady_frames_still_wait_for_the_minimum_time() {
        let steady = [6.7; 20];
        assert!(!WarmUp::GPU.settled(&steady, 0.2), "0.2 s is below the 0.5 s minimum");
        assert!(WarmUp::GPU.settled(&steady, 0.6));
        assert!(!WarmUp::GPU.settled(&steady[..5], 0.6), "fewer frames than two windows");
    }

    #[test]
    fn warm_up_ends_at_its_time_limit_even_unsettled() {
        let alternating: Vec<f64> = (0..40).map(|i| if i % 2 == 0 { 5.0 } else { 10.0 }).collect();
        let unsettled = [5.0, 5.0, 5.0, 10.0, 10.0, 10.0];
        assert!(!WarmUp::GPU.settled(&unsettled, 1.0));
        assert!(WarmUp::GPU.settled(&alternating, 5.0));
    }

    #[test]
    fn more_minimum_frames_are_kept() {
        assert_eq!(WarmUp { min_frames: 20, ..WarmUp::GPU }.min_frames, 20);
        let steady = [6.7; 10];
        assert!(!WarmUp { min_frames: 20, ..WarmUp::GPU }.settled(&steady, 1.0));
    }
}
