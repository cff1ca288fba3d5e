//! GPU refit of the merged layout (`Accel(merge: true)` on the `compute` back-end): when only
//! instance transforms change, the triangles are moved to world space again on the GPU and
//! every node box is recomputed bottom-up (`shaders/accel/refit.wgsl`: one dispatch per large
//! tree level, one per run of small levels), instead of merging and rebuilding on the CPU. The tree's topology is kept, so its
//! quality is the one built for the first positions; a structural change rebuilds.

use super::bvh::instance_transform;
use super::layout::{affine_rows, GpuAccel, GpuBvhNode, NO_PRIM};
use crate::scene::Scene;
use wgpu::util::DeviceExt;

/// The refit kernel (part of the back-end, not of any graph).
pub const REFIT_WGSL: &str = include_str!("../../shaders/accel/refit.wgsl");
const WORKGROUP: u32 = 64;

/// The levels of a tree, deepest first: node indices grouped by depth, and (first, count) per
/// level into that list.
pub fn levels_deepest_first(nodes: &[GpuBvhNode]) -> (Vec<u32>, Vec<(u32, u32)>) {
    let mut by_depth: Vec<Vec<u32>> = Vec::new();
    let mut frontier = vec![0u32];
    while !frontier.is_empty() && !nodes.is_empty() {
        let mut next = Vec::new();
        for &n in &frontier {
            let node = &nodes[n as usize];
            if node.count == 0 {
                next.extend([node.left_or_first, node.left_or_first + 1]);
            }
        }
        by_depth.push(std::mem::replace(&mut frontier, next));
    }
    let mut order = Vec::new();
    let mut levels = Vec::new();
    for level in by_depth.iter().rev() {
        levels.push((order.len() as u32, level.len() as u32));
        order.extend_from_slice(level);
    }
    (order, levels)
}

/// The refit's own GPU objects for one merged build.
pub struct MergedRefit {
    /// `refit_level` (one large level) and `refit_small_levels` (a run of small ones).
    pipelines: [wgpu::ComputePipeline; 2],
    layout: wgpu::BindGroupLayout,
    object_vertices: wgpu::Buffer,
    transforms: wgpu::Buffer,
    level_nodes: wgpu::Buffer,
    level_ranges: wgpu::Buffer,
    /// One `Params` record per dispatch, `params_stride` bytes apart.
    params: wgpu::Buffer,
    params_stride: u64,
    dispatches: Vec<Dispatch>,
    levels: usize,
    /// Which scene instances were merged (usable transform and mesh), in scene order.
    usable: Vec<bool>,
}

impl MergedRefit {
    /// The refit of `flat` (the merged layout of `scene`); `None` for an empty tree.
    pub fn new(device: &wgpu::Device, scene: &Scene, flat: &GpuAccel) -> Option<Self> {
        if *flat.blas_roots.first()? != 0 || flat.triangles.iter().all(|t| t.prim == NO_PRIM) {
            return None;
        }
        // Object-space vertices in the triangles' (leaf) order.
        let mut object = Vec::with_capacity(flat.triangles.len() * 3);
        for t in &flat.triangles {
            let verts = scene
                .instances
                .get(t.instance as usize)
                .and_then(|i| scene.meshes.get(i.mesh))
                .filter(|_| t.prim != NO_PRIM)
                .and_then(|m| super::bvh::mesh_triangle(m, t.prim as usize))
                .unwrap_or([glam::Vec3::ZERO; 3]);
            object.extend(verts.map(|v| v.extend(0.0).to_array()));
        }
        let (order, levels) = levels_deepest_first(&flat.blas_nodes);
        let dispatches = plan_dispatches(&levels);
        let params_stride = device.limits().min_uniform_buffer_offset_alignment.max(16) as u64;
        let mut params = vec![0u8; params_stride as usize * dispatches.len().max(1)];
        for (k, d) in dispatches.iter().enumerate() {
            let record = [d.first_level, d.level_count, (k + 1 == dispatches.len()) as u32, 0];
            params[k * params_stride as usize..][..16].copy_from_slice(bytemuck::cast_slice(&record));
        }
        let ranges: Vec<[u32; 2]> = levels.iter().map(|&(first, count)| [first, count]).collect();
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let object_vertices = init("refit object vertices", bytemuck::cast_slice(&object), storage);
        let transforms = init("refit transforms", &vec![0u8; 48 * scene.instances.len().max(1)], storage | wgpu::BufferUsages::COPY_DST);
        let level_nodes = init("refit level nodes", bytemuck::cast_slice(&order), storage);
        let level_ranges = init("refit level ranges", bytemuck::cast_slice(&ranges), storage);
        let params = init("refit params", &params, wgpu::BufferUsages::UNIFORM);

        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("refit.wgsl"), source: wgpu::ShaderSource::Wgsl(REFIT_WGSL.into()) });
        let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: binding == 0, min_binding_size: None },
            count: None,
        };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("refit"),
            entries: &[
                buffer(0, wgpu::BufferBindingType::Uniform),
                buffer(1, rw),
                buffer(2, rw),
                buffer(3, ro),
                buffer(4, ro),
                buffer(5, ro),
                buffer(6, rw),
                buffer(7, ro),
            ],
        });
        let pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("refit"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipelines = [pipeline("refit_level"), pipeline("refit_small_levels")];
        let usable = usable_instances(scene);
        Some(Self {
            pipelines,
            layout,
            object_vertices,
            transforms,
            level_nodes,
            level_ranges,
            params,
            params_stride,
            dispatches,
            levels: levels.len(),
            usable,
        })
    }

    /// Whether `scene` differs from the merged one only in where its instances are (same
    /// meshes, same instances of them, every transform as usable as before): the caller checks
    /// the meshes, this the transforms.
    pub fn applies_to(&self, scene: &Scene) -> bool {
        usable_instances(scene) == self.usable
    }

    /// Writes `scene`'s transforms and records the refit of the merged arrays `buffers`
    /// (tlas nodes, instances, blas nodes, triangles, as the cache holds them).
    pub fn record(&self, device: &wgpu::Device, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scene: &Scene, buffers: &[wgpu::Buffer; 4]) {
        let rows: Vec<[[f32; 4]; 3]> = scene.instances.iter().map(|i| instance_transform(&i.transform).map(|a| affine_rows(&a)).unwrap_or_default()).collect();
        if !rows.is_empty() {
            queue.write_buffer(&self.transforms, 0, bytemuck::cast_slice(&rows));
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("refit"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: &self.params, offset: 0, size: wgpu::BufferSize::new(16) }),
                },
                wgpu::BindGroupEntry { binding: 1, resource: buffers[2].as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: buffers[3].as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: self.object_vertices.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: self.transforms.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: self.level_nodes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: buffers[0].as_entire_binding() },
                wgpu::BindGroupEntry { binding: 7, resource: self.level_ranges.as_entire_binding() },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("accel refit"), timestamp_writes: None });
        for (k, d) in self.dispatches.iter().enumerate() {
            pass.set_pipeline(&self.pipelines[d.small as usize]);
            pass.set_bind_group(0, &bind_group, &[(k as u64 * self.params_stride) as u32]);
            pass.dispatch_workgroups(if d.small { 1 } else { d.nodes.div_ceil(WORKGROUP) }, 1, 1);
        }
    }

    /// Tree levels.
    pub fn level_count(&self) -> usize {
        self.levels
    }

    /// Dispatches per refit.
    pub fn dispatch_count(&self) -> usize {
        self.dispatches.len()
    }
}

/// Levels with at most this many nodes are refitted by one workgroup, several in a row.
pub const SMALL_LEVEL: u32 = 1024;

/// One dispatch of the refit: a large level, or a run of consecutive small levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dispatch {
    pub first_level: u32,
    pub level_count: u32,
    /// Nodes of the (large) level.
    pub nodes: u32,
    pub small: bool,
}

/// Groups `levels` (deepest first) into dispatches.
pub fn plan_dispatches(levels: &[(u32, u32)]) -> Vec<Dispatch> {
    let mut out: Vec<Dispatch> = Vec::new();
    for (l, &(_, count)) in levels.iter().enumerate() {
        let small = count <= SMALL_LEVEL;
        match out.last_mut() {
            Some(d) if small && d.small => d.level_count += 1,
            _ => out.push(Dispatch { first_level: l as u32, level_count: 1, nodes: count, small }),
        }
    }
    out
}

fn usable_instances(scene: &Scene) -> Vec<bool> {
    scene.instances.iter().map(|i| scene.meshes.get(i.mesh).is_some() && instance_transform(&i.transform).is_some()).collect()
}
