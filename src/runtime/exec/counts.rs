//! The counts passes' `runs_when` compare (`crate::graph::desc::RunsWhen`): the first two
//! words of each count buffer (a count and its whole), copied out after a frame's last pass
//! and read back with the frame's other read-backs; the next frame decides from them which of
//! those passes it records.

use crate::error::RuntimeError;
use crate::gpu_util::{map_read_async, readback_buffer};
use crate::graph::compile::{Plan, ResourceId};

/// The count buffers of a plan, a read-back buffer with two words for each, and what came back.
pub(super) struct RunCounts {
    /// The count resources (with a slot), in the order of their words in `readback`.
    resources: Vec<ResourceId>,
    readback: wgpu::Buffer,
    /// The last (count, whole) read back for each; `None` before the first frame came back.
    values: Vec<Option<(u32, u32)>>,
}

/// Bytes of a count and its whole: the first two 32-bit words of its buffer.
const COUNT_BYTES: u64 = 8;

impl RunCounts {
    /// The counts `plan`'s passes run by; `None` where no pass has a `runs_when`.
    pub(super) fn of_plan(device: &wgpu::Device, plan: &Plan) -> Option<Self> {
        let mut resources: Vec<ResourceId> = plan.passes.iter().filter_map(|p| p.runs_when.as_ref().map(|(_, r)| *r)).collect();
        resources.sort_unstable();
        resources.dedup();
        resources.retain(|r| plan.resources[*r].slot.is_some());
        if resources.is_empty() {
            return None;
        }
        let readback = readback_buffer(device, "run counts readback", COUNT_BYTES * resources.len() as u64);
        Some(Self { values: vec![None; resources.len()], resources, readback })
    }

    /// The (count, whole) in resource `r` as last read back; `None` before one came back, or
    /// for a count no kept pass writes.
    pub(super) fn count(&self, r: ResourceId) -> Option<(u32, u32)> {
        let k = self.resources.iter().position(|c| *c == r)?;
        self.values[k]
    }

    /// Records the copy of every count and its whole (`buffer_of` a count resource: its
    /// buffer) into the read-back buffer, after the frame's last pass.
    pub(super) fn copy<'a>(&self, encoder: &mut wgpu::CommandEncoder, buffer_of: impl Fn(ResourceId) -> &'a wgpu::Buffer) {
        for (k, r) in self.resources.iter().enumerate() {
            encoder.copy_buffer_to_buffer(buffer_of(*r), 0, &self.readback, COUNT_BYTES * k as u64, COUNT_BYTES);
        }
    }

    /// Reads back the counts copied at the end of the frame just completed.
    pub(super) async fn read(&mut self, device: &wgpu::Device) -> Result<(), RuntimeError> {
        let data = map_read_async(device, self.readback.slice(..)).await?;
        let words: &[u32] = bytemuck::cast_slice(&data);
        for (value, pair) in self.values.iter_mut().zip(words.chunks_exact(2)) {
            *value = Some((pair[0], pair[1]));
        }
        drop(data);
        self.readback.unmap();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::graph::desc::RunsWhen;

    #[test]
    fn below_and_at_least_split_every_count_at_the_fraction_of_its_whole() {
        let below = RunsWhen::Below { buffer: "covered".into(), fraction: 0.25 };
        let at_least = RunsWhen::AtLeast { buffer: "covered".into(), fraction: 0.25 };
        // 1,200 pixels: 300 is a quarter (the fraction here).
        for (count, is_below) in [(0, true), (299, true), (300, false), (1200, false)] {
            assert_eq!(below.holds(count, 1200), is_below, "{count} of 1200");
            assert_eq!(at_least.holds(count, 1200), !is_below, "{count} of 1200");
        }
        // Counts near u32::MAX compare exactly (in f64).
        assert!(below.holds(u32::MAX / 4 - 1, u32::MAX - 3) && !below.holds(u32::MAX / 4, u32::MAX - 3));
        // The count before one came back is its whole: AtLeast of any fraction up to 1 holds.
        assert!(at_least.holds(1, 1) && !below.holds(1, 1));
    }
}
