//! GPU refit of the merged layout (`Accel(merge: true)` on the `compute` back-end): when only
//! instance transforms change, the triangles are moved to world space again on the GPU and
//! every node box is recomputed bottom-up, instead of merging and rebuilding on the CPU. The
//! tree's topology is kept, so its quality is the one built for the first positions; a
//! structural change rebuilds.
//!
//! A tree built on the CPU is refitted by [`MergedRefit`] (`shaders/accel/refit.wgsl`'s
//! `refit_treelets`: the tree cut on the CPU into treelets of at most [`TREELET_NODES`] nodes,
//! one workgroup each, then the top part). A tree built on the GPU never comes back to the CPU:
//! [`TreeRefit`] carries every leaf's box up its parents with atomics (`refit_leaves`, then
//! `refit_interior`), from the parents and leaf order the builder writes. [`Refit`] is either.

use super::bvh::instance_transform;
use super::gpu_build::GpuBlas;
use super::layout::{affine_rows, GpuAccel, GpuBvhNode, NO_PRIM};
use crate::gpu_util::compute_pipeline;
use crate::scene::Scene;
use wgpu::util::DeviceExt;

/// The refit kernel (part of the back-end, not of any graph).
pub(crate) const REFIT_WGSL: &str = include_str!("../../shaders/accel/refit.wgsl");

/// Subtrees of at most this many nodes are treelets (one workgroup each); the nodes above them
/// form the top treelet. Raised for trees so large that the treelets would pass the dispatch
/// limit.
pub const TREELET_NODES: usize = 512;

/// The refit's work, as the shader reads it: node indices grouped by treelet and, within one,
/// by level from the deepest; `(first, count)` per level into `nodes`; `(first level, level
/// count)` per treelet, the subtree treelets first and the top one (if any) last.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TreeletPlan {
    /// Node indices by treelet, then by level from the deepest.
    pub nodes: Vec<u32>,
    /// `(first, count)` per level into `nodes`.
    pub levels: Vec<[u32; 2]>,
    /// `(first level, level count)` per treelet.
    pub treelets: Vec<[u32; 2]>,
    /// Whether the last treelet is the top part (refitted after all the others).
    pub has_top: bool,
    /// Depth of the tree (levels from the root to the deepest leaf).
    pub depth: usize,
}

/// Cuts the tree `nodes` (root at 0, children of interior node `n` at `n.left_or_first` and
/// the next) into treelets of at most `max_nodes` nodes and the top part above them.
pub fn plan_treelets(nodes: &[GpuBvhNode], max_nodes: usize) -> TreeletPlan {
    let mut plan = TreeletPlan::default();
    if nodes.is_empty() {
        return plan;
    }
    let children = |n: u32| {
        let node = &nodes[n as usize];
        (node.count == 0).then_some([node.left_or_first, node.left_or_first + 1])
    };
    // Pre-order with depths, then subtree sizes from the back (children come after parents).
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack = vec![(0u32, 0usize)];
    while let Some((n, d)) = stack.pop() {
        order.push((n, d));
        plan.depth = plan.depth.max(d + 1);
        if let Some(c) = children(n) {
            stack.extend([(c[1], d + 1), (c[0], d + 1)]);
        }
    }
    let mut size = vec![1usize; nodes.len()];
    for &(n, _) in order.iter().rev() {
        if let Some(c) = children(n) {
            size[n as usize] = 1 + size[c[0] as usize] + size[c[1] as usize];
        }
    }
    let push_levels = |plan: &mut TreeletPlan, by_depth: Vec<Vec<u32>>| {
        let first_level = plan.levels.len() as u32;
        for level in by_depth.iter().rev().filter(|l| !l.is_empty()) {
            plan.levels.push([plan.nodes.len() as u32, level.len() as u32]);
            plan.nodes.extend_from_slice(level);
        }
        plan.treelets.push([first_level, plan.levels.len() as u32 - first_level]);
    };
    // Treelet roots: nodes small enough whose parent is not (or the root itself).
    let mut top: Vec<Vec<u32>> = Vec::new();
    let mut stack = vec![(0u32, 0usize)];
    while let Some((n, d)) = stack.pop() {
        if size[n as usize] <= max_nodes {
            let mut by_depth: Vec<Vec<u32>> = Vec::new();
            let mut inner = vec![(n, 0usize)];
            while let Some((m, k)) = inner.pop() {
                if by_depth.len() <= k {
                    by_depth.resize(k + 1, Vec::new());
                }
                by_depth[k].push(m);
                if let Some(c) = children(m) {
                    inner.extend([(c[1], k + 1), (c[0], k + 1)]);
                }
            }
            push_levels(&mut plan, by_depth);
            continue;
        }
        if top.len() <= d {
            top.resize(d + 1, Vec::new());
        }
        top[d].push(n);
        if let Some(c) = children(n) {
            stack.extend([(c[1], d + 1), (c[0], d + 1)]);
        }
    }
    if !top.is_empty() {
        push_levels(&mut plan, top);
        plan.has_top = true;
    }
    plan
}

/// The refit's own GPU objects for one merged build (its arrays stay the same buffers until
/// the next build, which makes a new refit).
pub struct MergedRefit {
    pipeline: wgpu::ComputePipeline,
    /// The merged arrays and the refit's own buffers; `Params` records `params_stride` apart.
    bind_group: wgpu::BindGroup,
    transforms: wgpu::Buffer,
    /// Object-space vertices in leaf order, with their gather indices.
    object_vertices: wgpu::Buffer,
    /// The merged tree's nodes (the cache's buffer) and their count.
    nodes: wgpu::Buffer,
    node_count: u32,
    params_stride: u64,
    /// Workgroups (treelets) per dispatch: the subtree treelets, then the top one.
    dispatches: Vec<u32>,
    levels: usize,
    /// Which scene instances were merged (usable transform and mesh), in scene order.
    usable: Vec<bool>,
}

/// The bindings of `refit_treelets` after the parameters (binding 0, a uniform with a dynamic
/// offset) and whether each is read-only: nodes, triangles, object vertices, transforms, level
/// nodes, TLAS nodes, level ranges, treelets.
const PLANNED_BINDINGS: [(u32, bool); 8] = [(1, false), (2, false), (3, true), (4, true), (5, true), (6, false), (7, true), (8, true)];

/// The buffers a [`MergedRefit`] makes for itself (the merged arrays are the cache's).
struct PlannedArrays {
    object_vertices: wgpu::Buffer,
    transforms: wgpu::Buffer,
    level_nodes: wgpu::Buffer,
    level_ranges: wgpu::Buffer,
    treelets: wgpu::Buffer,
    params: wgpu::Buffer,
}

impl PlannedArrays {
    /// The refit's input vertices `object`, zeroed transforms for `scene`'s instances, the
    /// treelet plan and the parameter records `params`.
    fn new(device: &wgpu::Device, scene: &Scene, object: &[[u32; 4]], plan: &TreeletPlan, params: &[u8]) -> Self {
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        Self {
            object_vertices: init("refit object vertices", bytemuck::cast_slice(object), storage),
            transforms: init("refit transforms", &vec![0u8; 48 * scene.instances().len().max(1)], storage | wgpu::BufferUsages::COPY_DST),
            level_nodes: init("refit level nodes", bytemuck::cast_slice(&plan.nodes), storage),
            level_ranges: init("refit level ranges", bytemuck::cast_slice(&plan.levels), storage),
            treelets: init("refit treelets", bytemuck::cast_slice(&plan.treelets), storage),
            params: init("refit params", params, wgpu::BufferUsages::UNIFORM),
        }
    }

    /// The bind group of `refit_treelets` over these buffers and the cache's `buffers` (tlas
    /// nodes, instances, blas nodes, triangles).
    fn bind_group(&self, device: &wgpu::Device, layout: &wgpu::BindGroupLayout, buffers: &[wgpu::Buffer; 4]) -> wgpu::BindGroup {
        let params = wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: &self.params, offset: 0, size: wgpu::BufferSize::new(16) }),
        };
        let resources = [&buffers[2], &buffers[3], &self.object_vertices, &self.transforms, &self.level_nodes, &buffers[0], &self.level_ranges, &self.treelets];
        let entries: Vec<_> = std::iter::once(params)
            .chain(PLANNED_BINDINGS.iter().zip(resources).map(|(&(binding, _), b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }))
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("refit"), layout, entries: &entries })
    }
}

/// Workgroups (treelets) per dispatch of `plan`: the subtree treelets, then the top one.
fn treelet_dispatches(plan: &TreeletPlan) -> Vec<u32> {
    let subtrees = plan.treelets.len() as u32 - plan.has_top as u32;
    [subtrees, plan.has_top as u32].into_iter().filter(|&n| n > 0).collect()
}

/// The `Params` record of each dispatch, `stride` bytes apart: its first treelet and whether
/// it is the last dispatch.
fn dispatch_params(dispatches: &[u32], stride: u64) -> Vec<u8> {
    let mut params = vec![0u8; stride as usize * dispatches.len()];
    let mut first = 0;
    for (k, &n) in dispatches.iter().enumerate() {
        let record = [first, (k + 1 == dispatches.len()) as u32, 0, 0];
        params[k * stride as usize..][..16].copy_from_slice(bytemuck::cast_slice(&record));
        first += n;
    }
    params
}

/// The layout and pipeline of `refit_treelets`.
fn planned_pipeline(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("refit.wgsl"), source: wgpu::ShaderSource::Wgsl(REFIT_WGSL.into()) });
    let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: binding == 0, min_binding_size: None },
        count: None,
    };
    let entries: Vec<_> = std::iter::once(buffer(0, wgpu::BufferBindingType::Uniform))
        .chain(PLANNED_BINDINGS.iter().map(|&(binding, read_only)| buffer(binding, wgpu::BufferBindingType::Storage { read_only })))
        .collect();
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("refit"), entries: &entries });
    let pipeline_layout =
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("refit"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
    let pipeline = compute_pipeline(device, "refit", &pipeline_layout, &module, "refit_treelets");
    (layout, pipeline)
}

impl MergedRefit {
    /// The refit of `flat` (the merged layout of `scene`) in the cache's `buffers` (tlas nodes,
    /// instances, blas nodes, triangles); `None` for an empty tree.
    pub fn new(device: &wgpu::Device, scene: &Scene, flat: &GpuAccel, buffers: &[wgpu::Buffer; 4]) -> Option<Self> {
        if *flat.blas_roots.first()? != 0 || flat.triangles.iter().all(|t| t.prim == NO_PRIM) {
            return None;
        }
        let object = object_vertices(scene, flat);
        let max_nodes = TREELET_NODES.max(flat.blas_nodes.len().div_ceil(60_000));
        let plan = plan_treelets(&flat.blas_nodes, max_nodes);
        let dispatches = treelet_dispatches(&plan);
        let params_stride = device.limits().min_uniform_buffer_offset_alignment.max(16) as u64;
        let arrays = PlannedArrays::new(device, scene, &object, &plan, &dispatch_params(&dispatches, params_stride));
        let (layout, pipeline) = planned_pipeline(device);
        let bind_group = arrays.bind_group(device, &layout, buffers);
        let usable = usable_instances(scene);
        Some(Self {
            pipeline,
            bind_group,
            transforms: arrays.transforms,
            object_vertices: arrays.object_vertices,
            nodes: buffers[2].clone(),
            node_count: flat.blas_nodes.len() as u32,
            params_stride,
            dispatches,
            levels: plan.depth,
            usable,
        })
    }

    /// Writes `scene`'s transforms and records the refit of the merged arrays.
    pub fn record(&self, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scene: &Scene) {
        write_transforms(queue, &self.transforms, scene);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("accel refit"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        for (k, &groups) in self.dispatches.iter().enumerate() {
            pass.set_bind_group(0, &self.bind_group, &[(k as u64 * self.params_stride) as u32]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
    }

    /// Tree levels.
    pub(crate) fn level_count(&self) -> usize {
        self.levels
    }

    /// Dispatches per refit.
    pub(crate) fn dispatch_count(&self) -> usize {
        self.dispatches.len()
    }
}

/// Object-space vertices in the triangles' (leaf) order, each with its index among all meshes'
/// vertices (mesh by mesh, as [`crate::accel::gpu_records`] lays them out) in w: where
/// `shaders/accel/gather_positions.wgsl` gathers a deformed position from ([`NO_VERTEX`] for none).
fn object_vertices(scene: &Scene, flat: &GpuAccel) -> Vec<[u32; 4]> {
    let mut first_vertex = Vec::with_capacity(scene.meshes().len());
    let mut next = 0u64;
    for m in scene.meshes() {
        first_vertex.push(next);
        next += m.vertices.len() as u64;
    }
    let mut object = Vec::with_capacity(flat.triangles.len() * 3);
    for t in &flat.triangles {
        let mesh = scene.instances().get(t.instance as usize).map(|i| i.mesh).filter(|_| t.prim != NO_PRIM);
        let verts = mesh.and_then(|m| super::bvh::mesh_triangle(&scene.meshes()[m], t.prim as usize));
        match (mesh, verts) {
            (Some(m), Some(verts)) => {
                let index = |c: usize| {
                    let id = first_vertex[m] + scene.meshes()[m].indices[3 * t.prim as usize + c] as u64;
                    u32::try_from(id).unwrap_or(NO_VERTEX)
                };
                object.extend((0..3).map(|c| [verts[c].x.to_bits(), verts[c].y.to_bits(), verts[c].z.to_bits(), index(c)]));
            }
            _ => object.extend([[0, 0, 0, NO_VERTEX]; 3]),
        }
    }
    object
}

/// No vertex to gather from: the gather index of a leaf slot without a triangle.
pub(crate) const NO_VERTEX: u32 = u32::MAX;

fn usable_instances(scene: &Scene) -> Vec<bool> {
    scene.instances().iter().map(|i| scene.meshes().get(i.mesh).is_some() && instance_transform(&i.transform).is_some()).collect()
}

/// The merged layout's GPU refit, for a tree built on the CPU or on the GPU.
pub enum Refit {
    /// A CPU-built tree, refitted by the CPU's treelet plan.
    Planned(MergedRefit),
    /// A GPU-built tree, refitted from its parents.
    Tree(TreeRefit),
}

impl Refit {
    /// Whether `scene` differs from the refitted one only in where its instances are (same
    /// meshes, same instances of them, every transform as usable as before): the caller checks
    /// the meshes, this the transforms.
    pub(crate) fn applies_to(&self, scene: &Scene) -> bool {
        let usable = match self {
            Refit::Planned(r) => &r.usable,
            Refit::Tree(r) => &r.usable,
        };
        usable_instances(scene) == *usable
    }

    /// The refit's object-space input (three `vec4` per leaf triangle, w: the gather index).
    pub fn object_vertices(&self) -> &wgpu::Buffer {
        match self {
            Refit::Planned(r) => &r.object_vertices,
            Refit::Tree(r) => &r.arrays[5],
        }
    }

    /// The refitted tree's nodes and their count.
    pub fn nodes(&self) -> (&wgpu::Buffer, u32) {
        match self {
            Refit::Planned(r) => (&r.nodes, r.node_count),
            Refit::Tree(r) => (&r.arrays[0], r.node_count),
        }
    }

    /// Writes `scene`'s transforms and records the refit of the merged arrays.
    pub fn record(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scene: &Scene) {
        match self {
            Refit::Planned(r) => r.record(queue, encoder, scene),
            Refit::Tree(r) => r.record(device, queue, encoder, scene),
        }
    }

    /// Tree levels.
    pub(crate) fn level_count(&self) -> usize {
        match self {
            Refit::Planned(r) => r.level_count(),
            Refit::Tree(r) => r.depth as usize + 1,
        }
    }

    /// Dispatches per refit.
    pub(crate) fn dispatch_count(&self) -> usize {
        match self {
            Refit::Planned(r) => r.dispatch_count(),
            Refit::Tree(_) => 2,
        }
    }
}

/// The pipelines of [`TreeRefit`] (`refit_leaves`, `refit_interior`), made once per device.
#[derive(Clone)]
pub struct TreeRefitPipelines {
    layout: wgpu::BindGroupLayout,
    leaves: wgpu::ComputePipeline,
    interior: wgpu::ComputePipeline,
}

impl TreeRefitPipelines {
    /// Compiles the refit shader's two entry points for GPU-built trees.
    pub fn new(device: &wgpu::Device) -> Self {
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("refit.wgsl"), source: wgpu::ShaderSource::Wgsl(REFIT_WGSL.into()) });
        let buffer = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let entries: Vec<_> = TREE_BINDINGS.iter().map(|&(binding, read_only)| buffer(binding, read_only)).collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("tree refit"), entries: &entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tree refit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let leaves = compute_pipeline(device, "refit leaves", &pipeline_layout, &module, "refit_leaves");
        let interior = compute_pipeline(device, "refit interior", &pipeline_layout, &module, "refit_interior");
        Self { layout, leaves, interior }
    }
}

/// The bindings of `refit_leaves` and `refit_interior` and whether each is read-only: nodes,
/// triangles, object vertices, transforms, TLAS nodes, parents, leaf order, box keys.
const TREE_BINDINGS: [(u32, bool); 8] = [(1, false), (2, false), (3, true), (4, true), (6, false), (9, true), (10, true), (11, false)];

/// The refit of a merged tree built on the GPU: its arrays stay where the builder wrote them
/// and the traversal binds them; the refit needs the builder's parents and leaf order, and the
/// object-space vertices of the builder's input records (made beside them on the GPU,
/// [`crate::accel::gpu_records`]), bound at its first refit.
pub struct TreeRefit {
    pipelines: TreeRefitPipelines,
    /// nodes, triangles, parents, leaf order (the builder's), TLAS nodes (the cache's) and the
    /// object-space vertices in input order.
    arrays: [wgpu::Buffer; 6],
    node_count: u32,
    depth: u32,
    usable: Vec<bool>,
    /// The bind group and transforms buffer, made at the first refit.
    bound: Option<(wgpu::BindGroup, wgpu::Buffer)>,
}

impl TreeRefit {
    /// The refit of `built` (the merged layout of `scene`, built from records whose three
    /// object-space vertices each are `object_vertices`, as `vec4<f32>`), whose root the refit
    /// also writes into `tlas_nodes`.
    pub fn new(pipelines: &TreeRefitPipelines, scene: &Scene, built: &GpuBlas, object_vertices: &wgpu::Buffer, tlas_nodes: &wgpu::Buffer) -> Self {
        Self {
            pipelines: pipelines.clone(),
            arrays: [
                built.nodes.clone(),
                built.triangles.clone(),
                built.parents.clone(),
                built.leaf_order.clone(),
                tlas_nodes.clone(),
                object_vertices.clone(),
            ],
            node_count: built.node_count,
            depth: built.depth,
            usable: usable_instances(scene),
            bound: None,
        }
    }

    /// The bind group and the transforms buffer it binds.
    fn bind(&self, device: &wgpu::Device, scene: &Scene) -> (wgpu::BindGroup, wgpu::Buffer) {
        let storage = wgpu::BufferUsages::STORAGE;
        let transforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("refit transforms"),
            contents: &vec![0u8; 48 * scene.instances().len().max(1)],
            usage: storage | wgpu::BufferUsages::COPY_DST,
        });
        let box_keys = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("refit box keys"),
            size: 24 * self.node_count as u64,
            usage: storage,
            mapped_at_creation: false,
        });
        let [nodes, triangles, parents, leaf_order, tlas_nodes, object_vertices] = &self.arrays;
        let resources = [nodes, triangles, object_vertices, &transforms, tlas_nodes, parents, leaf_order, &box_keys];
        let entries: Vec<_> =
            TREE_BINDINGS.iter().zip(resources).map(|(&(binding, _), b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }).collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("tree refit"), layout: &self.pipelines.layout, entries: &entries });
        (bind_group, transforms)
    }

    /// Writes `scene`'s transforms and records the two dispatches (the first refit binds first).
    pub fn record(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scene: &Scene) {
        if self.bound.is_none() {
            self.bound = Some(self.bind(device, scene));
        }
        let Some((bind_group, transforms)) = &self.bound else { return };
        write_transforms(queue, transforms, scene);
        let groups = (self.node_count as u64).div_ceil(256).max(1);
        let (x, y) = (groups.min(32768) as u32, groups.div_ceil(32768) as u32);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("accel refit"), timestamp_writes: None });
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_pipeline(&self.pipelines.leaves);
        pass.dispatch_workgroups(x, y, 1);
        pass.set_pipeline(&self.pipelines.interior);
        pass.dispatch_workgroups(x, y, 1);
    }
}

/// Writes `scene`'s object-to-world rows per instance (zero rows where a transform is unusable).
fn write_transforms(queue: &wgpu::Queue, transforms: &wgpu::Buffer, scene: &Scene) {
    let rows: Vec<[[f32; 4]; 3]> = scene.instances().iter().map(|i| instance_transform(&i.transform).map(|a| affine_rows(&a)).unwrap_or_default()).collect();
    if !rows.is_empty() {
        queue.write_buffer(transforms, 0, bytemuck::cast_slice(&rows));
    }
}
