//! How the host waits for a submission: polling the device until its queue is empty (the
//! default on a GPU), blocked in the driver (the default on a CPU adapter such as lavapipe,
//! whose threads need the cores), or blocked until shortly before the GPU is expected to finish
//! and then polling. `RAYGRAPH_GPU_WAIT=spin|block|tail|tail:<ms>` chooses.
//!
//! A frame waits for the GPU before the next is recorded. Blocked for the whole wait, the
//! host's core idles, and the work after it (the next frame's recording, wgpu's encoding at
//! `CommandEncoder::finish`, the submission) runs up to 2.5x slower, the more so the longer the
//! wait: on the H200's host hybrid_denoised's time outside its passes was 0.43-0.48 ms blocked
//! and 0.17-0.20 polling, and frames ended 0.5 ms sooner; polling only the last 0.5 ms did not
//! help (BENCHMARKS.md, "Waiting for the GPU"). Polling keeps one core busy while the GPU
//! works.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;
use web_time::Instant;

/// How [`GpuWait::wait`] waits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WaitMode {
    /// Blocked in the driver until the work is done.
    Block,
    /// Blocked until `tail` before the time the last wait took, then polling until done.
    Tail(Duration),
    /// Polling from the start.
    Spin,
}

impl WaitMode {
    /// `block`, `spin`, or `tail` (0.5 ms) or `tail:<ms>`; `None` for anything else.
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "block" => Some(Self::Block),
            "spin" => Some(Self::Spin),
            "tail" => Some(Self::Tail(DEFAULT_TAIL)),
            _ => {
                let ms: f64 = text.strip_prefix("tail:")?.parse().ok()?;
                (ms.is_finite() && ms >= 0.0).then(|| Self::Tail(Duration::from_secs_f64(ms * 1e-3)))
            }
        }
    }

    /// How an adapter of `device_type` waits by default: blocked on a CPU adapter (its own
    /// threads do the GPU's work on the host's cores), polling otherwise.
    pub fn default_for(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            wgpu::DeviceType::Cpu => Self::Block,
            _ => Self::Spin,
        }
    }

    /// `RAYGRAPH_GPU_WAIT`'s mode, or `default_for(device_type)` where it is unset; an unknown
    /// value is an error naming the variable.
    pub fn from_env(device_type: wgpu::DeviceType) -> Result<Self, String> {
        match std::env::var("RAYGRAPH_GPU_WAIT") {
            Err(_) => Ok(Self::default_for(device_type)),
            Ok(text) => Self::parse(&text).ok_or_else(|| format!("RAYGRAPH_GPU_WAIT={text}: expected spin, block, tail or tail:<ms>")),
        }
    }
}

/// What the tail of a wait polls for by default.
const DEFAULT_TAIL: Duration = Duration::from_micros(500);

/// The wait and what it remembers: how long the last one took.
pub struct GpuWait {
    mode: WaitMode,
    /// Seconds the last wait took, as f64 bits.
    last: AtomicU64,
}

impl GpuWait {
    /// Waits in `mode`.
    pub fn new(mode: WaitMode) -> Self {
        Self { mode, last: AtomicU64::new(0f64.to_bits()) }
    }

    /// The mode.
    pub fn mode(&self) -> WaitMode {
        self.mode
    }

    /// Waits for all of `device`'s submitted work, for at most `timeout`.
    pub fn wait(&self, device: &wgpu::Device, timeout: Duration) -> Result<wgpu::PollStatus, wgpu::PollError> {
        let start = Instant::now();
        let waited = match self.mode {
            WaitMode::Block => device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(timeout) }),
            WaitMode::Spin => poll_until_done(device, start + timeout),
            WaitMode::Tail(tail) => {
                let last = Duration::from_secs_f64(f64::from_bits(self.last.load(Ordering::Relaxed)));
                match last.checked_sub(tail).filter(|d| !d.is_zero()).map(|d| d.min(timeout)) {
                    Some(first) => match device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(first) }) {
                        Err(wgpu::PollError::Timeout) => poll_until_done(device, start + timeout),
                        done => done,
                    },
                    None => poll_until_done(device, start + timeout),
                }
            }
        };
        self.last.store(start.elapsed().as_secs_f64().to_bits(), Ordering::Relaxed);
        waited
    }
}

/// Polls `device` until its queue is empty, or fails with a timeout past `deadline`.
fn poll_until_done(device: &wgpu::Device, deadline: Instant) -> Result<wgpu::PollStatus, wgpu::PollError> {
    loop {
        let status = device.poll(wgpu::PollType::Poll)?;
        if status.is_queue_empty() {
            return Ok(status);
        }
        if Instant::now() >= deadline {
            return Err(wgpu::PollError::Timeout);
        }
        std::hint::spin_loop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_are_read_from_their_names() {
        assert_eq!(WaitMode::parse("block"), Some(WaitMode::Block));
        assert_eq!(WaitMode::parse("spin"), Some(WaitMode::Spin));
        assert_eq!(WaitMode::parse("tail"), Some(WaitMode::Tail(DEFAULT_TAIL)));
        assert_eq!(WaitMode::parse("tail:2"), Some(WaitMode::Tail(Duration::from_millis(2))));
        for bad in ["tail:", "tail:-1", "tail:nan", "Block", "wait", ""] {
            assert_eq!(WaitMode::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_gpu_polls_and_a_cpu_adapter_blocks() {
        assert_eq!(WaitMode::default_for(wgpu::DeviceType::DiscreteGpu), WaitMode::Spin);
        assert_eq!(WaitMode::default_for(wgpu::DeviceType::IntegratedGpu), WaitMode::Spin);
        assert_eq!(WaitMode::default_for(wgpu::DeviceType::Cpu), WaitMode::Block);
    }
}
