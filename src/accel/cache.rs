//! The acceleration-structure cache behind a graph's `Accel` node. Keyed by content hashes of
//! the meshes (positions and indices) and of the instances (mesh and transform):
//!
//! - unchanged scene: no build work at all;
//! - a mesh's geometry changed: only that mesh's BLAS is rebuilt (one per instance of it
//!   without de-duplication), then the TLAS;
//! - instances moved: the TLAS only — refitted in the `compute` back-end when the set of
//!   instances is the same, rebuilt in `ray-query` (wgpu has no refit);
//! - identical meshes share one BLAS unless de-duplication is off;
//! - the merged layout rebuilt by the GPU builder stays on the GPU: the traversal binds the
//!   builder's arrays and the refit works from the parents it writes beside them
//!   ([`crate::accel::refit::TreeRefit`]); only a few words (depth, SAH cost) come back.
//!
//! Each update returns a [`BuildReport`]: what was built and its CPU time (GPU time comes from
//! the `Accel` pass's timestamps). The cache also owns the `accel_stats` ray counters that the
//! trace module adds to, and the `accel_alpha` buffer of the alpha test
//! ([`crate::accel::alpha::gpu_words`], rewritten when it changes; whether an instance is
//! alpha-tested is part of the keys: it sets the compute layouts' flags and the driver
//! back-ends' opaque geometry flag).

use super::bvh::{instance_transform, instance_world_bounds, Aabb, AccelOptions, Blas, SceneAccel, Tlas};
use super::deform::{DeformPipelines, RebuildLedger, RefitPolicy, SahProbe};
use super::gpu_build::{GpuBlas, GpuBlasBuilder, GpuBuildError, MAX_GPU_BUILD_TRIANGLES};
use super::gpu_records::{GpuRecordMaker, GpuRecords};
use super::layout::{flatten, merge, merge_instances, merged_accel, GpuAccel};
use super::packed::PackedArrays;
use super::refit::{MergedRefit, Refit, TreeRefit, TreeRefitPipelines};
use crate::backend::Backend;
use crate::error::RuntimeError;
use crate::gpu_util::{map_read_async, storage_with_readback};
use crate::scene::{Mesh, Scene};
use crate::util::hash_words;
use rayon::prelude::*;
use web_time::Instant;

/// Slots of the `accel_stats` buffer (see `shaders/trace/common.wgsl`).
pub(crate) const STAT_SLOTS: usize = 4;

/// Ray counts of one frame, read from the GPU counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Closest-hit rays traced.
    pub closest: u64,
    /// Any-hit (shadow, AO) rays traced.
    pub any: u64,
    /// Rays with NaN/Inf, a zero direction or a bad t range: counted and not traced.
    pub invalid: u64,
    /// Rays that hit something.
    pub hits: u64,
}

impl RayStats {
    /// Rays traced (closest and any).
    pub fn traced(&self) -> u64 {
        self.closest + self.any
    }

    /// Rays traced that hit nothing.
    pub fn misses(&self) -> u64 {
        self.traced() - self.hits.min(self.traced())
    }

    /// The sum of both counts.
    pub(crate) fn add(&self, o: &RayStats) -> RayStats {
        RayStats { closest: self.closest + o.closest, any: self.any + o.any, invalid: self.invalid + o.invalid, hits: self.hits + o.hits }
    }
}

/// What happened to the top level in an update.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TlasWork {
    /// Nothing to do: the top level is as it was.
    #[default]
    None,
    /// Boxes refitted to moved instances.
    Refit,
    /// Built again.
    Rebuild,
}

/// The work of one [`AccelCache::update`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BuildReport {
    /// BLASes built this update.
    pub blas_built: usize,
    /// BLASes kept from earlier updates.
    pub blas_reused: usize,
    /// What happened to the top level.
    pub tlas: TlasWork,
    /// CPU time of the update (hashing, CPU builds, flattening, recording), milliseconds.
    pub cpu_ms: f64,
    /// CPU milliseconds of the change detection: the content hash of every mesh and instance.
    pub hash_ms: f64,
    /// Bytes uploaded to GPU buffers this update (compute back-end).
    pub bytes_uploaded: u64,
    /// BLAS count in use.
    pub blas_count: usize,
    /// CPU milliseconds of the BLAS and TLAS builds (compute back-end; the ray-query back-end
    /// builds on the GPU inside the `Accel` pass's timestamps).
    pub blas_ms: f64,
    /// CPU milliseconds of the TLAS build.
    pub tlas_ms: f64,
    /// SAH cost of the built BVHs, triangle-weighted over the BLASes, and of the TLAS (compute).
    pub blas_sah: Option<f64>,
    /// SAH cost of the TLAS.
    pub tlas_sah: Option<f64>,
    /// The merged BLAS was refitted on the GPU (inside the `Accel` pass's timestamps).
    pub blas_refit: bool,
    /// The merged BLAS was built on the GPU ([`crate::accel::gpu_build`]); `blas_ms` is then
    /// the wall time until its arrays were in place, `blas_gpu_ms` the build's GPU time.
    pub blas_gpu_built: bool,
    /// GPU milliseconds of the merged BLAS's GPU build.
    pub blas_gpu_ms: Option<f64>,
    /// Deforming meshes whose positions changed in this update.
    pub deformed_meshes: usize,
    /// Two-level layout: BLASes of deforming meshes refitted on the CPU instead of built.
    pub blas_refits: usize,
    /// The merged tree's SAH cost over the builder's, as last measured after a refit (before
    /// this update's work).
    pub sah_growth: Option<f64>,
    /// The merged layout was rebuilt because its refitted tree had degraded past the policy's
    /// threshold (a refit was possible).
    pub rebuilt_for_quality: bool,
}

impl BuildReport {
    /// Whether anything was built or refitted.
    pub fn built_anything(&self) -> bool {
        self.blas_built > 0 || self.blas_refit || self.blas_refits > 0 || self.tlas != TlasWork::None
    }

    /// One line for reports.
    pub fn describe(&self) -> String {
        if !self.built_anything() {
            return format!("no build ({} BLAS cached)", self.blas_count);
        }
        let tlas = match self.tlas {
            TlasWork::None => "TLAS kept",
            TlasWork::Refit => "TLAS refit",
            TlasWork::Rebuild => "TLAS rebuilt",
        };
        let refit = if self.blas_refit {
            " (merged BLAS refitted on the GPU)"
        } else if self.blas_gpu_built {
            " (merged BLAS built on the GPU)"
        } else {
            ""
        };
        let mut deformed = if self.deformed_meshes > 0 { format!(", {} deforming meshes", self.deformed_meshes) } else { String::new() };
        if self.blas_refits > 0 {
            deformed += &format!(" ({} BLAS refitted)", self.blas_refits);
        }
        let growth = self
            .sah_growth
            .map(|g| format!(", SAH x{g:.3} of the build{}", if self.rebuilt_for_quality { ", rebuilt for quality" } else { "" }))
            .unwrap_or_default();
        format!("{} BLAS built{refit}, {} reused, {tlas}{deformed}{growth}, {:.2} ms CPU", self.blas_built, self.blas_reused, self.cpu_ms)
    }
}

/// Content hash of what an acceleration structure sees of a mesh: positions and indices.
pub fn mesh_hash(mesh: &Mesh) -> u64 {
    let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
    hash_words(hash_words(1, bytemuck::cast_slice(&positions)), bytemuck::cast_slice(&mesh.indices))
}

/// What a refit keeps of a mesh: its index triples and vertex count.
fn topology_hash(mesh: &Mesh) -> u64 {
    hash_words(mesh.vertices.len() as u64, bytemuck::cast_slice(&mesh.indices))
}

fn instance_hash(inst: &crate::scene::Instance, alpha_tested: bool) -> u64 {
    hash_words(inst.mesh as u64 | (alpha_tested as u64) << 63, bytemuck::cast_slice(&inst.transform.to_cols_array()))
}

/// What changed for the merged layout: every mesh's content hash, the hash of what a refit
/// keeps (topology, instances of meshes, alpha flags), the deforming meshes' positions, and
/// whether to refit.
#[derive(Clone, Copy)]
struct MergedChange<'a> {
    mesh_hashes: &'a [u64],
    meshes_hash: u64,
    deformed_hash: Option<u64>,
    refit: bool,
    /// The deforming meshes' positions are on the device only (the scene was posed for the GPU).
    gpu_deformed: bool,
}

/// One BLAS unit: a mesh (de-duplication on) or an instance (off).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct UnitKey {
    mesh: usize,
    hash: u64,
}

/// The alpha flags and content hashes of a scene that an update compares with the last one's.
struct SceneKeys {
    /// Per mesh: whether an alpha-tested instance uses it.
    tested_meshes: Vec<bool>,
    /// Per instance: whether it is alpha-tested.
    tested: Vec<bool>,
    /// Per mesh: its [`mesh_hash`].
    mesh_hashes: Vec<u64>,
    /// Per instance: its mesh, transform and alpha flag, hashed.
    instances: Vec<u64>,
    /// The BLAS units.
    units: Vec<UnitKey>,
}

struct ComputeState {
    /// The two levels (`None` in the merged layout).
    accel: Option<SceneAccel>,
    /// tlas_nodes, instances, blas_nodes, triangles
    buffers: [wgpu::Buffer; 4],
    /// The merged layout's GPU refit, and the hash of the meshes it was built from.
    refit: Option<(Refit, u64)>,
}

struct RqBlas {
    blas: wgpu::Blas,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    size: wgpu::BlasTriangleGeometrySizeDescriptor,
}

struct RayQueryState {
    /// Per unit; `None` for a unit with no valid triangle (its instances are left out).
    blases: Vec<Option<RqBlas>>,
    tlas: wgpu::Tlas,
    capacity: u32,
}

enum State {
    Empty,
    Compute(ComputeState),
    RayQuery(RayQueryState),
    RtPipeline(super::rt_pipeline::RtAccel),
}

/// How an `Accel` node organises the scene (the node's `dedup` and `merge` settings).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AccelSettings {
    /// One BLAS per mesh, shared by its instances (off: one per instance).
    pub dedup: bool,
    /// `compute` and `rt-pipeline` back-ends: one BVH over all instances in world space (see
    /// [`crate::accel::layout::merge_instances`]; `rt-pipeline` builds it as one BLAS under a
    /// one-instance TLAS).
    pub merge: bool,
}

impl Default for AccelSettings {
    fn default() -> Self {
        Self { dedup: true, merge: false }
    }
}

impl AccelSettings {
    /// Whether `backend` builds the merged layout.
    pub fn merges(&self, backend: Backend) -> bool {
        self.merge && matches!(backend, Backend::Compute | Backend::RtPipeline)
    }

    /// One line for reports of what the settings do on `backend`.
    pub(crate) fn describe(&self, backend: Backend) -> String {
        if self.merges(backend) {
            "all instances merged into one BVH".into()
        } else {
            format!("de-duplication {}", if self.dedup { "on" } else { "off" })
        }
    }
}

/// The cache of one `Accel` node.
pub struct AccelCache {
    /// Each mesh's [`mesh_hash`] while it stays the same `Arc` (`crate::scene::memo`).
    mesh_memo: crate::scene::memo::MeshMemo<u64>,
    /// The scene the last update brought the structure up to date with, by pointer: an update
    /// for the same scene does nothing and reads nothing.
    seen: Option<crate::scene::memo::SceneSnapshot>,
    backend: Backend,
    dedup: bool,
    merge: bool,
    units: Vec<UnitKey>,
    instances: Vec<u64>,
    instance_meshes: Vec<usize>,
    state: State,
    /// One window of [`STAT_SLOTS`] counters per trace pass, at `stats_stride` bytes apart.
    stats: wgpu::Buffer,
    stats_readback: wgpu::Buffer,
    stats_windows: u32,
    stats_stride: u64,
    /// Changes whenever the GPU objects bound by trace passes are replaced.
    generation: u64,
    /// Total BLAS builds since creation (tests read it).
    total_blas_builds: usize,
    /// Who builds the merged layout's BLAS on a rebuild, and the GPU builder once made.
    merged_builder: MergedBuilder,
    gpu_builder: Option<GpuBlasBuilder>,
    /// The GPU builder's record maker (and the meshes it keeps on the GPU), once made.
    record_maker: Option<GpuRecordMaker>,
    /// The refit pipelines of GPU-built merged trees, once made.
    tree_refit: Option<TreeRefitPipelines>,
    /// The rt-pipeline back-end's build command buffer, until taken ([`AccelCache::take_pending`]).
    pending: Option<wgpu::CommandBuffer>,
    /// The compute back-end's arrays and alpha words copied into one buffer after every
    /// update, on devices with few storage buffers per stage ([`AccelCache::pack_arrays`]).
    packed: Option<PackedArrays>,
    /// The arrays or the alpha words were written since they were last packed.
    packed_stale: bool,
    /// `accel_alpha` and the words last written to it.
    alpha: wgpu::Buffer,
    alpha_words: Vec<[u32; 4]>,
    /// When the merged layout is refitted and when rebuilt.
    policy: RefitPolicy,
    /// The merged layout's deformation: gather and SAH pipelines, once a refit needed them;
    /// the probe of the current tree; the builder's SAH cost of its last build; the hash of
    /// the deforming meshes' positions last gathered.
    deform: Option<DeformPipelines>,
    probe: Option<SahProbe>,
    built_sah: Option<f64>,
    /// What the refits have cost since the merged layout's last build ([`RefitPolicy::Cost`]).
    ledger: RebuildLedger,
    /// The hash of the deforming meshes' positions in the refit's input (`None`: as built).
    gathered: Option<u64>,
    /// The deforming meshes' shape at the last update ([`Scene::deformation_key`]).
    deformed: Option<u64>,
    /// Two-level layout: per unit, the SAH cost of its BLAS when it was last built.
    unit_built_sah: Vec<f64>,
    /// Every mesh's positions as the executor's GPU deformation writes them
    /// ([`crate::runtime::deform::GpuDeform::positions`]), for scenes posed for the GPU.
    device_positions: Option<wgpu::Buffer>,
    /// Whether the alpha records name textures as pooled ([`AccelCache::set_pooled_textures`]).
    pooled_textures: bool,
}

impl AccelCache {
    /// Total BLAS builds since creation (tests read it).
    pub fn total_blas_builds(&self) -> usize {
        self.total_blas_builds
    }
}

/// Who builds the merged layout's BLAS when it is rebuilt (a refit stays on the GPU either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MergedBuilder {
    /// The CPU binned-SAH builder ([`crate::accel::bvh`]).
    Cpu,
    /// The GPU PLOC builder ([`crate::accel::gpu_build`]) for at least
    /// `GPU_BUILD_MIN_TRIANGLES` triangles, the CPU below that or if the GPU build fails.
    Gpu,
    /// The first build on the CPU, every later rebuild (a structural change) as [`Self::Gpu`]:
    /// a static scene keeps the CPU's tree, which traces faster (the atrium's Stress test
    /// 7.25 GigaRays/s against 5.84 through the GPU-built tree on the H100, whose SAH cost is
    /// 1.08x), and a changing one rebuilds in about a millisecond instead of 60.
    GpuRebuilds,
}

/// Below this many triangles the CPU builds the merged BLAS faster than the GPU builder's
/// fixed cost of a few dispatches and read-backs (on the H100: 12 triangles 0.07 ms on the
/// GPU against 0.01 on the CPU; 3,920 triangles 0.6 against 2.4 ms).
pub(crate) const GPU_BUILD_MIN_TRIANGLES: usize = 1024;

impl AccelCache {
    /// Whether the compute back-end traverses the merged layout: one identity instance over one
    /// BLAS of the whole scene, for every frame of this cache.
    pub fn merged_layout(&self) -> bool {
        self.merge && self.backend == Backend::Compute
    }

    /// A cache for `backend`, with ray counters for `trace_passes` passes.
    pub fn new(device: &wgpu::Device, backend: Backend, settings: AccelSettings, trace_passes: u32) -> Self {
        let stats_windows = trace_passes.max(1);
        let stats_stride = (device.limits().min_storage_buffer_offset_alignment as u64).max((STAT_SLOTS * 4) as u64);
        let size = stats_stride * stats_windows as u64;
        let (stats, stats_readback) = storage_with_readback(device, "accel stats", size);
        Self {
            mesh_memo: crate::scene::memo::MeshMemo::new(),
            seen: None,
            backend,
            dedup: settings.dedup,
            merge: settings.merges(backend),
            units: Vec::new(),
            instances: Vec::new(),
            instance_meshes: Vec::new(),
            state: State::Empty,
            stats,
            stats_readback,
            stats_windows,
            stats_stride,
            generation: 0,
            total_blas_builds: 0,
            merged_builder: MergedBuilder::Cpu,
            gpu_builder: None,
            record_maker: None,
            tree_refit: None,
            pending: None,
            packed: None,
            packed_stale: true,
            alpha: storage(device, "accel alpha", 16),
            alpha_words: Vec::new(),
            policy: RefitPolicy::default(),
            deform: None,
            probe: None,
            built_sah: None,
            ledger: RebuildLedger::default(),
            gathered: None,
            deformed: None,
            unit_built_sah: Vec::new(),
            device_positions: None,
            pooled_textures: false,
        }
    }

    /// Whether the scene's textures are bound pooled (`crate::scene::texture_pool`): the alpha
    /// records name them so. Set by whoever uploads the textures; off until then.
    pub fn set_pooled_textures(&mut self, pooled: bool) {
        if self.pooled_textures != pooled {
            self.pooled_textures = pooled;
            self.alpha_words.clear();
            self.seen = None;
        }
    }

    /// Rewrites `accel_alpha` if the scene's alpha data changed (a new buffer, and a new
    /// generation, when it outgrows the old one). Returns whether it wrote them.
    fn update_alpha(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<bool, RuntimeError> {
        let words = super::alpha::gpu_words(scene, &crate::scene::texture_pool::texture_refs(scene, self.pooled_textures));
        if words == self.alpha_words {
            return Ok(false);
        }
        let bytes: &[u8] = bytemuck::cast_slice(&words);
        let max = device.limits().max_storage_buffer_binding_size;
        if bytes.len() as u64 > max {
            return Err(RuntimeError::Gpu(format!(
                "scene `{}`: the alpha test's uv data takes {} bytes in one storage binding, the device allows {max}\n  help: use fewer alpha-tested meshes",
                scene.name(),
                bytes.len()
            )));
        }
        if bytes.len() as u64 > self.alpha.size() {
            self.alpha = storage(device, "accel alpha", grown_capacity(bytes.len() as u64, max));
            self.generation += 1;
        }
        queue.write_buffer(&self.alpha, 0, bytes);
        self.alpha_words = words;
        Ok(true)
    }

    /// Chooses who builds the merged layout's BLAS (the executor picks
    /// [`MergedBuilder::GpuRebuilds`] on a real GPU and the CPU on a CPU adapter such as
    /// lavapipe, where the CPU builder is ten times faster than the GPU builder emulated on the
    /// same cores).
    pub fn set_merged_builder(&mut self, builder: MergedBuilder) {
        self.merged_builder = builder;
    }

    /// Where the executor's GPU deformation writes every mesh's positions (`None`: no GPU
    /// deformation). A scene posed for the GPU is refitted and rebuilt on the GPU from them;
    /// a CPU build poses a copy of the scene on the CPU.
    pub(crate) fn set_device_positions(&mut self, positions: Option<wgpu::Buffer>) {
        self.device_positions = positions;
        self.seen = None;
    }

    /// Makes the pipelines that refits and GPU rebuilds of a changing scene need now (at
    /// start-up) instead of in the first frame that needs them (a compile of up to a second
    /// on the H100 the first time a driver sees them).
    pub(crate) fn prepare_for_changes(&mut self, device: &wgpu::Device) {
        if !self.merge || self.backend != Backend::Compute {
            return;
        }
        self.deform.get_or_insert_with(|| DeformPipelines::new(device));
        self.tree_refit.get_or_insert_with(|| TreeRefitPipelines::new(device));
        self.record_maker.get_or_insert_with(|| GpuRecordMaker::new(device));
        if self.merged_builder != MergedBuilder::Cpu && self.gpu_builder.is_none() {
            match GpuBlasBuilder::new(device) {
                Ok(b) => self.gpu_builder = Some(b),
                Err(e) => log::warn!("accel: {e}; merged layouts are built on the CPU"),
            }
        }
    }

    /// Sets when the merged layout is refitted and when rebuilt.
    pub fn set_refit_policy(&mut self, policy: RefitPolicy) {
        self.policy = policy;
    }

    /// When the merged layout is refitted and when rebuilt.
    pub fn refit_policy(&self) -> RefitPolicy {
        self.policy
    }

    /// The merged tree's SAH cost over the builder's, as last measured after a refit.
    pub fn sah_growth(&self) -> Option<f64> {
        match (self.probe.as_ref().and_then(SahProbe::latest), self.built_sah) {
            (Some(l), Some(b)) if b > 0.0 => Some(l / b),
            _ => None,
        }
    }

    /// Reads the SAH measurement of the frame that has just finished (the executor calls this
    /// after each frame).
    pub(crate) async fn read_probe(&mut self, device: &wgpu::Device) -> Result<(), RuntimeError> {
        match &mut self.probe {
            Some(p) => p.read(device).await,
            None => Ok(()),
        }
    }

    /// The trace passes' GPU milliseconds of the frame that has just finished, for the ledger
    /// of [`RefitPolicy::Cost`] (the executor calls this after each frame with timestamps).
    pub(crate) fn note_trace_ms(&mut self, trace_ms: f64) {
        let growth = self.sah_growth();
        self.ledger.note_frame(trace_ms, growth);
    }

    /// The back-end the cache builds for.
    pub(crate) fn backend(&self) -> Backend {
        self.backend
    }

    /// Tree levels and dispatches of the merged layout's GPU refit, if there is one.
    pub fn refit_shape(&self) -> Option<(usize, usize)> {
        match &self.state {
            State::Compute(ComputeState { refit: Some((r, _)), .. }) => Some((r.level_count(), r.dispatch_count())),
            _ => None,
        }
    }

    fn instance_meshes_of(&self, scene: &Scene) -> Vec<u64> {
        scene.instances().iter().map(|i| i.mesh as u64).collect()
    }

    /// Changes whenever the GPU objects trace passes bind are replaced: bind groups made before must be made again.
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// Brings the acceleration structure up to date with `scene`, recording GPU work into
    /// `encoder` (ray-query builds) or writing buffers through `queue` (compute back-end).
    /// Nothing is read or done for the scene the last update saw (`crate::scene::memo`).
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
    ) -> Result<BuildReport, RuntimeError> {
        let start = Instant::now();
        if !matches!(self.state, State::Empty) && self.seen.as_ref().is_some_and(|seen| seen.matches(scene)) {
            let ms = start.elapsed().as_secs_f64() * 1e3;
            return Ok(BuildReport { blas_count: self.units.len(), hash_ms: ms, cpu_ms: ms, ..Default::default() });
        }
        self.seen = None;
        let report = self.update_changed(device, queue, encoder, scene)?;
        self.seen = Some(crate::scene::memo::SceneSnapshot::of(scene));
        Ok(report)
    }

    /// [`AccelCache::update`] for a scene that may have changed since the last update.
    fn update_changed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
    ) -> Result<BuildReport, RuntimeError> {
        let start = Instant::now();
        // The GPU-deformed merged layout reads the device's positions; every other path (and
        // any CPU build) the meshes posed on the CPU.
        let gpu_deformed =
            self.merge && self.backend == Backend::Compute && self.device_positions.is_some() && scene.posed().is_some_and(|p| !p.meshes_deformed);
        let posed = if gpu_deformed { std::borrow::Cow::Borrowed(scene) } else { scene.with_meshes_posed() };
        let scene = &*posed;
        let deform_key = scene.deformation_key();
        self.packed_stale |= self.update_alpha(device, queue, scene)?;
        let keys = self.scene_keys(scene, deform_key)?;
        let fresh = matches!(self.state, State::Empty);
        let changed: Vec<usize> = (0..keys.units.len()).filter(|&u| fresh || self.units.get(u) != Some(&keys.units[u])).collect();
        let instances_changed = fresh || keys.instances != self.instances;
        let same_instance_set =
            !fresh && self.instances.len() == keys.instances.len() && scene.instances().iter().zip(&self.instance_meshes).all(|(i, m)| i.mesh == *m);
        let mut report = BuildReport { blas_count: keys.units.len(), hash_ms: start.elapsed().as_secs_f64() * 1e3, ..Default::default() };
        if changed.is_empty() && !instances_changed {
            report.cpu_ms = start.elapsed().as_secs_f64() * 1e3;
            return Ok(report);
        }
        // Everything below writes the arrays (a build, a refit, new instances).
        self.packed_stale = true;
        // The merged layout when only instances moved or meshes deformed (their triangles the
        // same): a GPU refit, no build, while the policy allows.
        let deforming = scene.deforming_meshes();
        let meshes_hash = self.refit_keeps_hash(scene, &keys, &deforming);
        let refittable = match &self.state {
            State::Compute(c) if self.merge => c.refit.as_ref().is_some_and(|(r, meshes)| *meshes == meshes_hash && r.applies_to(scene)),
            _ => false,
        };
        let growth = self.sah_growth();
        let refit = refittable && self.policy.refits(growth, &self.ledger);
        report.deformed_meshes = if deform_key != self.deformed { deforming.len() } else { 0 };
        report.sah_growth = growth;
        self.deformed = deform_key;
        let built = if refit { 0 } else { changed.len() };
        report.blas_built = built;
        report.blas_reused = keys.units.len() - built;
        self.total_blas_builds += built;
        let SceneKeys { tested_meshes, tested, mesh_hashes, instances, units } = keys;
        match self.backend {
            Backend::Compute if self.merge => {
                report.rebuilt_for_quality = refittable && !refit;
                let change = MergedChange { mesh_hashes: &mesh_hashes, meshes_hash, deformed_hash: deform_key, refit, gpu_deformed };
                self.update_compute_merged(device, queue, encoder, scene, change, &mut report)?
            }
            Backend::Compute => self.update_compute(device, queue, scene, (&units, &changed), same_instance_set, &mut report)?,
            Backend::RayQuery => self.update_ray_query(device, encoder, scene, (&units, &changed), (&tested, &tested_meshes), &mut report)?,
            Backend::RtPipeline => self.update_rt_pipeline(device, scene, &units, &changed, &mut report)?,
        }
        self.total_blas_builds -= report.blas_refits; // counted as builds above
        self.units = units;
        self.instances = instances;
        self.instance_meshes = scene.instances().iter().map(|i| i.mesh).collect();
        report.cpu_ms = start.elapsed().as_secs_f64() * 1e3;
        log::debug!("accel: {}", report.describe());
        Ok(report)
    }

    /// The alpha flags and content hashes of `scene` an update compares with the last one's;
    /// fails for an instance of a mesh the scene does not have.
    fn scene_keys(&mut self, scene: &Scene, deform_key: Option<u64>) -> Result<SceneKeys, RuntimeError> {
        // Whether a unit holds alpha-tested geometry is part of its key (the driver back-ends
        // build it non-opaque; the merged layout's triangles carry the flag).
        let tested_meshes = super::alpha::tested_meshes(scene);
        let tested: Vec<bool> = (0..scene.instances().len()).map(|i| super::alpha::instance_tested(scene, i)).collect();
        let mesh_hashes: Vec<u64> = self.mesh_memo.values(&scene.meshes(), mesh_hash);
        let instances: Vec<u64> = scene.instances().iter().zip(&tested).map(|(i, &t)| instance_hash(i, t)).collect();
        let units: Vec<UnitKey> = if self.merge {
            // One unit, the whole scene: any change rebuilds it (or refits it, below).
            let unit = hash_words(hash_words(2, bytemuck::cast_slice(&mesh_hashes)), bytemuck::cast_slice(&instances));
            vec![UnitKey { mesh: 0, hash: hash_words(unit, &deform_key.unwrap_or(0).to_le_bytes()) }]
        } else if self.dedup {
            mesh_hashes.iter().enumerate().map(|(mesh, &hash)| UnitKey { mesh, hash: hash ^ tested_meshes[mesh] as u64 }).collect()
        } else {
            scene
                .instances()
                .iter()
                .zip(&tested)
                .map(|(i, &t)| UnitKey { mesh: i.mesh, hash: mesh_hashes.get(i.mesh).copied().unwrap_or(0) ^ t as u64 })
                .collect()
        };
        if let Some(bad) = scene.instances().iter().position(|i| i.mesh >= scene.meshes().len()) {
            return Err(RuntimeError::Gpu(format!(
                "scene `{}`: instance {bad} refers to mesh {} of {}",
                scene.name(),
                scene.instances()[bad].mesh,
                scene.meshes().len()
            )));
        }
        Ok(SceneKeys { tested_meshes, tested, mesh_hashes, instances, units })
    }

    /// The hash of what a refit of the merged layout keeps: the `deforming` meshes' topology,
    /// the other meshes' content, which mesh each instance is and its alpha flag.
    fn refit_keeps_hash(&self, scene: &Scene, keys: &SceneKeys, deforming: &[usize]) -> u64 {
        let tested_words: Vec<u64> = keys.tested.iter().map(|&t| t as u64).collect();
        let topology: Vec<u64> = keys
            .mesh_hashes
            .iter()
            .enumerate()
            .map(|(m, &h)| if deforming.binary_search(&m).is_ok() { topology_hash(&scene.meshes()[m]) } else { h })
            .collect();
        hash_words(
            hash_words(hash_words(3, bytemuck::cast_slice(&topology)), bytemuck::cast_slice(&self.instance_meshes_of(scene))),
            bytemuck::cast_slice(&tested_words),
        )
    }

    /// The two-level layout: the changed `units` get a new BLAS (or a CPU refit, for a
    /// deforming mesh), then the TLAS is rebuilt, or only refitted when the instances moved and
    /// nothing else changed.
    fn update_compute(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        (units, changed): (&[UnitKey], &[usize]),
        same_instance_set: bool,
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        let opts = AccelOptions { dedup: self.dedup, ..Default::default() };
        let old = match std::mem::replace(&mut self.state, State::Empty) {
            State::Compute(c) => Some(c),
            _ => None,
        };
        // Instances moved, nothing else: refit the TLAS in place. (Any other change keeps
        // `old`: its BLASes of unchanged units are reused below.)
        let old = match old {
            Some(c) if changed.is_empty() && same_instance_set => match self.refit_tlas(device, queue, scene, c, report) {
                None => return Ok(()),
                kept => kept,
            },
            old => old,
        };
        let blases = self.update_blases(scene, (units, changed), old.as_ref(), &opts, report);
        let accel = self.two_level_accel(scene, units, blases, &opts, report);
        report.tlas = TlasWork::Rebuild;
        let flat = flatten(scene, &accel);
        self.install(device, queue, scene, old, Some(accel), &flat, report)
    }

    /// Refits the TLAS of `c` in place for `scene`'s instance transforms, uploads the arrays
    /// and makes it the current state (`None`); `Some(c)` unchanged if it cannot be refitted.
    fn refit_tlas(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, mut c: ComputeState, report: &mut BuildReport) -> Option<ComputeState> {
        let refitted = c.accel.as_mut().is_some_and(|a| a.refit_instances(scene).is_ok());
        if let Some(accel) = c.accel.as_ref().filter(|_| refitted) {
            report.tlas = TlasWork::Refit;
            let flat = flatten(scene, accel);
            report.bytes_uploaded = self.upload(device, queue, &mut c.buffers, &flat);
            self.state = State::Compute(c);
            return None;
        }
        Some(c)
    }

    /// The BLAS of every unit: `old`'s for the unchanged ones; for the `changed` ones, a
    /// deforming mesh's BLAS (same triangles, moved vertices) is refitted on the CPU while the
    /// policy allows its SAH growth over its build's cost (the cost policy keeps no ledger per
    /// BLAS: its SAH threshold decides); others are built.
    fn update_blases(
        &mut self,
        scene: &Scene,
        (units, changed): (&[UnitKey], &[usize]),
        old: Option<&ComputeState>,
        opts: &AccelOptions,
        report: &mut BuildReport,
    ) -> Vec<Blas> {
        let t0 = Instant::now();
        let mut blases = old.and_then(|c| c.accel.as_ref()).map(|a| a.blases.clone()).unwrap_or_default();
        blases.resize_with(units.len(), Blas::default);
        let deforming = scene.deforming_meshes();
        self.unit_built_sah.resize(units.len(), 0.0);
        let refitted: Vec<usize> = changed
            .iter()
            .copied()
            .filter(|&u| {
                let (mesh, blas, built_sah) = (units[u].mesh, &blases[u], self.unit_built_sah[u]);
                let growth = (built_sah > 0.0).then(|| blas.bvh.sah_cost() as f64 / built_sah);
                deforming.binary_search(&mesh).is_ok()
                    && !blas.is_empty()
                    && blas.triangle_count == scene.meshes()[mesh].triangle_count()
                    && self.policy.refits(growth, &RebuildLedger::default())
            })
            .collect();
        for &u in &refitted {
            if blases[u].refit(&scene.meshes()[units[u].mesh], units[u].mesh).is_err() {
                blases[u] = Blas::default(); // unreachable: the triangle counts were checked
            }
        }
        let to_build: Vec<usize> = changed.iter().copied().filter(|u| !refitted.contains(u)).collect();
        let built: Vec<(usize, Blas)> = to_build.par_iter().map(|&u| (u, Blas::build(&scene.meshes()[units[u].mesh], &opts.build))).collect();
        report.blas_ms = t0.elapsed().as_secs_f64() * 1e3;
        report.blas_built = built.len();
        report.blas_refits = refitted.len();
        report.blas_reused = units.len() - changed.len();
        for (u, b) in built {
            self.unit_built_sah[u] = b.bvh.sah_cost() as f64;
            blases[u] = b;
        }
        report.sah_growth = refitted
            .iter()
            .filter(|&&u| self.unit_built_sah[u] > 0.0)
            .map(|&u| blases[u].bvh.sah_cost() as f64 / self.unit_built_sah[u])
            .fold(None, |a: Option<f64>, g| Some(a.map_or(g, |a| a.max(g))));
        blases
    }

    /// The two levels over `blases` (one per unit): each instance's BLAS and transform, and
    /// the TLAS built over their world bounds.
    fn two_level_accel(&self, scene: &Scene, units: &[UnitKey], blases: Vec<Blas>, opts: &AccelOptions, report: &mut BuildReport) -> SceneAccel {
        let instance_transforms: Vec<_> = scene.instances().iter().map(|i| instance_transform(&i.transform)).collect();
        let instance_blas: Vec<Option<u32>> = scene
            .instances()
            .iter()
            .enumerate()
            .map(|(i, inst)| {
                let b = if self.dedup { inst.mesh } else { i };
                (instance_transforms[i].is_some() && blases.get(b).is_some_and(|bl| !bl.is_empty())).then_some(b as u32)
            })
            .collect();
        let bounds: Vec<Aabb> = instance_blas
            .iter()
            .zip(&instance_transforms)
            .map(|(b, xf)| match (b, xf) {
                (Some(b), Some(xf)) => instance_world_bounds(&blases[*b as usize].bounds(), xf),
                _ => Aabb::EMPTY,
            })
            .collect();
        let t0 = Instant::now();
        let tlas = Tlas::build(&bounds, &opts.build);
        report.tlas_ms = t0.elapsed().as_secs_f64() * 1e3;
        let tris: f64 = blases.iter().map(|b| b.bvh.prim_order.len() as f64).sum();
        if tris > 0.0 {
            report.blas_sah = Some(blases.iter().map(|b| b.bvh.sah_cost() as f64 * b.bvh.prim_order.len() as f64).sum::<f64>() / tris);
        }
        report.tlas_sah = (!tlas.bvh.is_empty()).then(|| tlas.bvh.sah_cost() as f64);
        SceneAccel {
            blases,
            blas_mesh: units.iter().map(|k| Some(k.mesh)).collect(),
            instance_blas,
            instance_transforms,
            tlas,
            dedup: self.dedup,
            build_time: std::time::Duration::ZERO,
        }
    }

    /// Checks that `flat` fits the device, uploads it into `old`'s buffers (or new ones) and
    /// makes it the current state.
    #[allow(clippy::too_many_arguments)]
    fn install(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        old: Option<ComputeState>,
        accel: Option<SceneAccel>,
        flat: &GpuAccel,
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        check_fits(scene.name(), flat, device.limits().max_storage_buffer_binding_size)?;
        let mut buffers = match old {
            Some(c) => c.buffers,
            None => {
                self.generation += 1;
                new_accel_buffers(device)
            }
        };
        report.bytes_uploaded = self.upload(device, queue, &mut buffers, flat);
        self.state = State::Compute(ComputeState { accel, buffers, refit: None });
        Ok(())
    }

    /// The merged layout: one BLAS over every instance's world-space triangles, rebuilt when
    /// anything but the instance transforms and the deforming meshes' positions changed (or
    /// when the policy says the refitted tree has degraded), else refitted on the GPU.
    fn update_compute_merged(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        change: MergedChange,
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        let mut old = match std::mem::replace(&mut self.state, State::Empty) {
            State::Compute(c) => Some(c),
            _ => None,
        };
        // Only instances moved or meshes deformed: refit on the GPU.
        if change.refit {
            if let Some((refit, _)) = old.as_mut().and_then(|c| c.refit.as_mut()) {
                self.record_refit(device, queue, encoder, scene, refit, change);
                report.tlas = TlasWork::Refit;
                report.blas_refit = true;
            }
            self.state = old.map(State::Compute).unwrap_or(State::Empty);
            return Ok(());
        }
        let t0 = Instant::now();
        report.tlas = TlasWork::Rebuild;
        let first_build = old.is_none();
        self.probe = None;
        self.gathered = change.deformed_hash;
        let positions = self.device_positions.clone().filter(|_| change.gpu_deformed);
        if let Some((built, records)) = self.build_merged_on_gpu(device, queue, scene, (change.mesh_hashes, positions.as_ref()), first_build) {
            report.blas_gpu_built = true;
            report.blas_gpu_ms = built.gpu_ms;
            report.blas_sah = Some(built.sah_cost);
            report.blas_ms = t0.elapsed().as_secs_f64() * 1e3;
            self.built_sah = report.blas_sah;
            self.ledger.note_build(report.blas_ms);
            return self.install_gpu_built(device, queue, encoder, scene, old, (built, records), change.meshes_hash, report);
        }
        let posed = scene.with_meshes_posed();
        let scene = &*posed;
        let (mesh, origin) = merge_instances(scene);
        let blas = Blas::build(&mesh, &AccelOptions::default().build);
        report.blas_sah = (!blas.is_empty()).then(|| blas.bvh.sah_cost() as f64);
        self.built_sah = report.blas_sah;
        let flat = merge(&mesh, &origin, blas);
        report.blas_ms = t0.elapsed().as_secs_f64() * 1e3;
        self.ledger.note_build(report.blas_ms);
        self.install(device, queue, scene, old, None, &flat, report)?;
        if let State::Compute(c) = &mut self.state {
            c.refit = MergedRefit::new(device, scene, &flat, &c.buffers).map(|r| (Refit::Planned(r), change.meshes_hash));
        }
        Ok(())
    }

    /// Records a refit of the merged tree: the deforming meshes' new positions gathered into
    /// its input first (where they changed since the input was made), its SAH cost measured
    /// after.
    fn record_refit(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        refit: &mut Refit,
        change: MergedChange,
    ) {
        let pipelines = self.deform.get_or_insert_with(|| DeformPipelines::new(device));
        if change.deformed_hash != self.gathered {
            let positions = match (&self.device_positions, change.gpu_deformed) {
                (Some(p), true) => Some(p),
                _ => {
                    let maker = self.record_maker.get_or_insert_with(|| GpuRecordMaker::new(device));
                    maker.sync_meshes(device, queue, scene, change.mesh_hashes).and_then(|_| maker.positions())
                }
            };
            if let Some(positions) = positions {
                pipelines.record_gather(device, encoder, positions, refit.object_vertices());
                self.gathered = change.deformed_hash;
            }
        }
        refit.record(device, queue, encoder, scene);
        let probe = self.probe.get_or_insert_with(|| {
            let (nodes, count) = refit.nodes();
            SahProbe::new(device, pipelines, nodes, count)
        });
        probe.record(pipelines, encoder);
    }

    /// Makes the GPU-built merged tree `built` (from the records `records`) the current state
    /// without reading it back: the traversal binds the builder's node and triangle buffers
    /// (a new generation), the one TLAS node and instance are written from the CPU and the
    /// root's box copied into that node on the GPU (recorded into `encoder`), and the refit
    /// works from the builder's parents ([`TreeRefit`]).
    #[allow(clippy::too_many_arguments)]
    fn install_gpu_built(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        old: Option<ComputeState>,
        (built, records): (GpuBlas, GpuRecords),
        meshes_hash: u64,
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        let top = merged_accel(Vec::new(), Vec::new());
        let (nodes, tris) = (built.node_count as usize, built.triangle_count as usize);
        let arrays = [("BLAS nodes", nodes, 32 * nodes), ("triangles", tris, 48 * tris), ("TLAS nodes", 1, 32), ("instances", 1, 112)];
        check_arrays(scene.name(), &arrays, device.limits().max_storage_buffer_binding_size)?;
        let mut buffers = match old {
            Some(c) => c.buffers,
            None => new_accel_buffers(device),
        };
        let [tlas_nodes, instances, blas_nodes, triangles] = &mut buffers;
        report.bytes_uploaded = self.write_array(device, queue, tlas_nodes, bytemuck::cast_slice(&top.tlas_nodes))
            + self.write_array(device, queue, instances, bytemuck::cast_slice(&top.instances))
            + records.bytes_uploaded;
        *blas_nodes = built.nodes.clone();
        *triangles = built.triangles.clone();
        self.generation += 1;
        // The TLAS node's box is the root's: min at bytes 0..12, max at 16..28.
        encoder.copy_buffer_to_buffer(&buffers[2], 0, &buffers[0], 0, 12);
        encoder.copy_buffer_to_buffer(&buffers[2], 16, &buffers[0], 16, 12);
        let pipelines = self.tree_refit.get_or_insert_with(|| TreeRefitPipelines::new(device));
        let refit = TreeRefit::new(pipelines, scene, &built, &records.object_vertices, &buffers[0]);
        self.state = State::Compute(ComputeState { accel: None, buffers, refit: Some((Refit::Tree(refit), meshes_hash)) });
        Ok(())
    }

    /// The merged layout built by the GPU builder (left on the GPU) from input records made on
    /// the GPU ([`GpuRecordMaker`]: no CPU work per triangle; `mesh_hashes` say which meshes
    /// to upload again), when [`MergedBuilder::Gpu`] applies; `None` to build on the CPU (too
    /// few or too many triangles, or a GPU build that failed, which is logged).
    fn build_merged_on_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        (mesh_hashes, positions): (&[u64], Option<&wgpu::Buffer>),
        first_build: bool,
    ) -> Option<(GpuBlas, GpuRecords)> {
        match self.merged_builder {
            MergedBuilder::Cpu => return None,
            MergedBuilder::GpuRebuilds if first_build => return None,
            _ => {}
        }
        if self.gpu_builder.is_none() {
            match GpuBlasBuilder::new(device) {
                Ok(b) => self.gpu_builder = Some(b),
                Err(e) => {
                    log::warn!("accel: {e}; merged layouts are built on the CPU");
                    self.merged_builder = MergedBuilder::Cpu;
                    return None;
                }
            }
        }
        let max_binding = device.limits().max_storage_buffer_binding_size / 48;
        let max_slots = (MAX_GPU_BUILD_TRIANGLES as u64).min(max_binding) as u32;
        let maker = self.record_maker.get_or_insert_with(|| GpuRecordMaker::new(device));
        // The records and the build in a row, the survivor count copied on the GPU: one wait,
        // after the build. Too few survivors (known then) are built again on the CPU.
        let mut records = maker.record(device, queue, scene, (mesh_hashes, positions), max_slots).filter(|r| r.slots as usize >= GPU_BUILD_MIN_TRIANGLES)?;
        let builder = self.gpu_builder.as_ref()?;
        match builder.build_records_counted(device, queue, &records.records, (&records.count_word, 0), records.slots as usize) {
            Ok(built) if built.triangle_count as usize >= GPU_BUILD_MIN_TRIANGLES => {
                records.count = built.triangle_count;
                Some((built, records))
            }
            Ok(_) | Err(GpuBuildError::Size(0)) => None,
            Err(e) => {
                log::warn!("accel: the GPU build of the merged layout failed ({e}); building it on the CPU");
                None
            }
        }
    }

    /// Writes the flattened arrays, growing buffers (and bumping the generation) as needed.
    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, buffers: &mut [wgpu::Buffer; 4], flat: &GpuAccel) -> u64 {
        let data: [&[u8]; 4] = [
            bytemuck::cast_slice(&flat.tlas_nodes),
            bytemuck::cast_slice(&flat.instances),
            bytemuck::cast_slice(&flat.blas_nodes),
            bytemuck::cast_slice(&flat.triangles),
        ];
        buffers.iter_mut().zip(data).map(|(buf, d)| self.write_array(device, queue, buf, d)).sum()
    }

    /// Writes `data` into `buf`, replacing it by a larger one (a new generation) if it is too
    /// small; the bytes written.
    fn write_array(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, buf: &mut wgpu::Buffer, data: &[u8]) -> u64 {
        if (data.len() as u64) > buf.size() {
            let label = format!("accel buffer of {} bytes", data.len());
            *buf = storage(device, &label, grown_capacity(data.len() as u64, device.limits().max_storage_buffer_binding_size));
            self.generation += 1;
        }
        queue.write_buffer(buf, 0, data);
        data.len() as u64
    }

    /// The ray-query back-end: new BLAS for the `changed` units (non-opaque where alpha-tested:
    /// `tested` per instance, `tested_meshes` per mesh), then the TLAS's instances written and
    /// the builds recorded into `encoder` (wgpu rebuilds the TLAS).
    fn update_ray_query(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
        (units, changed): (&[UnitKey], &[usize]),
        (tested, tested_meshes): (&[bool], &[bool]),
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        const MAX_CUSTOM_DATA: usize = 0xFF_FFFF;
        if scene.instances().len() > MAX_CUSTOM_DATA {
            return Err(RuntimeError::Gpu(format!(
                "scene `{}` has {} instances; the ray-query back-end identifies instances in 24 bits (at most {MAX_CUSTOM_DATA}); use --backend compute",
                scene.name(),
                scene.instances().len()
            )));
        }
        let old = match std::mem::replace(&mut self.state, State::Empty) {
            State::RayQuery(r) => Some(r),
            _ => None,
        };
        let (mut blases, old_tlas) = match old {
            Some(r) => (r.blases, Some((r.tlas, r.capacity))),
            None => (Vec::new(), None),
        };
        blases.truncate(units.len());
        blases.resize_with(units.len(), || None);
        // A unit is non-opaque when an alpha-tested instance uses it (de-duplication on: any
        // instance of the mesh).
        for &u in changed {
            let alpha = if self.dedup { tested_meshes[units[u].mesh] } else { tested[u] };
            blases[u] = rq_blas(device, &scene.meshes()[units[u].mesh], u, !alpha);
        }
        let (mut tlas, capacity) = self.rq_tlas(device, old_tlas, (scene.instances().len() as u32).max(1));
        for i in 0..capacity as usize {
            tlas[i] = scene.instances().get(i).and_then(|inst| {
                let b = blases[if self.dedup { inst.mesh } else { i }].as_ref()?;
                instance_transform(&inst.transform)?;
                let m = inst.transform;
                let rows = [0, 1, 2].map(|r| [m.x_axis[r], m.y_axis[r], m.z_axis[r], m.w_axis[r]]);
                Some(wgpu::TlasInstance::new(&b.blas, bytemuck::cast(rows), i as u32, 0xff))
            });
        }
        record_rq_builds(encoder, &blases, changed, &tlas);
        report.tlas = TlasWork::Rebuild;
        self.state = State::RayQuery(RayQueryState { blases, tlas, capacity });
        Ok(())
    }

    /// The ray-query TLAS and its capacity: `old` if it holds `needed` instances, else a new
    /// one (a new generation) for the next power of two.
    fn rq_tlas(&mut self, device: &wgpu::Device, old: Option<(wgpu::Tlas, u32)>, needed: u32) -> (wgpu::Tlas, u32) {
        match old {
            Some((t, cap)) if cap >= needed => (t, cap),
            _ => {
                self.generation += 1;
                let cap = needed.next_power_of_two();
                let t = device.create_tlas(&wgpu::CreateTlasDescriptor {
                    label: Some("accel tlas"),
                    max_instances: cap,
                    flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                    update_mode: wgpu::AccelerationStructureUpdateMode::Build,
                });
                (t, cap)
            }
        }
    }

    /// The rt-pipeline back-end: new BLAS for the changed units, then TLAS and the geometry
    /// arrays again (recorded through wgpu-hal into a command buffer the caller submits,
    /// [`AccelCache::take_pending`]; see [`super::rt_pipeline`]). Bind groups follow through
    /// [`AccelCache::generation`].
    fn update_rt_pipeline(
        &mut self,
        device: &wgpu::Device,

        scene: &Scene,
        units: &[UnitKey],
        changed: &[usize],
        report: &mut BuildReport,
    ) -> Result<(), RuntimeError> {
        let mut rt = match std::mem::replace(&mut self.state, State::Empty) {
            State::RtPipeline(r) => r,
            _ => super::rt_pipeline::RtAccel::new(device),
        };
        let unit_meshes: Vec<usize> = units.iter().map(|u| u.mesh).collect();
        let dedup = self.dedup;
        let unit_of = |i: usize| if dedup { scene.instances()[i].mesh } else { i };
        let result = rt.update(scene, &unit_meshes, &unit_of, changed, self.merge);
        self.generation += 1;
        // After a failure the structures are gone (RtAccel::update) and the cache starts over:
        // the next update finds it empty and builds everything.
        let (built, commands) = result?;
        self.pending = Some(commands);
        self.state = State::RtPipeline(rt);
        // What was built: units without a valid triangle have no BLAS.
        self.total_blas_builds = self.total_blas_builds + built - report.blas_built;
        report.blas_built = built;
        report.blas_reused = units.len() - changed.len().min(units.len());
        report.tlas = TlasWork::Rebuild;
        Ok(())
    }

    /// The rt-pipeline back-end's build of the last update, recorded through wgpu-hal in a
    /// command buffer of its own: submit it after the update's encoder and before anything
    /// that traces (the executor does, between the `Accel` node's timestamps).
    pub(crate) fn take_pending(&mut self) -> Option<wgpu::CommandBuffer> {
        self.pending.take()
    }

    /// The rt-pipeline back-end's acceleration structures, once built.
    pub fn rt_accel(&self) -> Option<&super::rt_pipeline::RtAccel> {
        match &self.state {
            State::RtPipeline(r) => Some(r),
            _ => None,
        }
    }

    /// Binds the compute back-end's arrays as one packed buffer (`accel_packed`) from now on,
    /// for a device with few storage buffers per stage ([`super::packed`]); the executor then
    /// calls [`AccelCache::record_packing`] after every update.
    pub(crate) fn pack_arrays(&mut self) {
        self.packed.get_or_insert_with(PackedArrays::default);
    }

    /// Records the copy of the compute back-end's arrays into the packed buffer (after
    /// [`AccelCache::update`], before any trace) when the update wrote them; nothing without
    /// [`AccelCache::pack_arrays`] or on another back-end. A larger packed buffer starts a new
    /// generation.
    pub(crate) fn record_packing(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder) -> Result<(), RuntimeError> {
        let (Some(packed), State::Compute(c)) = (self.packed.as_mut(), &self.state) else { return Ok(()) };
        let [tlas, instances, blas, triangles] = &c.buffers;
        if packed.record(device, queue, encoder, [tlas, instances, blas, triangles, &self.alpha], self.packed_stale)? {
            self.generation += 1;
        }
        self.packed_stale = false;
        Ok(())
    }

    /// Bytes of the packed arrays' buffer (`AccelCache::pack_arrays`; 0 without).
    pub fn packed_bytes(&self) -> u64 {
        self.packed.as_ref().map_or(0, PackedArrays::size)
    }

    /// The buffer of ray counters and the byte range of trace pass number `window`'s counters.
    pub(crate) fn stats_window(&self, window: u32) -> (&wgpu::Buffer, u64, u64) {
        (&self.stats, self.stats_stride * window.min(self.stats_windows - 1) as u64, (STAT_SLOTS * 4) as u64)
    }

    /// The GPU object a trace-module binding (`accel_*`) refers to; `accel_stats` is the
    /// counter window of trace pass number `window`.
    pub fn binding(&self, name: &str, window: u32) -> Option<wgpu::BindingResource<'_>> {
        if name == "accel_stats" {
            let offset = self.stats_stride * window.min(self.stats_windows - 1) as u64;
            return Some(wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &self.stats,
                offset,
                size: std::num::NonZeroU64::new((STAT_SLOTS * 4) as u64),
            }));
        }
        match (&self.state, name) {
            (State::Compute(c), "accel_tlas_nodes") => Some(c.buffers[0].as_entire_binding()),
            (State::Compute(c), "accel_instances") => Some(c.buffers[1].as_entire_binding()),
            (State::Compute(c), "accel_blas_nodes") => Some(c.buffers[2].as_entire_binding()),
            (State::Compute(c), "accel_triangles") => Some(c.buffers[3].as_entire_binding()),
            (State::Compute(_), "accel_packed") => self.packed.as_ref().and_then(PackedArrays::buffer).map(wgpu::Buffer::as_entire_binding),
            (State::RayQuery(r), "accel_tlas") => Some(r.tlas.as_binding()),
            (_, "accel_alpha") => Some(self.alpha.as_entire_binding()),
            _ => None,
        }
    }

    /// Zeroes the ray counters (start of a frame).
    pub(crate) fn clear_stats(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.stats, 0, None);
    }

    /// Copies the ray counters for [`AccelCache::read_stats`] (end of a frame).
    pub(crate) fn copy_stats(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.copy_buffer_to_buffer(&self.stats, 0, &self.stats_readback, 0, self.stats.size());
    }

    /// The ray counts of each trace pass in the last submitted frame (after it completed).
    pub(crate) async fn read_stats(&self, device: &wgpu::Device) -> Result<Vec<RayStats>, RuntimeError> {
        let data = map_read_async(device, self.stats_readback.slice(..)).await?;
        let words: &[u32] = bytemuck::cast_slice(&data);
        let per = (self.stats_stride / 4) as usize;
        let stats = (0..self.stats_windows as usize)
            .map(|w| {
                let v = &words[w * per..w * per + STAT_SLOTS];
                RayStats { closest: v[0] as u64, any: v[1] as u64, invalid: v[2] as u64, hits: v[3] as u64 }
            })
            .collect();
        drop(data);
        self.stats_readback.unmap();
        Ok(stats)
    }
}

/// The compute back-end binds each array as one storage buffer: a scene whose arrays exceed
/// the device's binding size is refused with the numbers.
pub fn check_fits(scene: &str, flat: &GpuAccel, max_binding: u64) -> Result<(), RuntimeError> {
    let arrays = [
        ("BLAS nodes", flat.blas_nodes.len(), std::mem::size_of_val(flat.blas_nodes.as_slice())),
        ("triangles", flat.triangles.len(), std::mem::size_of_val(flat.triangles.as_slice())),
        ("TLAS nodes", flat.tlas_nodes.len(), std::mem::size_of_val(flat.tlas_nodes.as_slice())),
        ("instances", flat.instances.len(), std::mem::size_of_val(flat.instances.as_slice())),
    ];
    check_arrays(scene, &arrays, max_binding)
}

/// [`check_fits`] of arrays given as (name, elements, bytes).
fn check_arrays(scene: &str, arrays: &[(&str, usize, usize)], max_binding: u64) -> Result<(), RuntimeError> {
    let longest = arrays.iter().map(|a| a.1).max().unwrap_or(0);
    if longest >= super::layout::MAX_INDEX {
        return Err(RuntimeError::Gpu(format!(
            "scene `{scene}` is too large for the compute back-end: an array of its acceleration structure has {longest} elements, the traversal indexes fewer than {}\n  help: use a smaller scene or duplication factor, or the ray-query back-end",
            super::layout::MAX_INDEX
        )));
    }
    for &(what, _, bytes) in arrays {
        if bytes as u64 > max_binding {
            return Err(RuntimeError::Gpu(format!(
                "scene `{scene}` is too large for the compute back-end: its {what} take {bytes} bytes in one storage binding, the device allows {max_binding}\n  help: use a smaller scene or duplication factor, or the ray-query back-end"
            )));
        }
    }
    Ok(())
}

/// The compute back-end's four arrays, empty: tlas nodes, instances, blas nodes, triangles
/// (the caller starts a new generation).
fn new_accel_buffers(device: &wgpu::Device) -> [wgpu::Buffer; 4] {
    [0, 1, 2, 3].map(|i| storage(device, ["accel tlas nodes", "accel instances", "accel blas nodes", "accel triangles"][i], 32))
}

/// The size of a storage buffer grown to hold `len` bytes: the next power of two (room for the
/// next growth), but never past what one binding may cover (`max_binding`, rounded down to
/// whole 16-byte records): a buffer of 1.6 GB grown to 2 GiB could not be bound whole on a
/// device whose limit is 2 GiB - 1 (a 32.8M-triangle scene's triangle array on the H200).
/// `len` itself is checked against the limit before ([`check_fits`]).
fn grown_capacity(len: u64, max_binding: u64) -> u64 {
    len.next_power_of_two().min(max_binding / 16 * 16).max(len)
}

fn storage(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(32),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// A wgpu BLAS over a mesh's triangles ([`super::bvh::driver_triangles`]), opaque or not
/// (alpha-tested: its hits come to the shader's candidate loop). `None` if no triangle is
/// valid.
fn rq_blas(device: &wgpu::Device, mesh: &Mesh, unit: usize, opaque: bool) -> Option<RqBlas> {
    use wgpu::util::DeviceExt;
    let (positions, indices) = super::bvh::driver_triangles(mesh)?;
    let usage = wgpu::BufferUsages::BLAS_INPUT;
    let vertices =
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some("blas vertices"), contents: bytemuck::cast_slice(&positions), usage });
    let index_buf =
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some("blas indices"), contents: bytemuck::cast_slice(&indices), usage });
    let size = wgpu::BlasTriangleGeometrySizeDescriptor {
        vertex_format: wgpu::VertexFormat::Float32x3,
        vertex_count: positions.len() as u32,
        index_format: Some(wgpu::IndexFormat::Uint32),
        index_count: Some(indices.len() as u32),
        flags: if opaque {
            wgpu::AccelerationStructureGeometryFlags::OPAQUE
        } else {
            wgpu::AccelerationStructureGeometryFlags::NO_DUPLICATE_ANY_HIT_INVOCATION
        },
    };
    let blas = device.create_blas(
        &wgpu::CreateBlasDescriptor {
            label: Some(&format!("blas {unit}")),
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        },
        wgpu::BlasGeometrySizeDescriptors::Triangles { descriptors: vec![size.clone()] },
    );
    Some(RqBlas { blas, vertices, indices: index_buf, size })
}

/// Records the builds of the `changed` units' ray-query BLASes (those with a valid triangle)
/// and of `tlas`.
fn record_rq_builds(encoder: &mut wgpu::CommandEncoder, blases: &[Option<RqBlas>], changed: &[usize], tlas: &wgpu::Tlas) {
    let entries: Vec<wgpu::BlasBuildEntry> = changed
        .iter()
        .filter_map(|&u| blases[u].as_ref())
        .map(|b| wgpu::BlasBuildEntry {
            blas: &b.blas,
            geometry: wgpu::BlasGeometries::TriangleGeometries(vec![wgpu::BlasTriangleGeometry {
                size: &b.size,
                vertex_buffer: &b.vertices,
                first_vertex: 0,
                vertex_stride: 12,
                index_buffer: Some(&b.indices),
                first_index: Some(0),
                transform_buffer: None,
                transform_buffer_offset: None,
            }]),
        })
        .collect();
    encoder.build_acceleration_structures(entries.iter(), [tlas]);
}

/// The trace module's bindings that `cache` holds in wgpu buffers for trace pass number
/// `window` (its counter window; [`AccelCache::binding`]) as the `rt-pipeline` back-end takes
/// them ([`super::rt_pipeline::AccelBuffers`]).
pub(crate) fn cache_buffers(cache: &AccelCache, window: u32) -> impl Fn(&str) -> Option<(wgpu::Buffer, u64, Option<std::num::NonZeroU64>)> + '_ {
    move |name| match cache.binding(name, window)? {
        wgpu::BindingResource::Buffer(b) => Some((b.buffer.clone(), b.offset, b.size)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grown_buffers_stay_bindable() {
        assert_eq!(grown_capacity(1000, 1 << 30), 1024, "room for the next growth");
        let limit = (1u64 << 31) - 1;
        let triangles = 32_812_000 * 48;
        assert_eq!(grown_capacity(triangles, limit), limit / 16 * 16, "not past one binding");
        assert_eq!(grown_capacity(limit - 15, limit), limit - 15, "never below the data");
    }
}
