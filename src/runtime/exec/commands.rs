//! The frame's command buffers before its last encoder, in submission order, and their
//! finishing. wgpu encodes a command buffer's passes at `CommandEncoder::finish` (validation,
//! resource tracking, the driver's commands): natively the frame is recorded into a few
//! encoders cut between passes, and each one cut is finished on the worker pool while the
//! next is recorded; the last is finished on the recording thread.

use crate::error::RuntimeError;
use crate::runtime::gpu::Gpu;
use web_time::Instant;

/// A command buffer, the CPU milliseconds of finishing it, and the error its finishing raised.
type FinishedPiece = (wgpu::CommandBuffer, f64, Option<wgpu::Error>);

/// A part of the frame before its last encoder.
enum Piece {
    /// Recorded, to be finished with the last one (one worker, or a browser).
    Open(wgpu::CommandEncoder),
    /// Being finished on a worker thread.
    #[cfg(not(target_arch = "wasm32"))]
    Finishing(std::sync::mpsc::Receiver<FinishedPiece>),
    /// Finished already: a command buffer recorded elsewhere (an rt-pipeline pass, the
    /// driver's acceleration-structure build).
    Finished(wgpu::CommandBuffer),
}

/// The frame's pieces before its current encoder.
#[derive(Default)]
pub(super) struct FrameCommands {
    pieces: Vec<Piece>,
}

/// The frame's command buffers in submission order, and the CPU milliseconds of finishing
/// them, summed over the threads that did.
pub(super) struct Finished {
    pub command_buffers: Vec<wgpu::CommandBuffer>,
    pub encode_cpu_ms: f64,
    /// How many encoders the frame was recorded into.
    pub encoders: u32,
}

impl FrameCommands {
    /// How many encoders a frame of `passes` passes is cut into: one per worker thread, at
    /// most `most` ([`Gpu::frame_encoders`]), and at least two passes to each.
    pub fn pieces_for(passes: usize, most: usize) -> usize {
        workers().min(most).min(passes / 2).max(1)
    }

    /// Ends the piece `encoder` holds (natively, a worker starts finishing it), and a new
    /// encoder takes its place.
    pub fn cut(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder) {
        let next = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let piece = std::mem::replace(encoder, next);
        self.pieces.push(start_finishing(gpu, piece));
    }

    /// Adds a command buffer finished elsewhere after the pieces so far (cut the current
    /// encoder first, so that what it holds runs before).
    pub fn push_finished(&mut self, command_buffer: wgpu::CommandBuffer) {
        self.pieces.push(Piece::Finished(command_buffer));
    }

    /// Finishes `last` on this thread (inside the caller's error scopes), waits for the pieces
    /// finishing on workers and returns the command buffers in submission order. An error a
    /// worker's piece raised is the `Err`.
    pub fn finish(self, gpu: &Gpu, last: wgpu::CommandEncoder) -> Result<Finished, RuntimeError> {
        let (last, last_ms) = timed_finish(last);
        let mut encode_cpu_ms = last_ms;
        let encoders = 1 + self.pieces.iter().filter(|p| !matches!(p, Piece::Finished(_))).count() as u32;
        let mut command_buffers = Vec::with_capacity(self.pieces.len() + 1);
        let mut error = None;
        for piece in self.pieces {
            let (buffer, ms, e) = match piece {
                Piece::Open(encoder) => {
                    let (buffer, ms) = timed_finish(encoder);
                    (buffer, ms, None)
                }
                #[cfg(not(target_arch = "wasm32"))]
                Piece::Finishing(receiver) => receiver.recv().map_err(|_| RuntimeError::Gpu("a worker finishing the frame's commands ended".into()))?,
                Piece::Finished(buffer) => (buffer, 0.0, None),
            };
            encode_cpu_ms += ms;
            error = error.or(e);
            command_buffers.push(buffer);
        }
        if let Some(e) = error {
            return Err(gpu.scope_error("recording the frame", e));
        }
        command_buffers.push(last);
        Ok(Finished { command_buffers, encode_cpu_ms, encoders })
    }
}

/// `encoder` finished, and the CPU milliseconds it took.
fn timed_finish(encoder: wgpu::CommandEncoder) -> (wgpu::CommandBuffer, f64) {
    let t = Instant::now();
    let buffer = encoder.finish();
    (buffer, t.elapsed().as_secs_f64() * 1e3)
}

/// Hands `encoder` to a worker of the pool where there is more than one and this thread is
/// not one of them (a worker waiting on its own pool could wait forever), else keeps it to be
/// finished last. Error scopes are per thread: the worker opens its own around the finish.
#[cfg(not(target_arch = "wasm32"))]
fn start_finishing(gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Piece {
    if workers() < 2 || rayon::current_thread_index().is_some() {
        return Piece::Open(encoder);
    }
    let device = gpu.device().clone();
    let (sender, receiver) = std::sync::mpsc::sync_channel(1);
    rayon::spawn(move || {
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (buffer, ms) = timed_finish(encoder);
        let validation = pollster::block_on(validation.pop());
        let error = pollster::block_on(oom.pop()).or(validation);
        let _ = sender.send((buffer, ms, error));
    });
    Piece::Finishing(receiver)
}

/// A browser's WebGPU objects stay on their thread.
#[cfg(target_arch = "wasm32")]
fn start_finishing(_gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Piece {
    Piece::Open(encoder)
}

#[cfg(not(target_arch = "wasm32"))]
fn workers() -> usize {
    rayon::current_num_threads()
}

#[cfg(target_arch = "wasm32")]
fn workers() -> usize {
    1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_cut_into_at_most_one_piece_per_worker_and_two_passes_a_piece() {
        for most in [1, 4] {
            assert_eq!(FrameCommands::pieces_for(0, most), 1);
            assert_eq!(FrameCommands::pieces_for(3, most), 1);
            assert_eq!(FrameCommands::pieces_for(100, most), workers().min(most));
            assert!(FrameCommands::pieces_for(4, most) <= 2);
        }
    }
}
