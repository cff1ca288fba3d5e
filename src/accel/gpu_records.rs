//! The GPU builder's input records made on the GPU ([`GpuRecordMaker`]), so that a structural
//! rebuild of the merged layout does no CPU work proportional to the scene's triangles: every
//! mesh's positions and index triples stay on the GPU (a mesh is uploaded again only when its
//! content hash changes; its out-of-range triangles are marked then), each rebuild writes one
//! record per usable instance (its object-to-world rows, where its triangles start, its scene
//! index and triangle flags), and `shaders/accel/records.wgsl` moves the triangles to world
//! space, drops the ones [`crate::accel::gpu_build::merged_triangles`] drops (the same
//! classification as [`crate::accel::bvh::classify_mesh_triangle`]) and compacts the rest in
//! the same order. Beside the records go the survivors' object-space vertices, which the tree
//! refit ([`crate::accel::refit::TreeRefit`]) binds. The survivor count is one word on the GPU,
//! read back ([`GpuRecordMaker::make`]) or left for the builder to copy
//! ([`GpuRecordMaker::record`]).

use super::bvh::instance_transform;
use super::gpu_build::{read_bytes, GpuBuildError};
use super::layout::{affine_rows, TRI_ALPHA, TRI_MIRRORED};
use crate::gpu_util::compute_pipeline;
use crate::scene::{Mesh, Scene};
use wgpu::util::DeviceExt;

/// The records kernel's WGSL.
pub(crate) const RECORDS_WGSL: &str = include_str!("../../shaders/accel/records.wgsl");

const GROUP: u64 = 256;
/// The first index of a triangle with an index out of its mesh's range (the WGSL's `BAD_INDEX`).
const BAD_INDEX: u32 = u32::MAX;

/// The records of one rebuild, on the GPU.
pub struct GpuRecords {
    /// The builder's input: `count` [`crate::accel::layout::GpuTriangle`]s (the buffer may be
    /// longer).
    pub records: wgpu::Buffer,
    /// Per record, its three object-space vertices as `vec4<f32>`.
    pub object_vertices: wgpu::Buffer,
    /// Records made (the triangles that survived), after [`GpuRecordMaker::make`];
    /// [`GpuRecordMaker::record`] leaves the most there can be, `slots`, until its count is read.
    pub count: u32,
    /// The same count on the GPU: a `u32` at byte 0.
    pub count_word: wgpu::Buffer,
    /// Input slots: the usable instances' triangles before the classification.
    pub slots: u32,
    /// Bytes written to GPU buffers for them (instance records, meshes that changed).
    pub bytes_uploaded: u64,
}

/// Where a mesh lies in the shared vertex and index buffers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct MeshRange {
    first_vertex: u32,
    vertices: u32,
    first_triangle: u32,
    triangles: u32,
}

/// Every mesh's positions and index triples on the GPU, and the hashes they were written from.
struct MeshData {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    ranges: Vec<MeshRange>,
    hashes: Vec<u64>,
}

/// The records kernel's pipelines and the meshes it reads, kept between rebuilds.
pub struct GpuRecordMaker {
    layout: wgpu::BindGroupLayout,
    count: wgpu::ComputePipeline,
    scan: wgpu::ComputePipeline,
    write: wgpu::ComputePipeline,
    meshes: Option<MeshData>,
}

/// A mesh's positions as `vec4<f32>` (also the layout of the executor's deformed positions).
pub(crate) fn mesh_vertices(mesh: &Mesh) -> Vec<[f32; 4]> {
    mesh.vertices.iter().map(|v| [v.position[0], v.position[1], v.position[2], 0.0]).collect()
}

/// A mesh's whole index triples, a triangle with an index out of range marked by
/// [`BAD_INDEX`] as its first index.
fn mesh_indices(mesh: &Mesh) -> Vec<u32> {
    let n = mesh.vertices.len();
    mesh.indices.chunks_exact(3).flat_map(|tri| if tri.iter().all(|&k| (k as usize) < n) { [tri[0], tri[1], tri[2]] } else { [BAD_INDEX, 0, 0] }).collect()
}

/// Where each mesh goes in the shared buffers, or `None` past 32-bit offsets.
fn mesh_ranges(scene: &Scene) -> Option<Vec<MeshRange>> {
    let (mut vertex, mut triangle) = (0u32, 0u32);
    scene
        .meshes()
        .iter()
        .map(|m| {
            let r = MeshRange {
                first_vertex: vertex,
                vertices: u32::try_from(m.vertices.len()).ok()?,
                first_triangle: triangle,
                triangles: u32::try_from(m.indices.len() / 3).ok()?,
            };
            vertex = vertex.checked_add(r.vertices)?;
            triangle = triangle.checked_add(r.triangles)?;
            Some(r)
        })
        .collect()
}

/// The instance records (see the WGSL) of `scene`'s usable instances and the input slots.
fn instance_records(scene: &Scene, ranges: &[MeshRange]) -> Option<(Vec<[u32; 4]>, u32, u32)> {
    let mut words = Vec::new();
    let (mut slots, mut usable) = (0u32, 0u32);
    for (i, inst) in scene.instances().iter().enumerate() {
        let (Some(range), Some(xf)) = (ranges.get(inst.mesh), instance_transform(&inst.transform)) else { continue };
        if range.triangles == 0 {
            continue;
        }
        let flags = if xf.matrix3.determinant() < 0.0 { TRI_MIRRORED } else { 0 } | if super::alpha::instance_tested(scene, i) { TRI_ALPHA } else { 0 };
        words.extend(affine_rows(&xf).map(|row| row.map(f32::to_bits)));
        words.push([range.first_vertex, range.first_triangle, slots, i as u32]);
        words.push([flags, 0, 0, 0]);
        slots = slots.checked_add(range.triangles)?;
        usable += 1;
    }
    Some((words, slots, usable))
}

impl GpuRecordMaker {
    /// Compiles the records kernel.
    pub fn new(device: &wgpu::Device) -> Self {
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("records.wgsl"), source: wgpu::ShaderSource::Wgsl(RECORDS_WGSL.into()) });
        let entry = |binding: u32| {
            let ty = match binding {
                0 => wgpu::BufferBindingType::Uniform,
                1..=3 => wgpu::BufferBindingType::Storage { read_only: true },
                _ => wgpu::BufferBindingType::Storage { read_only: false },
            };
            wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
                count: None,
            }
        };
        let entries: Vec<_> = (0..8).map(entry).collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("gpu records"), entries: &entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gpu records"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |name: &str| compute_pipeline(device, name, &pipeline_layout, &module, name);
        Self { count: pipeline("records_count"), scan: pipeline("records_scan"), write: pipeline("records_write"), layout, meshes: None }
    }

    /// Brings the meshes on the GPU up to date with `scene` (`hashes`: each mesh's content
    /// hash): only meshes whose hash changed are written, unless the meshes' sizes changed,
    /// which lays them all out again. The bytes written, or `None` past 32-bit offsets.
    pub(crate) fn sync_meshes(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, hashes: &[u64]) -> Option<u64> {
        let ranges = mesh_ranges(scene)?;
        let same_layout = self.meshes.as_ref().is_some_and(|m| m.ranges == ranges);
        if !same_layout {
            let vertices: Vec<[f32; 4]> = scene.meshes().iter().flat_map(|m| mesh_vertices(m)).collect();
            let indices: Vec<u32> = scene.meshes().iter().flat_map(|m| mesh_indices(m)).collect();
            let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
            let init = |label: &str, bytes: &[u8]| {
                let contents = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
            };
            let bytes = 16 * vertices.len() as u64 + 4 * indices.len() as u64;
            self.meshes = Some(MeshData {
                vertices: init("records mesh vertices", bytemuck::cast_slice(&vertices)),
                indices: init("records mesh indices", bytemuck::cast_slice(&indices)),
                ranges,
                hashes: hashes.to_vec(),
            });
            return Some(bytes);
        }
        let data = self.meshes.as_mut()?;
        let mut bytes = 0;
        for (m, mesh) in scene.meshes().iter().enumerate() {
            if data.hashes.get(m) == hashes.get(m) {
                continue;
            }
            let r = data.ranges[m];
            let (vertices, indices) = (mesh_vertices(mesh), mesh_indices(mesh));
            queue.write_buffer(&data.vertices, 16 * r.first_vertex as u64, bytemuck::cast_slice(&vertices));
            queue.write_buffer(&data.indices, 12 * r.first_triangle as u64, bytemuck::cast_slice(&indices));
            bytes += 16 * vertices.len() as u64 + 4 * indices.len() as u64;
        }
        data.hashes = hashes.to_vec();
        Some(bytes)
    }

    /// Every mesh's positions as `vec4<f32>`, one mesh after another, as last synchronised.
    pub(crate) fn positions(&self) -> Option<&wgpu::Buffer> {
        self.meshes.as_ref().map(|m| &m.vertices)
    }

    /// The builder's input records of the merged layout of `scene` (`hashes`: each mesh's
    /// content hash, as the cache keeps them; `positions`: every mesh's positions where a GPU
    /// deformation wrote them, else the meshes' own), made on the GPU; waits for the survivor count.
    /// `None` for a scene without triangles, with more than `max_slots` of them, or past 32-bit
    /// offsets.
    pub fn make(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        meshes: (&[u64], Option<&wgpu::Buffer>),
        max_slots: u32,
    ) -> Result<Option<GpuRecords>, GpuBuildError> {
        let Some(mut made) = self.record(device, queue, scene, meshes, max_slots) else { return Ok(None) };
        made.count = bytemuck::pod_read_unaligned::<u32>(&read_bytes(device, queue, &made.count_word, 0, 4)?);
        Ok(Some(made))
    }

    /// [`Self::make`] without waiting: the kernel is submitted and its survivor count stays on
    /// the GPU ([`GpuRecords::count_word`]; [`GpuRecords::count`] is `slots`).
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        (hashes, positions): (&[u64], Option<&wgpu::Buffer>),
        max_slots: u32,
    ) -> Option<GpuRecords> {
        let mesh_bytes = self.sync_meshes(device, queue, scene, hashes)?;
        let data = self.meshes.as_ref()?;
        let (instances, slots, usable) = instance_records(scene, &data.ranges)?;
        if slots == 0 || slots > max_slots {
            return None;
        }
        let groups = (slots as u64).div_ceil(GROUP);
        let (x, y) = (groups.min(32768) as u32, groups.div_ceil(32768) as u32);
        let storage = wgpu::BufferUsages::STORAGE;
        let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let buffer =
            |label: &str, size: u64, usage| device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false });
        let params = init("records params", bytemuck::cast_slice(&[slots, usable, 1f32.to_bits(), 0]), wgpu::BufferUsages::UNIFORM);
        let instance_buffer = init("records instances", bytemuck::cast_slice(&instances), storage);
        let group_offsets = buffer("records group offsets", 4 * x as u64 * y as u64, storage);
        let total = buffer("records total", 16, storage | wgpu::BufferUsages::COPY_SRC);
        let records = buffer("records (GPU-made)", 48 * slots as u64, storage | wgpu::BufferUsages::COPY_SRC);
        let object_vertices = buffer("records object vertices", 48 * slots as u64, storage | wgpu::BufferUsages::COPY_SRC);
        let vertices = positions.unwrap_or(&data.vertices);
        let resources = [&params, &instance_buffer, vertices, &data.indices, &group_offsets, &total, &records, &object_vertices];
        let entries: Vec<_> = resources.iter().enumerate().map(|(b, r)| wgpu::BindGroupEntry { binding: b as u32, resource: r.as_entire_binding() }).collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("gpu records"), layout: &self.layout, entries: &entries });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("gpu records") });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("gpu records"), timestamp_writes: None });
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_pipeline(&self.count);
            pass.dispatch_workgroups(x, y, 1);
            pass.set_pipeline(&self.scan);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&self.write);
            pass.dispatch_workgroups(x, y, 1);
        }
        queue.submit([encoder.finish()]);
        let bytes_uploaded = mesh_bytes + 16 * instances.len() as u64;
        Some(GpuRecords { records, object_vertices, count: slots, count_word: total, slots, bytes_uploaded })
    }
}
