//! The GPU BLAS builder for the merged layout's one large BLAS: H-PLOC (Benthin et al., HPG
//! 2024; `shaders/accel/hploc.wgsl`) by default, or the PLOC rounds (Meister and Bittner,
//! "Parallel Locally-Ordered Clustering for Bounding Volume Hierarchy Construction", 2018;
//! `shaders/accel/build.wgsl`) with `RAYGRAPH_GPU_BUILD=ploc`, kept for comparing.
//!
//! The triangles are sorted by the Morton code of their box centres (24 bits up to 2^20
//! triangles, 30 above: [`SHORT_MORTON_UP_TO`]), ties in input order:
//! [`crate::accel::radix_sort`] above 2^17 keys, a bitonic network below (the same order;
//! `RAYGRAPH_GPU_BUILD_SORT=radix|bitonic` forces one, for comparing). H-PLOC then makes
//! the whole tree in one dispatch (each invocation climbs the codes' radix tree from its leaf;
//! a range of more than 16 leaves is merged down to 16 clusters by PLOC rounds in its
//! workgroup, each cluster's nearest among 4 on either side: [`HPLOC_SEARCH_RADIUS`], the root
//! to one), H200 atrium 0.447-0.449 ms a build (with the 24-bit codes) against the rounds'
//! 0.77. With the PLOC rounds instead: the first rounds run
//! within segments of 1024 leaves in workgroup memory (`LOCAL_CLUSTERS`). Then each round,
//! every cluster finds its nearest neighbour (the smallest box around both) among the
//! `SEARCH_RADIUS` clusters on either side in that order, mutual nearest neighbours merge into
//! a new node, and the survivors are compacted in order: one dispatch per round, each
//! workgroup finding the nearest neighbours of the clusters its merges look at in workgroup
//! memory, with decoupled look-back over the workgroups (`RAYGRAPH_GPU_BUILD_ROUND=pair`
//! selects two dispatches per round, the nearest neighbours in between in memory, for
//! comparing). Rounds are dispatched for all clusters and return at once when there is nothing
//! left to do, so they are recorded without reading anything back; the last
//! `FINISH_CLUSTERS` clusters are merged by one workgroup in workgroup memory. Each new node
//! gets its SAH cost (the cheaper of a leaf of at most four triangles and its split), so the
//! tree is collapsed into leaves as it is built. Finally every node walks up to the root to
//! find its first triangle in depth-first order, and the interior nodes write the traversal's
//! layout ([`crate::accel::layout`]: children side by side at `1 + 2 k` for the `k`-th merge,
//! boxes widened outwards as [`crate::accel::layout::widen_down`] does) and the triangles in
//! leaf order. Unused node slots (inside leaves) stay zero and are never referenced. Beside
//! them go what the GPU refit needs ([`crate::accel::refit::TreeRefit`]): each node's parent
//! and each triangle's input index.
//!
//! [`GpuBlasBuilder::build`] records all of it in one submission (the layout does nothing
//! until the root exists), then reads back a few words in one wait: the clusters left (in the
//! rare case that the recorded rounds did not bring them down to the finish's, more rounds and
//! the layout are submitted and read again), the finished tree's depth, its root's SAH cost
//! and the build's timestamps, when the adapter has timestamp queries. The tree stays on the
//! GPU ([`GpuBlas::read_back`] copies it when asked). [`GpuBlasBuilder::build_records_counted`]
//! takes a triangle count that only the GPU knows, so a cache rebuild waits once.

use super::bvh::MAX_TREE_DEPTH;
use super::bvh::{classify_mesh_triangle, TriangleStatus, INTERSECTION_COST, TRAVERSAL_COST};
use super::layout::{merged_flags, GpuBvhNode, GpuTriangle, TriangleOrigin};
use super::radix_sort::{GpuRadixSort, RadixSortJob};
use crate::gpu_util::{compute_pipeline, readback_buffer};
use crate::scene::Mesh;
use wgpu::util::DeviceExt;

/// The builder's WGSL.
pub(crate) const BUILD_WGSL: &str =
    concat!(include_str!("../../shaders/common/lookback.wgsl"), include_str!("../../shaders/accel/build.wgsl"), include_str!("../../shaders/accel/hploc.wgsl"));
/// Most neighbours searched on either side of a cluster (the WGSL's `RADIUS`, the margin of
/// the rounds' window in workgroup memory).
pub(crate) const RADIUS: u32 = 16;
/// Neighbours searched on either side of a cluster by the PLOC rounds (H100, atrium: 8 builds
/// in 0.84 ms with an SAH cost 1.066x the CPU build's; 16 in 1.03 ms, 1.080x; 4 in 0.76 ms,
/// 1.072x). `RAYGRAPH_GPU_BUILD_RADIUS` overrides it and [`HPLOC_SEARCH_RADIUS`], for measuring.
pub(crate) const SEARCH_RADIUS: u32 = 8;
/// Neighbours searched on either side by H-PLOC's rounds (H200, atrium: tree kernel 0.233 ms
/// with an SAH cost 1.063x the CPU build's, against 0.331 ms and 1.074x with 8; organic 1.079x
/// against 1.067x. BENCHMARKS.md, "The GPU rebuild within its budget").
pub(crate) const HPLOC_SEARCH_RADIUS: u32 = 4;
/// Bits of the Morton codes the triangles are sorted by: 24 (a grid of 256 cells an axis, three
/// passes of the radix sort) up to [`SHORT_MORTON_UP_TO`] padded triangles, where the sort's
/// fixed cost per pass is a large share (H200, atrium: kernels 0.483 -> 0.447 ms, the tree's SAH
/// cost 1.066x the CPU build's against 1.063x; BENCHMARKS.md, "The GPU rebuild within its
/// budget"), 30 (1024 cells, four passes) above, where there are fewer cells a triangle.
/// `RAYGRAPH_GPU_BUILD_MORTON_BITS=24|30` forces one, for measuring.
pub(crate) const SHORT_MORTON_BITS: u32 = 24;
/// Bits of the Morton codes above [`SHORT_MORTON_UP_TO`] padded triangles.
pub(crate) const MORTON_BITS: u32 = 30;
/// Padded triangle counts up to which the codes are [`SHORT_MORTON_BITS`] long (16 cells a
/// triangle or more).
pub(crate) const SHORT_MORTON_UP_TO: u64 = 1 << 20;
/// Clusters at or below which one workgroup finishes the tree (`ploc_finish`, one invocation
/// per cluster, the clusters in workgroup memory): the last rounds merge few clusters each,
/// and a dispatch per step would cost more than the work. Also the most the finish holds.
/// `RAYGRAPH_GPU_BUILD_FINISH` lowers it, for measuring.
pub(crate) const FINISH_CLUSTERS: u32 = 1024;
/// Clusters each segment of [`FINISH_CLUSTERS`] leaves is reduced to by `ploc_local` (the
/// first rounds, within the segment, in workgroup memory) before the rounds over all clusters.
/// `RAYGRAPH_GPU_BUILD_LOCAL` overrides it, for measuring.
pub(crate) const LOCAL_CLUSTERS: u32 = 256;
/// The builder [`GpuBlasBuilder`] runs, by the environment (`RAYGRAPH_GPU_BUILD=ploc`: the PLOC
/// rounds; otherwise H-PLOC).
pub fn builder_name() -> &'static str {
    if std::env::var("RAYGRAPH_GPU_BUILD").as_deref() == Ok("ploc") {
        "PLOC rounds"
    } else {
        "H-PLOC"
    }
}

/// Most triangles the GPU builder takes (its dispatch sizes and single-workgroup scan).
pub(crate) const MAX_GPU_BUILD_TRIANGLES: usize = 1 << 23;

const GROUP: u32 = 256;
/// Invocations of an `hploc` workgroup (the WGSL's `HPLOC_TEAM` times `HPLOC_TEAMS`).
const HPLOC_GROUP: u64 = 32;
/// Words of an H-PLOC cluster record (the WGSL's `HPLOC_RECORD`).
const HPLOC_RECORD: u64 = 9;
/// Keys sorted in workgroup memory per block (the WGSL's `SORT_BLOCK`).
const SORT_BLOCK: u32 = 4096;
const PARAMS_STRIDE: u64 = 256;
/// Words of the build's state (the WGSL's `state`): the clusters left, the triangles taken.
const STATE_WORDS: usize = 16;
const STATE_COUNT: usize = 6;
const STATE_N: usize = 15;
/// Storage buffers the builder binds (`tris_in` and bindings 2 to 16).
const STORAGE_BINDINGS: u32 = 16;

/// Why a GPU build did not produce a tree.
#[derive(Debug, thiserror::Error)]
pub enum GpuBuildError {
    /// The triangle count is out of the builder's range.
    #[error("the GPU builder takes 1 to {MAX_GPU_BUILD_TRIANGLES} triangles, not {0}")]
    Size(usize),
    /// The tree is deeper than the traversal stack.
    #[error("the GPU-built tree is {0} levels deep, past the traversal stack's {MAX_TREE_DEPTH}")]
    TooDeep(u32),
    /// The device failed the build.
    #[error("the GPU build did not finish: {0}")]
    Device(String),
}

/// A BLAS built on the GPU, in the layout the `compute` back-end traverses.
pub struct GpuBlas {
    /// `2 n - 1` [`GpuBvhNode`]s, root at 0.
    pub nodes: wgpu::Buffer,
    /// The `n` triangles in leaf order.
    pub triangles: wgpu::Buffer,
    /// Per node: its parent's index + 1; 0 for the root and for unused slots (inside leaves).
    pub parents: wgpu::Buffer,
    /// Per triangle in leaf order: its index in the builder's input.
    pub leaf_order: wgpu::Buffer,
    /// Nodes in `nodes`.
    pub node_count: u32,
    /// Triangles in `triangles`.
    pub triangle_count: u32,
    /// Depth of the deepest leaf (root = 0).
    pub depth: u32,
    /// SAH cost of the tree ([`layout_sah_cost`]'s weights), from the build's own f32 node
    /// costs and unwidened boxes: within a few parts in a million of [`layout_sah_cost`].
    pub sah_cost: f64,
    /// H-PLOC: the merging rounds of all its ranges, summed. PLOC rounds: the rounds that
    /// merged anything (the recorded rounds after the last one dispatch no
    /// work).
    pub rounds: u32,
    /// GPU milliseconds of the build's compute passes (None without timestamp queries).
    pub gpu_ms: Option<f64>,
    /// The same per `Phase`: boxes, Morton codes and sort; the rounds; the finish; layout.
    pub phase_ms: Option<[f64; 4]>,
}

impl GpuBlas {
    /// The built arrays, copied back to the CPU.
    pub fn read_back(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(Vec<GpuBvhNode>, Vec<GpuTriangle>), GpuBuildError> {
        let nodes = read_bytes(device, queue, &self.nodes, 0, self.node_count as u64 * 32)?;
        let tris = read_bytes(device, queue, &self.triangles, 0, self.triangle_count as u64 * 48)?;
        Ok((bytemuck::cast_slice(&nodes).to_vec(), bytemuck::cast_slice(&tris).to_vec()))
    }
}

/// The merged mesh's usable triangles (the ones the CPU builder keeps: in range, finite, with
/// an area) as the builder's input records, each carrying its scene instance and primitive.
pub fn merged_triangles(merged: &Mesh, origin: &[TriangleOrigin]) -> Vec<GpuTriangle> {
    (0..merged.indices.len() / 3)
        .filter_map(|t| {
            let (v, status) = classify_mesh_triangle(merged, t);
            let o = origin.get(t)?;
            (status == TriangleStatus::Valid).then(|| GpuTriangle {
                v0: v[0].to_array(),
                prim: o.prim,
                v1: v[1].to_array(),
                instance: o.instance,
                v2: v[2].to_array(),
                flags: merged_flags(o),
            })
        })
        .collect()
}

/// The SAH cost of a tree in the traversal's layout (root at 0), normalised by the root's
/// area, with the weights of [`crate::accel::bvh::Bvh::sah_cost`]: 1 per interior node, the
/// count per leaf, each times its area over the root's.
pub fn layout_sah_cost(nodes: &[GpuBvhNode]) -> f64 {
    let area = |n: &GpuBvhNode| {
        let d = [0, 1, 2].map(|a| (n.max[a] - n.min[a]).max(0.0) as f64);
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    };
    let Some(root) = nodes.first() else { return 0.0 };
    let root_area = area(root);
    let mut cost = 0.0;
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let Some(n) = nodes.get(i) else { continue };
        let rel = if root_area > 0.0 { area(n) / root_area } else { 1.0 };
        if n.count > 0 {
            cost += rel * INTERSECTION_COST as f64 * n.count as f64;
        } else {
            cost += rel * TRAVERSAL_COST as f64;
            stack.extend([n.left_or_first as usize, n.left_or_first as usize + 1]);
        }
    }
    cost
}

/// The builder's pipelines (one per entry point), made once per device.
pub struct GpuBlasBuilder {
    group0: wgpu::BindGroupLayout,
    prim_boxes: wgpu::ComputePipeline,
    morton: wgpu::ComputePipeline,
    sort_block: wgpu::ComputePipeline,
    sort_step: wgpu::ComputePipeline,
    sort_step_pair: wgpu::ComputePipeline,
    sort_block_merge: wgpu::ComputePipeline,
    ploc_local: wgpu::ComputePipeline,
    ploc_nearest: wgpu::ComputePipeline,
    ploc_merge: wgpu::ComputePipeline,
    ploc_round: wgpu::ComputePipeline,
    ploc_finish: wgpu::ComputePipeline,
    hploc: wgpu::ComputePipeline,
    layout_offsets: wgpu::ComputePipeline,
    layout_write: wgpu::ComputePipeline,
    radix_sort: GpuRadixSort,
}

/// Workgroups for `invocations` threads of [`GROUP`], spread over y past 32768 in x.
fn groups_for(invocations: u64) -> (u32, u32) {
    groups_of(invocations, GROUP as u64)
}

/// Workgroups of `size` invocations for `invocations` threads, spread over y past 32768 in x.
fn groups_of(invocations: u64, size: u64) -> (u32, u32) {
    let g = invocations.div_ceil(size).max(1);
    (g.min(32768) as u32, g.div_ceil(32768) as u32)
}

impl GpuBlasBuilder {
    /// The builder, or why this device cannot run it (its finish needs one workgroup of
    /// `FINISH_CLUSTERS` invocations and 32 KiB of workgroup memory).
    pub fn new(device: &wgpu::Device) -> Result<Self, GpuBuildError> {
        let l = device.limits();
        if l.max_compute_workgroup_storage_size < 32768
            || l.max_compute_invocations_per_workgroup < FINISH_CLUSTERS
            || l.max_compute_workgroup_size_x < FINISH_CLUSTERS
            || l.max_storage_buffers_per_shader_stage < STORAGE_BINDINGS
        {
            return Err(GpuBuildError::Device(format!(
                "the GPU builder needs workgroups of {FINISH_CLUSTERS} invocations, 32 KiB of workgroup memory and {STORAGE_BINDINGS} storage buffers per stage; the device has {}, {} bytes and {}",
                l.max_compute_invocations_per_workgroup, l.max_compute_workgroup_storage_size, l.max_storage_buffers_per_shader_stage
            )));
        }
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("build.wgsl"), source: wgpu::ShaderSource::Wgsl(BUILD_WGSL.into()) });
        let entry = |binding, ty, dynamic| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: dynamic, min_binding_size: None },
            count: None,
        };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let mut entries = vec![entry(0, wgpu::BufferBindingType::Uniform, true), entry(1, wgpu::BufferBindingType::Storage { read_only: true }, false)];
        entries.extend((2..=STORAGE_BINDINGS).map(|b| entry(b, rw, false)));
        let group0 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("gpu build"), entries: &entries });
        let layout0 = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gpu build"),
            bind_group_layouts: &[Some(&group0)],
            immediate_size: 0,
        });
        let pipeline = |name: &str, layout: &wgpu::PipelineLayout| compute_pipeline(device, name, layout, &module, name);
        Ok(Self {
            prim_boxes: pipeline("prim_boxes", &layout0),
            morton: pipeline("morton", &layout0),
            sort_block: pipeline("sort_block", &layout0),
            sort_step: pipeline("sort_step", &layout0),
            sort_step_pair: pipeline("sort_step_pair", &layout0),
            sort_block_merge: pipeline("sort_block_merge", &layout0),
            ploc_local: pipeline("ploc_local", &layout0),
            ploc_nearest: pipeline("ploc_nearest", &layout0),
            ploc_merge: pipeline("ploc_merge", &layout0),
            ploc_round: pipeline("ploc_round", &layout0),
            ploc_finish: pipeline("ploc_finish", &layout0),
            hploc: pipeline("hploc", &layout0),
            layout_offsets: pipeline("layout_offsets", &layout0),
            layout_write: pipeline("layout_write", &layout0),
            radix_sort: GpuRadixSort::new(device),
            group0,
        })
    }

    /// Builds a BLAS over `tris` (every one usable: see [`merged_triangles`]) and waits for it.
    pub fn build(&self, device: &wgpu::Device, queue: &wgpu::Queue, tris: &[GpuTriangle]) -> Result<GpuBlas, GpuBuildError> {
        if tris.is_empty() || tris.len() > MAX_GPU_BUILD_TRIANGLES {
            return Err(GpuBuildError::Size(tris.len()));
        }
        Self::scoped(device, || {
            let contents = bytemuck::cast_slice(tris);
            let tris_in = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("gpu build triangles in"),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            });
            self.build_unscoped(device, queue, &tris_in, tris.len(), None)
        })
    }

    /// Builds a BLAS over the first `count` records of `records` (a storage buffer of
    /// [`GpuTriangle`]s, every one usable: [`crate::accel::gpu_records`] makes them on the
    /// GPU) and waits for it.
    pub fn build_records(&self, device: &wgpu::Device, queue: &wgpu::Queue, records: &wgpu::Buffer, count: usize) -> Result<GpuBlas, GpuBuildError> {
        Self::scoped(device, || self.build_unscoped(device, queue, records, count, None))
    }

    /// Builds a BLAS over the records of `records` whose count only the GPU knows: the `u32`
    /// at byte `offset` of `count` (written by earlier submissions, such as the records
    /// kernel's), at most `capacity`; waits for it. Nothing is read back before the build: the
    /// count is copied into the build's parameters on the GPU, its arrays are sized for
    /// `capacity`, and the one read after it says how many triangles it took
    /// ([`GpuBlas::triangle_count`]; an empty input is [`GpuBuildError::Size`]).
    pub fn build_records_counted(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        records: &wgpu::Buffer,
        (count, offset): (&wgpu::Buffer, u64),
        capacity: usize,
    ) -> Result<GpuBlas, GpuBuildError> {
        Self::scoped(device, || self.build_unscoped(device, queue, records, capacity, Some((count, offset))))
    }

    /// `build` within error scopes: a device error is the build's error.
    fn scoped(device: &wgpu::Device, build: impl FnOnce() -> Result<GpuBlas, GpuBuildError>) -> Result<GpuBlas, GpuBuildError> {
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = build();
        let validation = pollster::block_on(validation.pop());
        if let Some(e) = pollster::block_on(oom.pop()).or(validation) {
            return Err(GpuBuildError::Device(e.to_string()));
        }
        result
    }

    /// The build over the first `n` records of `tris_in` (with `count`, over as many as that
    /// word says, at most `n`), waited for: everything in one submission (the rounds past the
    /// last and the layout before the tree is finished do nothing), then one read of the
    /// build's state and timestamps; more rounds and the layout again in the rare case that
    /// clusters are left.
    fn build_unscoped(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tris_in: &wgpu::Buffer,
        n: usize,
        count: Option<(&wgpu::Buffer, u64)>,
    ) -> Result<GpuBlas, GpuBuildError> {
        if n == 0 || n > MAX_GPU_BUILD_TRIANGLES {
            return Err(GpuBuildError::Size(n));
        }
        let shape = BuildShape::new(n);
        let tuning = Tuning::from_env(shape.padded);
        let sort_steps = if tuning.sort == SortKind::Bitonic { sort_steps(shape.padded) } else { Vec::new() };
        let buffers = BuildBuffers::new(device, &shape, &tuning.params(shape.n32, &sort_steps));
        let [keys, vals, _, _, clusters_a, clusters_b, ..] = &buffers.scratch;
        let even = buffers.bind(device, &self.group0, tris_in, [clusters_a, clusters_b], &buffers.round_groups[1]);
        let odd = buffers.bind(device, &self.group0, tris_in, [clusters_b, clusters_a], &buffers.round_groups[0]);
        let round_dispatch =
            RoundDispatch { bind: [&even, &odd], groups: shape.groups, fused: tuning.fused, indirect: tuning.indirect.then_some(&buffers.round_groups) };
        let radix_job = (tuning.sort == SortKind::Radix).then(|| self.radix_sort.job(device, keys, vals, (shape.n32, shape.n32), tuning.morton_bits));

        let mut timer = Timer::new(device, queue);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("gpu build") });
        if let Some(word) = count {
            buffers.copy_count(&mut encoder, word, 3 + sort_steps.len() as u64, radix_job.as_ref());
        }
        // Boxes, Morton codes, sort; then H-PLOC and the layout, or the first clusters, the
        // rounds down to `finish` clusters (each leaves about 83% of them on the atrium), the
        // finish and the layout.
        self.record_sort(&mut timer.pass(&mut encoder, Phase::Sort), &even, &shape, (&sort_steps, radix_job.as_ref()));
        if tuning.hierarchy {
            return self.finish_hierarchy(device, queue, (encoder, &mut timer), &even, (buffers, &shape));
        }
        // `ploc_local` leaves the clusters where a round of parity 1 reads them.
        let mut rounds = 1u32;
        {
            let mut pass = timer.pass(&mut encoder, Phase::Rounds);
            pass.set_bind_group(0, &even, &[slot(0)]);
            pass.set_pipeline(&self.ploc_local);
            pass.dispatch_workgroups(n.div_ceil(FINISH_CLUSTERS as usize) as u32, 1, 1);
            for _ in 0..tuning.first_rounds(n) {
                self.record_round(&mut pass, rounds, &round_dispatch);
                rounds += 1;
            }
        }
        self.record_finish(&mut timer.pass(&mut encoder, Phase::Finish), &even, slot(1));
        self.record_layout(&mut timer.pass(&mut encoder, Phase::Layout), &even, &shape);
        timer.resolve(&mut encoder);
        queue.submit([encoder.finish()]);
        let (state, phase_ms) = self.run_remaining_rounds(device, queue, &mut timer, (&buffers.state, &shape), &round_dispatch, rounds)?;
        finished_blas(buffers, &state, phase_ms)
    }

    /// The rest of an H-PLOC build (`hploc`: the whole tree in one dispatch, then the layout),
    /// submitted and waited for; fails if the root was not made.
    fn finish_hierarchy(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (mut encoder, timer): (wgpu::CommandEncoder, &mut Timer),
        even: &wgpu::BindGroup,
        (buffers, shape): (BuildBuffers, &BuildShape),
    ) -> Result<GpuBlas, GpuBuildError> {
        {
            let mut pass = timer.pass(&mut encoder, Phase::Rounds);
            pass.set_bind_group(0, even, &[slot(0)]);
            pass.set_pipeline(&self.hploc);
            let (x, y) = groups_of(shape.n as u64, HPLOC_GROUP);
            pass.dispatch_workgroups(x, y, 1);
        }
        self.record_layout(&mut timer.pass(&mut encoder, Phase::Layout), even, shape);
        timer.resolve(&mut encoder);
        queue.submit([encoder.finish()]);
        let (state, phase_ms) = timer.read_with_state(device, queue, &buffers.state)?;
        if state[STATE_COUNT] > 1 {
            return Err(GpuBuildError::Device(format!("H-PLOC did not reach the root: {} clusters left", state[STATE_COUNT])));
        }
        finished_blas(buffers, &state, phase_ms)
    }

    /// Leaf boxes, Morton codes and their sort: by `radix` where there is one, else bitonic
    /// (`sort_steps` after the first blocks).
    fn record_sort(
        &self,
        pass: &mut wgpu::ComputePass,
        even: &wgpu::BindGroup,
        shape: &BuildShape,
        (sort_steps, radix): (&[(u32, u32, SortStep)], Option<&RadixSortJob>),
    ) {
        let padded = shape.padded;
        pass.set_bind_group(0, even, &[slot(0)]);
        dispatch_for(pass, &self.prim_boxes, shape.n as u64);
        if let Some(job) = radix {
            dispatch_for(pass, &self.morton, shape.n as u64);
            self.radix_sort.record(pass, job);
            return;
        }
        dispatch_for(pass, &self.morton, padded);
        pass.set_pipeline(&self.sort_block);
        let blocks = padded / SORT_BLOCK as u64;
        let block_groups = (blocks.min(32768) as u32, blocks.div_ceil(32768) as u32);
        pass.dispatch_workgroups(block_groups.0, block_groups.1, 1);
        for (s, &(_, _, step)) in sort_steps.iter().enumerate() {
            pass.set_bind_group(0, even, &[slot(3 + s as u64)]);
            match step {
                SortStep::Block => {
                    pass.set_pipeline(&self.sort_block_merge);
                    pass.dispatch_workgroups(block_groups.0, block_groups.1, 1);
                }
                SortStep::Single => dispatch_for(pass, &self.sort_step, padded / 2),
                SortStep::Pair => dispatch_for(pass, &self.sort_step_pair, padded / 4),
            }
        }
    }

    /// Reads the build's state and timestamps; while more than one cluster is left, records
    /// four more rounds, the finish and the layout, and reads again (a round merges at least
    /// the closest pair; four that merge nothing are an error, not a loop); `rounds`: the
    /// rounds recorded so far. The state words and the phases' milliseconds of the finished build.
    fn run_remaining_rounds(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        timer: &mut Timer,
        (state, shape): (&wgpu::Buffer, &BuildShape),
        dispatch: &RoundDispatch,
        mut rounds: u32,
    ) -> Result<(Vec<u32>, Option<[f64; 4]>), GpuBuildError> {
        let mut left = u32::MAX;
        loop {
            let (words, phase_ms) = timer.read_with_state(device, queue, state)?;
            if words[STATE_COUNT] <= 1 {
                return Ok((words, phase_ms));
            }
            if words[STATE_COUNT] >= left {
                return Err(GpuBuildError::Device(format!("the rounds made no progress: {left} clusters left")));
            }
            left = words[STATE_COUNT];
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("gpu build rounds") });
            {
                let mut pass = timer.pass(&mut encoder, Phase::Rounds);
                for _ in 0..4 {
                    self.record_round(&mut pass, rounds, dispatch);
                    rounds += 1;
                }
            }
            self.record_finish(&mut timer.pass(&mut encoder, Phase::Finish), dispatch.bind[0], slot(1));
            self.record_layout(&mut timer.pass(&mut encoder, Phase::Layout), dispatch.bind[0], shape);
            timer.resolve(&mut encoder);
            queue.submit([encoder.finish()]);
        }
    }

    /// The depth-first offsets of every node (a walk per triangle), then the traversal's layout.
    fn record_layout(&self, pass: &mut wgpu::ComputePass, even: &wgpu::BindGroup, shape: &BuildShape) {
        pass.set_bind_group(0, even, &[slot(0)]);
        let (x, y) = groups_for(shape.n as u64);
        pass.set_pipeline(&self.layout_offsets);
        pass.dispatch_workgroups(x, y, 1);
        pass.set_pipeline(&self.layout_write);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// The finish: one workgroup, from at most `finish` clusters to the root.
    fn record_finish(&self, pass: &mut wgpu::ComputePass, even: &wgpu::BindGroup, params_offset: u32) {
        pass.set_bind_group(0, even, &[params_offset]);
        pass.set_pipeline(&self.ploc_finish);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// One PLOC round: nearest neighbours; then merges and the survivors compacted in order
    /// into the other cluster array ([`RoundDispatch`] says how it is dispatched); a round with
    /// nothing to do returns at once.
    fn record_round(&self, pass: &mut wgpu::ComputePass, round: u32, dispatch: &RoundDispatch) {
        let parity = (round % 2) as usize;
        pass.set_bind_group(0, dispatch.bind[parity], &[slot(1 + parity as u64)]);
        let pipelines: &[&wgpu::ComputePipeline] = if dispatch.fused { &[&self.ploc_round] } else { &[&self.ploc_nearest, &self.ploc_merge] };
        for pipeline in pipelines {
            pass.set_pipeline(pipeline);
            match dispatch.indirect {
                Some(groups) => pass.dispatch_workgroups_indirect(&groups[parity], 0),
                None => pass.dispatch_workgroups(dispatch.groups.0, dispatch.groups.1, 1),
            }
        }
    }
}

/// How the rounds are dispatched: the bind group of each parity, the workgroups of a round
/// over every triangle, whether a round is one dispatch (`ploc_round`) or two (`ploc_nearest`,
/// `ploc_merge`), and, for indirect dispatches, the workgroups each parity's rounds read
/// (written by the round before, sized for its clusters) instead of that many.
struct RoundDispatch<'a> {
    bind: [&'a wgpu::BindGroup; 2],
    groups: (u32, u32),
    fused: bool,
    indirect: Option<&'a [wgpu::Buffer; 2]>,
}

/// The dynamic offset of params record `s`.
fn slot(s: u64) -> u32 {
    (s * PARAMS_STRIDE) as u32
}

/// Sets `pipeline` and dispatches it for `invocations` threads ([`groups_for`]).
fn dispatch_for(pass: &mut wgpu::ComputePass, pipeline: &wgpu::ComputePipeline, invocations: u64) {
    let (x, y) = groups_for(invocations);
    pass.set_pipeline(pipeline);
    pass.dispatch_workgroups(x, y, 1);
}

/// The sizes of one build over `n` triangles.
struct BuildShape {
    n: usize,
    n32: u32,
    /// Keys sorted: `n` padded to a power of two, at least one sort block.
    padded: u64,
    /// Nodes of the tree, `2 n - 1`.
    nodes: u64,
    /// Workgroups of a dispatch over every triangle (or cluster).
    groups: (u32, u32),
}

impl BuildShape {
    fn new(n: usize) -> Self {
        Self { n, n32: n as u32, padded: n.next_power_of_two().max(SORT_BLOCK as usize) as u64, nodes: 2 * n as u64 - 1, groups: groups_for(n as u64) }
    }
}

/// The bitonic sort's dispatches after the first blocks, as (k, j, kind): the global steps of
/// each stage two at a time (an odd one alone), then the steps below [`SORT_BLOCK`] in
/// workgroup memory.
fn sort_steps(padded: u64) -> Vec<(u32, u32, SortStep)> {
    let mut sort_steps: Vec<(u32, u32, SortStep)> = Vec::new();
    let mut k = 2 * SORT_BLOCK as u64;
    while k <= padded {
        let mut j = k / 2;
        while j >= SORT_BLOCK as u64 {
            if j >= 2 * SORT_BLOCK as u64 {
                sort_steps.push((k as u32, j as u32, SortStep::Pair));
                j /= 4;
            } else {
                sort_steps.push((k as u32, j as u32, SortStep::Single));
                j /= 2;
            }
        }
        sort_steps.push((k as u32, SORT_BLOCK / 2, SortStep::Block));
        k *= 2;
    }
    sort_steps
}

/// Keys (padded to a power of two) above which the radix sort replaces the bitonic network.
/// H200, 2026-11-29 (BENCHMARKS.md, "The GPU rebuild"): the radix sort took 0.192 ms for the
/// atrium's 262,496 keys (bitonic: 0.240, 2^18 padded) and 0.147 for the organic scene's 3,920
/// (bitonic: 0.068): a fixed cost of about 0.14 ms in its four passes. Between the two, with
/// the radix sort's time linear in the keys and the network's in n log^2 n of the padded
/// count, the network is the faster up to 2^17 padded keys.
const RADIX_SORT_ABOVE: u64 = 1 << 17;

/// How the Morton codes are sorted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SortKind {
    /// [`crate::accel::radix_sort`] (above [`RADIX_SORT_ABOVE`] padded keys, or
    /// `RAYGRAPH_GPU_BUILD_SORT=radix`).
    Radix,
    /// The bitonic network (up to [`RADIX_SORT_ABOVE`], or `RAYGRAPH_GPU_BUILD_SORT=bitonic`):
    /// keys padded to a power of two, blocks of [`SORT_BLOCK`] in workgroup memory, then global
    /// steps.
    Bitonic,
}

/// The build's clusters per finish and per local segment, its search radius, its sort,
/// whether a round is one dispatch (`ploc_round`; `RAYGRAPH_GPU_BUILD_ROUND=pair` selects the
/// two dispatches it replaced, for comparing: the same tree) and whether the rounds' dispatches
/// are sized on the GPU for the clusters left (`RAYGRAPH_GPU_BUILD_INDIRECT=1`; by default every
/// round is dispatched for all triangles and returns at once past the clusters left, which the
/// H200 ran faster: atrium 0.770 ms a build against 0.801 indirect), from the environment's
/// overrides (for measuring) or the defaults.
struct Tuning {
    finish: u32,
    local: u32,
    radius: u32,
    morton_bits: u32,
    sort: SortKind,
    fused: bool,
    indirect: bool,
    hierarchy: bool,
}

impl Tuning {
    fn from_env(padded: u64) -> Self {
        let var = |name: &str| std::env::var(name).ok().and_then(|v| v.parse().ok());
        let hierarchy = builder_name() == "H-PLOC";
        let radius = if hierarchy { HPLOC_SEARCH_RADIUS } else { SEARCH_RADIUS };
        Self {
            finish: var("RAYGRAPH_GPU_BUILD_FINISH").unwrap_or(FINISH_CLUSTERS).clamp(2, FINISH_CLUSTERS),
            local: var("RAYGRAPH_GPU_BUILD_LOCAL").unwrap_or(LOCAL_CLUSTERS).clamp(1, FINISH_CLUSTERS),
            radius: var("RAYGRAPH_GPU_BUILD_RADIUS").unwrap_or(radius).clamp(1, RADIUS),
            morton_bits: match var("RAYGRAPH_GPU_BUILD_MORTON_BITS") {
                Some(bits @ (SHORT_MORTON_BITS | MORTON_BITS)) => bits,
                _ if padded <= SHORT_MORTON_UP_TO => SHORT_MORTON_BITS,
                _ => MORTON_BITS,
            },
            sort: match std::env::var("RAYGRAPH_GPU_BUILD_SORT").as_deref() {
                Ok("bitonic") => SortKind::Bitonic,
                Ok("radix") => SortKind::Radix,
                _ if padded > RADIX_SORT_ABOVE => SortKind::Radix,
                _ => SortKind::Bitonic,
            },
            fused: std::env::var("RAYGRAPH_GPU_BUILD_ROUND").as_deref() != Ok("pair"),
            indirect: std::env::var("RAYGRAPH_GPU_BUILD_INDIRECT").as_deref() == Ok("1"),
            hierarchy,
        }
    }

    /// The params records, [`PARAMS_STRIDE`] apart: 0 the base, 1 and 2 the rounds of each
    /// parity, then the sort's steps.
    fn params(&self, n32: u32, sort_steps: &[(u32, u32, SortStep)]) -> Vec<u8> {
        let mut params = vec![0u8; PARAMS_STRIDE as usize * (3 + sort_steps.len())];
        let mut put = |slot: usize, record: [u32; 8]| params[slot * PARAMS_STRIDE as usize..][..32].copy_from_slice(bytemuck::cast_slice(&record));
        let (local, finish, radius, cells) = (self.local, self.finish, self.radius, 1 << (self.morton_bits / 3));
        put(0, [n32, local, 0, 0, finish, radius, cells, 0]);
        put(1, [n32, 0, 0, 0, finish, radius, cells, 0]);
        put(2, [n32, 0, 0, 1, finish, radius, cells, 0]);
        for (s, &(k, j, _)) in sort_steps.iter().enumerate() {
            put(3 + s, [n32, k, j, 0, finish, radius, cells, 0]);
        }
        params
    }

    /// The rounds recorded with the first submission for `n` triangles: enough to bring the
    /// clusters left by the local rounds down to `finish` at about 83% left per round, and two
    /// more (a round with nothing to do costs a dispatch whose workgroups return at once; one
    /// too few costs another submission and wait).
    fn first_rounds(&self, n: usize) -> u32 {
        let (local, finish) = (self.local, self.finish);
        let after_local = n as f64 * local as f64 / FINISH_CLUSTERS as f64;
        if after_local > finish as f64 {
            ((after_local / finish as f64).ln() / 1.2f64.ln()).ceil() as u32 + 3
        } else {
            0
        }
    }
}

/// A build's buffers: its parameters and state, the tree it writes and its scratch arrays.
struct BuildBuffers {
    params: wgpu::Buffer,
    state: wgpu::Buffer,
    out_nodes: wgpu::Buffer,
    out_tris: wgpu::Buffer,
    parents: wgpu::Buffer,
    leaf_order: wgpu::Buffer,
    /// The indirect dispatch of the rounds of each parity (x, y, z workgroups; none at first).
    round_groups: [wgpu::Buffer; 2],
    /// Keys, values, node boxes, node links, clusters a and b, nearest, tile status, offsets.
    scratch: [wgpu::Buffer; 9],
}

impl BuildBuffers {
    fn new(device: &wgpu::Device, shape: &BuildShape, params: &[u8]) -> Self {
        let storage = wgpu::BufferUsages::STORAGE;
        let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let buffer =
            |label: &str, size: u64, usage| device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false });
        let scratch = |label: &str, bytes: u64| buffer(label, bytes.max(16), storage);
        let (n, nodes, padded, (gx, gy)) = (shape.n as u64, shape.nodes, shape.padded, shape.groups);
        let params = init("gpu build params", params, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let mut state = [0u32; STATE_WORDS];
        state[..3].fill(u32::MAX);
        state[STATE_COUNT] = shape.n32;
        state[STATE_N] = shape.n32;
        let state = init("gpu build state", bytemuck::cast_slice(&state), storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST);
        let out_usage = storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        Self {
            params,
            state,
            out_nodes: buffer("BLAS nodes (GPU-built)", nodes * 32, out_usage),
            out_tris: buffer("triangles (GPU-built)", n * 48, out_usage),
            parents: buffer("BLAS parents (GPU-built)", nodes * 4, storage | wgpu::BufferUsages::COPY_SRC),
            leaf_order: buffer("leaf order (GPU-built)", n * 4, storage | wgpu::BufferUsages::COPY_SRC),
            round_groups: [0, 1].map(|_| init("gpu build round groups", bytemuck::cast_slice(&[0u32, 1, 1, 0]), storage | wgpu::BufferUsages::INDIRECT)),
            scratch: [
                scratch("gpu build keys", padded * 4),
                scratch("gpu build values", padded * 4),
                scratch("gpu build node boxes", nodes * 32),
                scratch("gpu build node links", nodes * 16),
                scratch("gpu build clusters a", n * 4),
                scratch("gpu build clusters b", n * 4),
                scratch("gpu build nearest", n * 4),
                // Two sets: the fused rounds use them by turns; H-PLOC's split words and records.
                scratch("gpu build tile status", (2 * gx as u64 * gy as u64).max((1 + HPLOC_RECORD) * n) * 4),
                scratch("gpu build offsets", nodes * 4),
            ],
        }
    }

    /// Copies the triangle count the GPU holds (`word`: buffer, byte offset) into the `slots`
    /// params records, the state's cluster and triangle counts and the radix sort's count.
    fn copy_count(&self, encoder: &mut wgpu::CommandEncoder, (buffer, offset): (&wgpu::Buffer, u64), slots: u64, radix: Option<&RadixSortJob>) {
        for s in 0..slots {
            encoder.copy_buffer_to_buffer(buffer, offset, &self.params, s * PARAMS_STRIDE, 4);
        }
        for word in [STATE_COUNT, STATE_N] {
            encoder.copy_buffer_to_buffer(buffer, offset, &self.state, 4 * word as u64, 4);
        }
        if let Some((sort_state, sort_offset)) = radix.map(RadixSortJob::count_word) {
            encoder.copy_buffer_to_buffer(buffer, offset, sort_state, sort_offset, 4);
        }
    }

    /// The bind group over these buffers, reading clusters from `clusters_in` and writing the
    /// survivors to `clusters_out`, the next round's workgroups to `next_groups`.
    fn bind(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        tris_in: &wgpu::Buffer,
        [clusters_in, clusters_out]: [&wgpu::Buffer; 2],
        next_groups: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        fn b(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        let [keys, vals, node_box, node_link, _, _, nearest, tile_status, offsets] = &self.scratch;
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gpu build"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: &self.params, offset: 0, size: wgpu::BufferSize::new(32) }),
                },
                b(1, tris_in),
                b(2, keys),
                b(3, vals),
                b(4, &self.state),
                b(5, node_box),
                b(6, node_link),
                b(7, clusters_in),
                b(8, clusters_out),
                b(9, nearest),
                b(10, tile_status),
                b(11, offsets),
                b(12, &self.out_nodes),
                b(13, &self.out_tris),
                b(14, &self.parents),
                b(15, &self.leaf_order),
                b(16, next_groups),
            ],
        })
    }
}

/// The finished tree from the build's state words (`state`: depth, rounds, the triangles it
/// took, the root's cost) and its phases' milliseconds; fails for an empty input and for a
/// tree deeper than the traversal stack.
fn finished_blas(buffers: BuildBuffers, state: &[u32], phase_ms: Option<[f64; 4]>) -> Result<GpuBlas, GpuBuildError> {
    let n = state[STATE_N];
    if n == 0 {
        return Err(GpuBuildError::Size(0));
    }
    let depth = state[9];
    if depth as usize >= MAX_TREE_DEPTH {
        return Err(GpuBuildError::TooDeep(depth));
    }
    let gpu_ms = phase_ms.map(|p| p.iter().sum());
    let (root_cost, root_area) = (f32::from_bits(state[12]) as f64, f32::from_bits(state[13]) as f64);
    let sah_cost = if root_area > 0.0 { root_cost / root_area } else { INTERSECTION_COST as f64 * n as f64 };
    Ok(GpuBlas {
        nodes: buffers.out_nodes,
        triangles: buffers.out_tris,
        parents: buffers.parents,
        leaf_order: buffers.leaf_order,
        node_count: 2 * n - 1,
        triangle_count: n,
        depth,
        sah_cost,
        rounds: state[10],
        gpu_ms,
        phase_ms,
    })
}

/// Copies `size` bytes of `buffer` at `offset` back to the CPU.
pub fn read_bytes(device: &wgpu::Device, queue: &wgpu::Queue, buffer: &wgpu::Buffer, offset: u64, size: u64) -> Result<Vec<u8>, GpuBuildError> {
    read_regions(device, queue, &[(buffer, offset, size)])
}

/// Copies each (buffer, offset, size) region back to the CPU in one submission and one wait;
/// their bytes one after another.
fn read_regions(device: &wgpu::Device, queue: &wgpu::Queue, regions: &[(&wgpu::Buffer, u64, u64)]) -> Result<Vec<u8>, GpuBuildError> {
    let total = regions.iter().map(|r| r.2).sum();
    let staging = readback_buffer(device, "gpu build readback", total);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("gpu build readback") });
    let mut at = 0;
    for &(buffer, offset, size) in regions {
        encoder.copy_buffer_to_buffer(buffer, offset, &staging, at, size);
        at += size;
    }
    queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuBuildError::Device(e.to_string()))?;
    rx.recv().map_err(|e| GpuBuildError::Device(e.to_string()))?.map_err(|e| GpuBuildError::Device(e.to_string()))?;
    let bytes = slice.get_mapped_range().map_err(|e| GpuBuildError::Device(e.to_string()))?.to_vec();
    staging.unmap();
    Ok(bytes)
}

/// A dispatch of the bitonic sort after the first blocks.
#[derive(Debug, Clone, Copy)]
enum SortStep {
    /// Steps j and j / 2 of a stage (`sort_step_pair`).
    Pair,
    /// Step j alone (`sort_step`).
    Single,
    /// The stage's steps below the block size, in workgroup memory (`sort_block_merge`).
    Block,
}

/// The parts of a build the timestamps tell apart.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Phase {
    /// Leaf boxes, Morton codes and their sort.
    Sort = 0,
    /// The PLOC rounds down to [`FINISH_CLUSTERS`], or H-PLOC's one dispatch.
    Rounds = 1,
    /// The one-workgroup finish.
    Finish = 2,
    /// Depth-first offsets and the traversal layout.
    Layout = 3,
}

/// Timestamps around each compute pass of a build, by [`Phase`] (nothing without timestamp
/// queries).
struct Timer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    phases: Vec<Phase>,
    resolved: u32,
    period_ns: f32,
}

const TIMER_PASSES: u32 = 64;

impl Timer {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let queries = device.features().contains(wgpu::Features::TIMESTAMP_QUERY).then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("gpu build timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * TIMER_PASSES,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("gpu build timestamp resolve"),
                size: wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT * TIMER_PASSES as u64,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            (set, resolve)
        });
        Self { queries, phases: Vec::new(), resolved: 0, period_ns: queue.get_timestamp_period() }
    }

    fn pass<'e>(&mut self, encoder: &'e mut wgpu::CommandEncoder, phase: Phase) -> wgpu::ComputePass<'e> {
        let timestamp_writes = match &self.queries {
            Some((set, _)) if (self.phases.len() as u32) < TIMER_PASSES => {
                let k = self.phases.len() as u32;
                self.phases.push(phase);
                Some(wgpu::ComputePassTimestampWrites { query_set: set, beginning_of_pass_write_index: Some(2 * k), end_of_pass_write_index: Some(2 * k + 1) })
            }
            _ => None,
        };
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("gpu build"), timestamp_writes }).forget_lifetime()
    }

    /// Resolves the passes recorded since the last call (each pair into its own aligned slot).
    fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Some((set, resolve)) = &self.queries {
            for k in self.resolved..self.phases.len() as u32 {
                encoder.resolve_query_set(set, 2 * k..2 * k + 2, resolve, wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT * k as u64);
            }
            self.resolved = self.phases.len() as u32;
        }
    }

    /// The build's state words and the phases' milliseconds so far (None without timestamp
    /// queries or past [`TIMER_PASSES`]), in one read.
    fn read_with_state(&self, device: &wgpu::Device, queue: &wgpu::Queue, state: &wgpu::Buffer) -> Result<(Vec<u32>, Option<[f64; 4]>), GpuBuildError> {
        let stride = wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT;
        let state_bytes = 4 * STATE_WORDS as u64;
        let timed = match &self.queries {
            Some((_, resolve)) if !self.phases.is_empty() && (self.phases.len() as u32) < TIMER_PASSES => Some(resolve),
            _ => None,
        };
        let mut regions = vec![(state, 0, state_bytes)];
        regions.extend(timed.map(|resolve| (resolve, 0, stride * self.phases.len() as u64)));
        let bytes = read_regions(device, queue, &regions)?;
        let words = bytemuck::cast_slice(&bytes[..state_bytes as usize]).to_vec();
        if timed.is_none() {
            return Ok((words, None));
        }
        let mut ms = [0.0; 4];
        for (c, &phase) in bytes[state_bytes as usize..].chunks(stride as usize).zip(&self.phases) {
            let p: &[u64] = bytemuck::cast_slice(&c[..16]);
            ms[phase as usize] += p[1].saturating_sub(p[0]) as f64 * self.period_ns as f64 * 1e-6;
        }
        Ok((words, Some(ms)))
    }
}
