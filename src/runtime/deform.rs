//! The executor's GPU deformation of skinned and morphed meshes (`shaders/anim/deform.wgsl`):
//! each deforming mesh's rest vertices, morph displacements and joint influences go to the GPU
//! once; each frame whose pose changed uploads only the joint matrices and morph weights
//! (computed from the node hierarchy on the CPU, a few per mesh) and dispatches one kernel per
//! mesh, which writes the scene's vertex buffer and the acceleration structure's positions.
//! A scene posed with [`crate::scene::Scene::pose_for_gpu`] is deformed here; one posed on the
//! CPU ([`crate::scene::Scene::pose`]) has its vertices uploaded instead. A scene without
//! deforming meshes makes none of this.

use crate::gpu_util::compute_pipeline;
use crate::runtime::scene_upload::GpuScene;
use crate::scene::animation::{PoseTime, Rig};
use crate::scene::Scene;
use wgpu::util::DeviceExt;

/// The deformation kernel's WGSL.
pub(crate) const DEFORM_WGSL: &str = include_str!("../../shaders/anim/deform.wgsl");

/// Per deforming mesh: what the kernel's `Params` hold, and the frame data it needs.
struct MeshJob {
    params: [u32; 12],
    joints: usize,
    targets: usize,
    deformer: usize,
}

/// The GPU objects of one scene's deformation.
pub(crate) struct GpuDeform {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params_stride: u64,
    frame: wgpu::Buffer,
    jobs: Vec<MeshJob>,
    /// Every mesh's positions (`vec4<f32>`), one mesh after another: the deforming meshes'
    /// rewritten every frame, the others as uploaded.
    positions: wgpu::Buffer,
    /// The pose last deformed to.
    last: Option<PoseTime>,
}

impl GpuDeform {
    /// Every mesh's positions (`vec4<f32>`), one mesh after another: the deforming meshes'
    /// rewritten every frame, the others as uploaded.
    pub(crate) fn positions(&self) -> &wgpu::Buffer {
        &self.positions
    }
}

fn vec4(v: [f32; 3]) -> [f32; 4] {
    [v[0], v[1], v[2], 0.0]
}

/// Every deforming mesh's data as the kernel reads it, and its place there.
struct Packed {
    shape: Vec<[f32; 4]>,
    influences: Vec<[u32; 4]>,
    jobs: Vec<MeshJob>,
    /// The frame data's size: joint matrices (four each) and morph weights (four per vec4).
    frame_vec4s: usize,
}

impl Packed {
    /// The rest vertices and morph displacements (with normal displacements for every target
    /// where any target has them), the influences, and each mesh's `Params`.
    fn of(rig: &Rig, uploaded: &GpuScene) -> Option<Self> {
        let mut p = Packed { shape: Vec::new(), influences: Vec::new(), jobs: Vec::new(), frame_vec4s: 0 };
        let mut weight_vec4s = 0usize;
        for (d, deformer) in rig.deformers.iter().enumerate() {
            let shape_at = p.shape.len();
            p.shape.extend(deformer.rest.iter().flat_map(|v| [vec4(v.position), vec4(v.normal)]));
            let normals = deformer.targets.iter().any(|t| t.normals.is_some());
            for t in &deformer.targets {
                for (i, d) in t.positions.iter().enumerate() {
                    p.shape.push(d.extend(0.0).to_array());
                    if normals {
                        p.shape.push(t.normals.as_ref().map_or([0.0; 4], |n| n[i].extend(0.0).to_array()));
                    }
                }
            }
            let influences_at = p.influences.len();
            let sets = deformer.skin.as_ref().map_or(0, |s| s.sets);
            if let Some(skin) = &deformer.skin {
                for (j, w) in skin.joints.chunks_exact(4).zip(skin.weights.chunks_exact(4)) {
                    p.influences.push([j[0], j[1], j[2], j[3]]);
                    p.influences.push([w[0], w[1], w[2], w[3]].map(f32::to_bits));
                }
            }
            let joints = deformer.skin.as_ref().and_then(|s| rig.skins.get(s.skin)).map_or(0, |s| s.joints.len());
            let first_vertex = *uploaded.base_vertices().get(deformer.mesh)?;
            let (rest, targets) = (deformer.rest.len() as u32, deformer.targets.len() as u32);
            let at = [shape_at, influences_at, p.frame_vec4s, weight_vec4s].map(|x| x as u32);
            let params = [first_vertex, rest, targets, normals as u32, sets as u32, at[0], at[1], at[2], at[3], 0, 0, 0];
            p.jobs.push(MeshJob { params, joints, targets: deformer.targets.len(), deformer: d });
            p.frame_vec4s += 4 * joints;
            weight_vec4s += deformer.targets.len().div_ceil(4);
        }
        // Morph weights follow every joint matrix.
        for job in &mut p.jobs {
            job.params[8] += p.frame_vec4s as u32;
        }
        p.frame_vec4s += weight_vec4s;
        Some(p)
    }
}

/// A bind group entry over the whole of `buffer`.
fn entire(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

/// The deformation kernel's bind group layout and pipeline.
fn deform_pipeline(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("deform.wgsl"), source: wgpu::ShaderSource::Wgsl(DEFORM_WGSL.into()) });
    let entry = |binding: u32, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: binding == 0, min_binding_size: None },
        count: None,
    };
    let ro = wgpu::BufferBindingType::Storage { read_only: true };
    let rw = wgpu::BufferBindingType::Storage { read_only: false };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("deform"),
        entries: &[entry(0, wgpu::BufferBindingType::Uniform), entry(1, ro), entry(2, ro), entry(3, ro), entry(4, rw), entry(5, rw)],
    });
    let pipeline_layout =
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("deform"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
    let pipeline = compute_pipeline(device, "deform", &pipeline_layout, &module, "deform");
    (layout, pipeline)
}

impl GpuDeform {
    /// The deformation of `scene`'s deforming meshes into `uploaded`'s vertex buffer; `None`
    /// for a scene without them or a plan that uploads no vertices.
    pub fn new(device: &wgpu::Device, scene: &Scene, uploaded: &GpuScene) -> Option<Self> {
        let rig = scene.rig().filter(|r| !r.deformers.is_empty())?;
        let vertices = uploaded.vertices()?;
        let packed = Packed::of(rig, uploaded)?;
        let storage = wgpu::BufferUsages::STORAGE;
        let init = |label: &str, contents: &[u8], usage| {
            let contents = if contents.is_empty() { &[0u8; 16][..] } else { contents };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let shape = init("deform shape", bytemuck::cast_slice(&packed.shape), storage);
        let influences = init("deform influences", bytemuck::cast_slice(&packed.influences), storage);
        let frame = init("deform frame", &vec![0u8; 16 * packed.frame_vec4s.max(1)], storage | wgpu::BufferUsages::COPY_DST);
        let params_stride = device.limits().min_uniform_buffer_offset_alignment.max(48) as u64;
        let mut params = vec![0u8; params_stride as usize * packed.jobs.len()];
        for (k, job) in packed.jobs.iter().enumerate() {
            params[k * params_stride as usize..][..48].copy_from_slice(bytemuck::cast_slice(&job.params));
        }
        let params = init("deform params", &params, wgpu::BufferUsages::UNIFORM);
        let rest_positions: Vec<[f32; 4]> = scene.meshes().iter().flat_map(|m| crate::accel::gpu_records::mesh_vertices(m)).collect();
        let positions = init("deformed positions", bytemuck::cast_slice(&rest_positions), storage | wgpu::BufferUsages::COPY_DST);
        let (layout, pipeline) = deform_pipeline(device);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("deform"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: &params, offset: 0, size: wgpu::BufferSize::new(48) }),
                },
                entire(1, &shape),
                entire(2, &influences),
                entire(3, &frame),
                entire(4, vertices),
                entire(5, &positions),
            ],
        });
        Some(Self { pipeline, bind_group, params_stride, frame, jobs: packed.jobs, positions, last: None })
    }

    /// Records the deformation to `scene`'s pose where it was left to the GPU and differs from
    /// the last one; returns whether it recorded anything.
    pub fn record(&mut self, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scene: &Scene) -> bool {
        let (Some(rig), Some(pose)) = (scene.rig(), scene.posed()) else { return false };
        if pose.meshes_deformed || self.last == Some(pose) {
            return false;
        }
        self.write_frame(queue, rig, pose);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("deform"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        for (k, job) in self.jobs.iter().enumerate() {
            let groups = (job.params[1] as u64).div_ceil(64).max(1);
            pass.set_bind_group(0, &self.bind_group, &[(k as u64 * self.params_stride) as u32]);
            pass.dispatch_workgroups(groups.min(32768) as u32, groups.div_ceil(32768) as u32, 1);
        }
        self.last = Some(pose);
        true
    }

    /// The joint matrices and morph weights of `pose`, written where each mesh's params say.
    fn write_frame(&self, queue: &wgpu::Queue, rig: &Rig, pose: PoseTime) {
        let nodes = rig.pose(pose.clip, pose.time);
        let (mut joints, mut weights) = (Vec::<[f32; 4]>::new(), Vec::<f32>::new());
        for job in &self.jobs {
            let (j, w) = nodes.deform_inputs(rig, &rig.deformers[job.deformer]);
            debug_assert_eq!((j.len(), w.len()), (job.joints, job.targets));
            joints.extend(j.iter().flat_map(|m| m.to_cols_array_2d()));
            let mut w = w;
            w.resize(job.targets.div_ceil(4) * 4, 0.0);
            weights.extend(w);
        }
        let mut data: Vec<f32> = joints.into_iter().flatten().collect();
        data.extend(weights);
        if !data.is_empty() {
            queue.write_buffer(&self.frame, 0, bytemuck::cast_slice(&data));
        }
    }
}
