//! Deforming meshes in the merged layout, and how the cache chooses between a refit and a
//! rebuild. A skinned or morphed mesh keeps its triangles from frame to frame, so the merged
//! tree can be refitted instead of rebuilt: the meshes' current positions (on the GPU, in the
//! layout of [`crate::accel::gpu_records`]) are gathered into the refit's object-space input
//! (`shaders/accel/gather_positions.wgsl`) and the refit recomputes every box. A refitted tree keeps the
//! topology built for other positions, so its quality falls as the meshes move; the
//! `SahProbe` measures the refitted tree's SAH cost on the GPU after every refit (one
//! reduction, a few words read back with the frame's ray counters), and [`RefitPolicy`]
//! rebuilds once it has grown past a threshold over the builder's cost of the last build. A
//! scene that does not change never refits and pays for none of this.

use crate::error::RuntimeError;
use crate::gpu_util::{compute_pipeline, map_read_async, readback_buffer, storage_buffer};
use wgpu::util::DeviceExt;

/// The gather kernel's WGSL.
pub(crate) const DEFORM_WGSL: &str = include_str!("../../shaders/accel/gather_positions.wgsl");
/// The SAH reduction's WGSL.
pub(crate) const SAH_WGSL: &str = include_str!("../../shaders/accel/sah.wgsl");

/// The SAH growth over the builder's cost of the last build past which [`RefitPolicy::Auto`]
/// rebuilds. Measured with `raygraph bench anim` on the H100 (BENCHMARKS.md, "Animation";
/// results/h100/anim/): the trace time of a refitted tree follows its SAH growth (atrium-moving
/// always refitted: x3.8 SAH, 4.2x the trace time), and of the thresholds run (1.1, 1.25, 1.5,
/// 2) 1.1 came closest to the best policy on both scenes (update plus trace time within 3% of
/// always rebuilding on atrium-moving, within 6% of always refitting on organic-skinned),
/// where 1.5 was 19% worse on the atrium.
pub(crate) const REBUILD_SAH_GROWTH: f64 = 1.1;

/// When the merged layout is refitted and when it is rebuilt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RefitPolicy {
    /// Refit while the tree's measured SAH cost stays within `max_growth` times its cost after
    /// the last build; rebuild past it.
    Auto {
        /// The growth that triggers a rebuild.
        max_growth: f64,
    },
    /// Refit until the trace time the refitted tree has cost beyond the rebuilt one (the trace
    /// time of the first frame after the build times the SAH growth over it, summed over the
    /// frames since) reaches what the last rebuild cost; then rebuild ([`RebuildLedger`]).
    /// Without GPU timestamps the ledger has no trace time and `Auto` at
    /// `REBUILD_SAH_GROWTH` decides.
    Cost,
    /// Refit whenever the topology allows (the tree may degrade without bound).
    AlwaysRefit,
    /// Rebuild on every change.
    AlwaysRebuild,
}

impl Default for RefitPolicy {
    fn default() -> Self {
        RefitPolicy::Auto { max_growth: REBUILD_SAH_GROWTH }
    }
}

impl RefitPolicy {
    /// Whether a tree whose SAH cost has grown by `growth` (unknown: `None`) is refitted, with
    /// `ledger` the costs since the last build.
    pub fn refits(&self, growth: Option<f64>, ledger: &RebuildLedger) -> bool {
        match self {
            RefitPolicy::Auto { max_growth } => growth.is_none_or(|g| g <= *max_growth),
            RefitPolicy::Cost => match ledger.owes_rebuild() {
                Some(owes) => !owes,
                None => RefitPolicy::default().refits(growth, ledger),
            },
            RefitPolicy::AlwaysRefit => true,
            RefitPolicy::AlwaysRebuild => false,
        }
    }

    /// The policy's name in reports.
    pub fn name(&self) -> String {
        match self {
            RefitPolicy::Auto { max_growth } => format!("refit until SAH x{max_growth}"),
            RefitPolicy::Cost => "refit until it cost a rebuild".into(),
            RefitPolicy::AlwaysRefit => "always refit".into(),
            RefitPolicy::AlwaysRebuild => "always rebuild".into(),
        }
    }
}

/// What a refitted tree has cost since its build, against what the build cost: the ledger
/// of [`RefitPolicy::Cost`]. The extra trace time of a frame is estimated from the SAH growth
/// (trace time follows it: BENCHMARKS.md, "Animation"), not from the frame's own trace time,
/// which moves with the camera.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RebuildLedger {
    /// Milliseconds the last build took (wall time, its GPU work waited for).
    pub rebuild_ms: Option<f64>,
    /// The trace passes' GPU milliseconds of the first frame after the build.
    pub base_trace_ms: Option<f64>,
    /// The estimated trace milliseconds lost to the refitted tree since the build.
    pub regret_ms: f64,
}

impl RebuildLedger {
    /// A build that took `ms` milliseconds: the ledger starts again.
    pub(crate) fn note_build(&mut self, ms: f64) {
        *self = RebuildLedger { rebuild_ms: Some(ms), base_trace_ms: None, regret_ms: 0.0 };
    }

    /// A frame that traced for `trace_ms` GPU milliseconds with a tree grown by `growth`.
    pub(crate) fn note_frame(&mut self, trace_ms: f64, growth: Option<f64>) {
        match (self.base_trace_ms, growth) {
            (None, _) => self.base_trace_ms = Some(trace_ms),
            (Some(base), Some(g)) => self.regret_ms += base * (g - 1.0).max(0.0),
            (Some(_), None) => {}
        }
    }

    /// Whether the refits have lost as much trace time as a rebuild costs (`None`: not known).
    pub(crate) fn owes_rebuild(&self) -> Option<bool> {
        let (rebuild, _) = (self.rebuild_ms?, self.base_trace_ms?);
        Some(self.regret_ms >= rebuild)
    }
}

/// The gather and SAH pipelines, made once per cache.
pub(crate) struct DeformPipelines {
    gather_layout: wgpu::BindGroupLayout,
    gather: wgpu::ComputePipeline,
    sah_layout: wgpu::BindGroupLayout,
    sah: wgpu::ComputePipeline,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

fn pipeline(
    device: &wgpu::Device,
    label: &str,
    wgsl: &str,
    entry: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(wgsl.into()) });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries });
    let pipeline_layout =
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some(label), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
    let pipeline = compute_pipeline(device, label, &pipeline_layout, &module, entry);
    (layout, pipeline)
}

/// A 1D dispatch of `groups` workgroups split over x and y (x at most 32,768).
fn dispatch_shape(groups: u64) -> (u32, u32) {
    let groups = groups.max(1);
    (groups.min(32768) as u32, groups.div_ceil(32768) as u32)
}

impl DeformPipelines {
    /// Compiles both kernels.
    pub fn new(device: &wgpu::Device) -> Self {
        let (gather_layout, gather) = pipeline(device, "deform gather", DEFORM_WGSL, "gather_positions", &[storage_entry(0, true), storage_entry(1, false)]);
        let uniform = wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let (sah_layout, sah) = pipeline(device, "sah", SAH_WGSL, "sah_partials", &[storage_entry(0, true), storage_entry(1, false), uniform]);
        Self { gather_layout, gather, sah_layout, sah }
    }

    /// Records the gather of the current `positions` into the refit's `object_vertices`
    /// (`count` vertices).
    pub(crate) fn record_gather(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, positions: &wgpu::Buffer, object_vertices: &wgpu::Buffer) {
        let count = object_vertices.size() / 16;
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("deform gather"),
            layout: &self.gather_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: positions.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: object_vertices.as_entire_binding() },
            ],
        });
        let (x, y) = dispatch_shape(count.div_ceil(256));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("deform gather"), timestamp_writes: None });
        pass.set_pipeline(&self.gather);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}

/// The SAH cost of one refitted tree, measured on the GPU after every refit (the cost after
/// the build is the builder's own).
pub(crate) struct SahProbe {
    bind_group: wgpu::BindGroup,
    partials: wgpu::Buffer,
    readback: wgpu::Buffer,
    groups: u64,
    /// A measurement recorded and not yet read.
    pending: bool,
    /// The latest cost read.
    latest: Option<f64>,
}

impl SahProbe {
    /// A probe of the tree in `nodes` (`node_count` nodes in the traversal's layout).
    pub fn new(device: &wgpu::Device, pipelines: &DeformPipelines, nodes: &wgpu::Buffer, node_count: u32) -> Self {
        let groups = (node_count as u64).div_ceil(256).max(1);
        let bytes = 4 * (groups + 1);
        let partials = storage_buffer(device, "sah partials", bytes);
        let readback = readback_buffer(device, "sah partials readback", bytes);
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sah params"),
            contents: bytemuck::cast_slice(&[node_count, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sah"),
            layout: &pipelines.sah_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: nodes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: partials.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: params.as_entire_binding() },
            ],
        });
        Self { bind_group, partials, readback, groups, pending: false, latest: None }
    }

    /// Records a measurement of the tree as it will be when `encoder` has run.
    pub fn record(&mut self, pipelines: &DeformPipelines, encoder: &mut wgpu::CommandEncoder) {
        let (x, y) = dispatch_shape(self.groups);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("sah"), timestamp_writes: None });
            pass.set_pipeline(&pipelines.sah);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        encoder.copy_buffer_to_buffer(&self.partials, 0, &self.readback, 0, self.partials.size());
        self.pending = true;
    }

    /// Reads the measurement recorded, once its frame has finished (nothing to do without one).
    pub async fn read(&mut self, device: &wgpu::Device) -> Result<(), RuntimeError> {
        if !std::mem::take(&mut self.pending) {
            return Ok(());
        }
        let cost = {
            let view = map_read_async(device, self.readback.slice(..)).await?;
            let words: &[f32] = bytemuck::cast_slice(&view);
            let (sums, root) = words.split_at(words.len() - 1);
            let total: f64 = sums.iter().map(|&s| s as f64).sum();
            if root[0] > 0.0 {
                total / root[0] as f64
            } else {
                f64::NAN
            }
        };
        self.readback.unmap();
        self.latest = cost.is_finite().then_some(cost);
        Ok(())
    }

    /// The latest measured SAH cost.
    pub(crate) fn latest(&self) -> Option<f64> {
        self.latest
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cost_policy_rebuilds_once_the_refits_have_lost_a_rebuild() {
        let mut ledger = RebuildLedger::default();
        let policy = RefitPolicy::Cost;
        // Unknown costs: the SAH threshold decides.
        assert!(policy.refits(Some(1.05), &ledger) && !policy.refits(Some(1.2), &ledger));
        ledger.note_build(3.0);
        ledger.note_frame(20.0, Some(1.0)); // the first frame after the build: the base
        assert_eq!(ledger.owes_rebuild(), Some(false));
        ledger.note_frame(20.0, Some(1.05)); // 1 ms lost
        ledger.note_frame(20.0, Some(1.05)); // 2
        assert!(policy.refits(Some(1.05), &ledger));
        ledger.note_frame(35.0, Some(1.05)); // 3: the frame's own trace time plays no part
        assert!((ledger.regret_ms - 3.0).abs() < 1e-9, "{}", ledger.regret_ms);
        assert!(!policy.refits(Some(1.05), &ledger), "3 ms lost: a rebuild's worth");
        ledger.note_build(3.0);
        assert!(policy.refits(Some(1.0), &ledger) || ledger.owes_rebuild().is_none());
    }
}
