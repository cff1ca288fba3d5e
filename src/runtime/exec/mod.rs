//! The executor: allocates a plan's slots, builds pipelines and bind groups from shader
//! reflection, and records every pass of a frame with a timestamp pair around it.
//!
//! This file holds the [`Executor`] and the order of its steps; each pass kind's build and
//! record code lives in a file of its own (`compute`, `fullscreen`, `scene_raster`,
//! `trace`, `accel_build`, `rust`), beside what they share: the slots (`slots`), the
//! bindings from reflection (`bindings`), the raster kinds' render pass (`render_pass`), the
//! `params` uniforms (`params`), the scene and frame uniforms (`scene_state`), reading
//! textures back (`readback`) and the counts that decide which passes with `runs_when` a
//! frame records (`counts`).

mod accel_build;
mod bindings;
mod compute;
mod counts;
mod draws;
pub mod features;
mod fullscreen;
pub mod history;
mod params;
mod readback;
mod render_pass;
mod rust;
mod scene_raster;
mod scene_state;
mod slots;
mod trace;

pub use features::{SceneFeatures, TRACE_ALPHA_CONSTANT};
#[cfg(not(target_arch = "wasm32"))]
pub use readback::{read_texture, write_exr, write_png};

use super::gpu::Gpu;
use super::profiler::{FramePhases, FrameTimings, GpuTimer};
use super::raster::ScenePipelines;
use super::rust_pass::{RustPass, RustPassIo, RustPasses};
use crate::accel::cache::{AccelCache, BuildReport, RayStats};
use crate::accel::rt_pipeline::RtPass;
use crate::error::RuntimeError;
use crate::graph::compile::{Plan, PlannedPass};
use crate::graph::desc::PassKind;
use crate::graph::reflect::UniformMember;
use crate::runtime::scene_upload::{GpuScene, SceneContent};
use crate::scene::{Camera, Scene};
use web_time::Instant;

enum Pipeline {
    Compute(wgpu::ComputePipeline),
    /// A fullscreen pass.
    Render(wgpu::RenderPipeline),
    /// A `SceneRaster` pass: one variant per draw class (`super::raster`).
    Scene(ScenePipelines),
    /// The `Accel` node's build: the cache's update, recorded at the node's place in the schedule.
    AccelBuild,
    /// A trace pass on the `rt-pipeline` back-end: a ray-tracing pipeline recorded through
    /// wgpu-hal into a command buffer of its own (`crate::accel::rt_pipeline`).
    RayTracing(Box<RtPass>),
    /// A `Rust` pass: the instance of the registered pass, and what it works on.
    Rust {
        pass: Box<dyn RustPass>,
        io: Box<RustPassIo>,
    },
}

/// The layout of a trace module's bind group, its entries and the binding names they have.
type AccelLayout = (wgpu::BindGroupLayout, Vec<wgpu::BindGroupLayoutEntry>, Vec<String>);

/// A raster pass's colour attachments' views and its depth attachment's.
type AttachmentViews = (Vec<wgpu::TextureView>, Option<wgpu::TextureView>);

struct PassRuntime {
    pipeline: Pipeline,
    /// One per `@group`, in order; the trace module's group is in `accel_group`.
    bind_groups: Vec<wgpu::BindGroup>,
    /// For a pass that binds a texture of a history pair: its groups with the pairs' textures
    /// exchanged, set on the frames where they are (`history`).
    history_bind_groups: Option<Vec<wgpu::BindGroup>>,
    /// Trace passes: the layout of the trace module's bind group, and the group itself (made
    /// again whenever the cache replaces its GPU objects).
    accel_layout: Option<AccelLayout>,
    accel_group: Option<wgpu::BindGroup>,
    /// A raster pass's attachment views, made with the pass: with the history pairs in place
    /// (`[0]`) and exchanged (`[1]`, see `history`). Empty for the other kinds.
    views: [AttachmentViews; 2],
    groups: [u32; 3],
    /// The pass's `params` uniform buffer and the members written into it (see
    /// [`Executor::set_param`]).
    params: Option<(wgpu::Buffer, u64, Vec<UniformMember>)>,
}

impl PassRuntime {
    /// A pass of `pipeline` with no bindings, attachments or dispatch size of its own.
    fn bare(pipeline: Pipeline) -> Self {
        Self {
            pipeline,
            bind_groups: Vec::new(),
            history_bind_groups: None,
            accel_layout: None,
            accel_group: None,
            views: Default::default(),
            groups: [0; 3],
            params: None,
        }
    }

    /// The attachment views of a frame where the history pairs are `swapped` or not.
    fn views(&self, swapped: bool) -> &AttachmentViews {
        &self.views[swapped as usize]
    }

    /// The bind groups to set on a frame where the history pairs are `swapped` or not.
    fn bind_groups(&self, swapped: bool) -> &[wgpu::BindGroup] {
        match (&self.history_bind_groups, swapped) {
            (Some(groups), true) => groups,
            _ => &self.bind_groups,
        }
    }
}

enum Physical {
    Texture(wgpu::Texture),
    Buffer(wgpu::Buffer),
    /// An acceleration structure: owned by the [`AccelCache`], not by a slot.
    Accel,
}

/// A plan instantiated on a device, ready to render frames.
pub struct Executor {
    plan: Plan,
    slots: Vec<Physical>,
    passes: Vec<PassRuntime>,
    frame_uniforms: wgpu::Buffer,
    debug_counters: wgpu::Buffer,
    scene: Option<GpuScene>,
    timer: Option<GpuTimer>,
    frame_index: u32,
    /// The acceleration-structure cache (graphs whose kept passes trace rays).
    accel: Option<AccelCache>,
    accel_generation: u64,
    /// Bounding sphere of the scene (centre, radius) this frame.
    scene_sphere: (glam::Vec3, f32),
    /// What the uploaded scene was made from (see [`Executor::sync_scene`]).
    scene_content: SceneContent,
    /// Each mesh's content hashes and bounds while it stays the same `Arc`
    /// (`crate::scene::memo`): a static scene's frame reads no vertex.
    content_memo: crate::scene::memo::MeshMemo<[u64; 2]>,
    bounds_memo: crate::scene::memo::MeshMemo<crate::scene::Bounds>,
    /// The scene as last seen, by pointer, and a count of its changes: a frame of an unchanged
    /// scene skips change detection and the draw inputs made from it.
    seen: Option<crate::scene::memo::SceneSnapshot>,
    scene_generation: u64,
    /// The draw classes and order of the last frame, kept while the scene and camera stay.
    draws: draws::DrawInputs,
    samplers: (wgpu::Sampler, wgpu::Sampler),
    /// What the scene uses of the features passes compile out ([`features`]); the passes are
    /// built again when it changes.
    features: features::SceneFeatures,
    /// The light records of the scene generation they were made for (`scene_state`).
    lights: Option<(u64, crate::runtime::light_records::LightRecords)>,
    /// Whether the warning about lights without a raster shadow map was printed.
    warned_unshadowed: bool,
    /// Whether the warning about emissive surfaces that light nothing was printed.
    warned_glow: bool,
    /// The Rust passes layer files may name (`PassKind::Rust`).
    rust_passes: RustPasses,
    /// The history pairs, their swap and the history's validity (`history`).
    history: history::HistoryState,
    /// The GPU deformation of the scene's skinned and morphed meshes, if it has any.
    deform: Option<crate::runtime::deform::GpuDeform>,
    /// The counts passes with `runs_when` are recorded by, if any pass has one.
    run_counts: Option<counts::RunCounts>,
}

/// One frame while it is recorded.
struct FrameRecording {
    encoder: wgpu::CommandEncoder,
    /// Command buffers before `encoder`'s, in submission order (rt-pipeline passes record
    /// into command buffers of their own).
    command_buffers: Vec<wgpu::CommandBuffer>,
    /// CPU milliseconds of recording each pass.
    cpu_ms: Vec<f64>,
    /// The `Accel` node's build report and its CPU milliseconds.
    accel_report: Option<(BuildReport, f64)>,
}

/// What the passes of one frame record with, beside the executor.
struct FrameInputs<'a> {
    scene: &'a Scene,
    /// Shadow slots lights use this frame (bit `slot`); passes of the other slots are not drawn.
    shadow_slots: u32,
    /// Whether consecutive compute nodes are recorded into one pass ([`Gpu::merges_compute_passes`]).
    merged: bool,
    /// The passes the frame does not record ([`Executor::passes_skipped`]).
    skipped: Vec<bool>,
}

/// Whether shadow slot `slot` is among those of the mask `slots` (`FrameUniforms::shadow_slots`).
fn slot_in_use(slots: u32, slot: u32) -> bool {
    slot < 32 && slots & (1 << slot) != 0
}

impl Executor {
    /// How many times the frames so far found the scene changed (by pointer: `scene::memo`),
    /// the first frame included: a static scene's count stays 1.
    pub fn scene_changes(&self) -> u64 {
        self.scene_generation
    }

    /// The scene as uploaded (None when no kept pass reads it).
    pub fn uploaded_scene(&self) -> Option<&GpuScene> {
        self.scene.as_ref()
    }

    /// Allocates the plan's resources and builds its pipelines. The scene is uploaded only if
    /// the plan uses it. A plan with a `Rust` pass needs [`Executor::with_rust_passes`].
    pub fn new(gpu: &Gpu, plan: Plan, scene: &Scene) -> Result<Self, RuntimeError> {
        Self::with_rust_passes(gpu, plan, scene, RustPasses::new())
    }

    /// [`Executor::new`] for a plan whose layer files may name the Rust passes of
    /// `rust_passes` (`kind: Rust`, the registered name in `entry`); one that names another is
    /// an error naming its layer file and pass.
    pub fn with_rust_passes(gpu: &Gpu, plan: Plan, scene: &Scene, rust_passes: RustPasses) -> Result<Self, RuntimeError> {
        let scope = gpu.scopes();
        let slots = Self::allocate_slots(gpu, &plan)?;
        let (frame_uniforms, debug_counters) = Self::builtin_buffers(gpu.device());
        let scene_gpu = Self::upload_scene(gpu, &plan, scene)?;
        let samplers = Self::samplers(gpu.device());
        let accel = Self::accel_cache(gpu, &plan);
        let run_counts = counts::RunCounts::of_plan(gpu.device(), &plan);
        let mut content_memo = crate::scene::memo::MeshMemo::new();
        let scene_content = if scene_gpu.is_some() { SceneContent::of(scene, &mut content_memo) } else { SceneContent::default() };
        let mut exec = Self {
            plan,
            slots,
            passes: Vec::new(),
            frame_uniforms,
            debug_counters,
            scene: scene_gpu,
            timer: None,
            frame_index: 0,
            accel,
            accel_generation: u64::MAX,
            scene_sphere: (glam::Vec3::ZERO, 1.0),
            scene_content,
            content_memo,
            bounds_memo: crate::scene::memo::MeshMemo::new(),
            seen: None,
            scene_generation: 0,
            draws: draws::DrawInputs::default(),
            samplers,
            lights: None,
            warned_unshadowed: false,
            warned_glow: false,
            features: features::SceneFeatures::of(scene),
            rust_passes,
            history: history::HistoryState::default(),
            deform: None,
            run_counts,
        };
        exec.make_deform(gpu, scene);
        exec.history = history::HistoryState::of_plan(&exec.plan);
        exec.rebuild_passes(gpu)?;
        if gpu.timestamps() {
            exec.timer = Some(GpuTimer::new(gpu.device(), gpu.queue(), exec.plan.passes.len() as u32));
        }
        let (w, h) = exec.plan.frame_size;
        let context = format!(
            "creating the graph's GPU objects ({} of textures and buffers in {} slots for a {w}x{h} frame, {} of scene data)",
            crate::graph::compile::fmt_bytes(exec.plan.bytes_with_reuse()),
            exec.plan.slots.len(),
            crate::graph::compile::fmt_bytes(exec.scene.as_ref().map_or(0, |s| s.bytes()))
        );
        scope.finish(gpu, &context)?;
        Ok(exec)
    }

    /// The plan the executor runs.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Marks the next frame as a camera cut: its history is not valid
    /// (`frame.history_valid` = 0), as after a jump of the camera (`history`).
    pub fn camera_cut(&mut self) {
        self.history.cut_requested = true;
    }

    /// Whether the frame being recorded, or the last one rendered, had a valid history.
    pub fn history_valid(&self) -> bool {
        self.history.valid
    }

    /// Builds every pass's GPU objects again (the draws kept for the old ones are forgotten).
    fn rebuild_passes(&mut self, gpu: &Gpu) -> Result<(), RuntimeError> {
        let passes = self.plan.passes.iter().map(|pass| self.build_pass(gpu, pass)).collect::<Result<Vec<_>, _>>()?;
        self.passes = passes;
        self.draws.forget_passes();
        Ok(())
    }

    /// One pass's GPU objects: its bindings from reflection, then its kind's pipeline.
    fn build_pass(&self, gpu: &Gpu, pass: &PlannedPass) -> Result<PassRuntime, RuntimeError> {
        match pass.kind {
            PassKind::AccelBuild => return Ok(Self::accel_build_pass()),
            PassKind::Rust => return self.build_rust_pass(gpu, pass),
            _ => {}
        }
        let bindings = self.reflect_bindings(gpu, pass, false)?;
        if pass.kind == PassKind::Trace && self.plan.backend == crate::backend::Backend::RtPipeline {
            if self.binds_history(pass) {
                return Err(RuntimeError::Gpu(format!(
                    "pass {} ({}) traces rays on the rt-pipeline back-end and binds a history texture, which that back-end cannot swap yet: read the history in a compute pass, or use the compute or ray-query back-end",
                    pass.name,
                    pass.location
                )));
            }
            return self.build_rt_pass(gpu, pass, bindings);
        }
        let history_bind_groups = match self.binds_history(pass) {
            true => {
                let mut swapped = self.reflect_bindings(gpu, pass, true)?;
                // One `params` buffer for both sets, so that `set_param` reaches either.
                swapped.params_buffer.clone_from(&bindings.params_buffer);
                Some(self.create_bind_groups(gpu, pass, &swapped).bind_groups)
            }
            false => None,
        };
        let layout = self.create_bind_groups(gpu, pass, &bindings);
        let runtime = match pass.kind {
            PassKind::AccelBuild | PassKind::Rust => unreachable!("returned above"),
            PassKind::Compute | PassKind::Trace => self.build_compute_pass(gpu, pass, layout, bindings),
            PassKind::Fullscreen => self.build_fullscreen_pass(gpu, pass, layout, bindings),
            PassKind::SceneRaster => self.build_scene_raster_pass(gpu, pass, layout, bindings),
        };
        Ok(PassRuntime { history_bind_groups, ..runtime })
    }

    /// Records and submits one frame; waits for it and returns its pass timings.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn render(&mut self, gpu: &Gpu, camera: &Camera, scene: &Scene) -> Result<FrameTimings, RuntimeError> {
        // Native, every await below is ready at once: the waits are inside (`map_read_async`).
        pollster::block_on(self.render_async(gpu, camera, scene))
    }

    /// [`Executor::render`] as a future: what a browser runs, whose main thread cannot wait
    /// for the GPU. It resolves once the frame's timestamps and ray counters are read back.
    pub async fn render_async(&mut self, gpu: &Gpu, camera: &Camera, scene: &Scene) -> Result<FrameTimings, RuntimeError> {
        let start = Instant::now();
        // A pose left to the GPU, without a GPU deformation here (a plan that uploads no
        // vertices): deformed on the CPU instead.
        let posed;
        let scene = if self.deform.is_none() && scene.posed().is_some_and(|p| !p.meshes_deformed) {
            posed = scene.with_meshes_posed();
            &*posed
        } else {
            scene
        };
        let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        self.begin_frame(gpu, scene, camera)?;
        let mut phases = FramePhases { scene_ms: ms(t), ..Default::default() };
        let t = Instant::now();
        let uniforms = self.frame_uniforms(gpu, camera, scene)?;
        gpu.queue().write_buffer(&self.frame_uniforms, 0, bytemuck::bytes_of(&uniforms));
        let scope = gpu.scopes();
        let mut frame = FrameRecording {
            encoder: gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") }),
            command_buffers: Vec::new(),
            cpu_ms: Vec::with_capacity(self.passes.len()),
            accel_report: None,
        };
        let inputs = self.frame_inputs(gpu, camera, scene, &uniforms);
        phases.uniforms_ms = ms(t);
        // Before every pass: rasterized and traced passes alike see this frame's shapes.
        self.record_deform(gpu, &mut frame.encoder, scene);
        self.record_passes(gpu, &mut frame, &inputs)?;
        let FrameRecording { encoder, command_buffers, cpu_ms, accel_report } = frame;
        let t = Instant::now();
        phases.finish_ms = self.submit(gpu, encoder, command_buffers);
        scope.finish_async(gpu, "recording the frame").await?;
        phases.submit_ms = ms(t);
        let t = Instant::now();
        // The GPU deadline (a browser has its own: it loses the device).
        #[cfg(not(target_arch = "wasm32"))]
        gpu.wait_for(|| self.frame_work())?;
        phases.wait_ms = ms(t);
        let t = Instant::now();
        if let Some(cache) = self.accel.as_mut() {
            cache.read_probe(gpu.device()).await?;
        }
        if let Some(counts) = self.run_counts.as_mut() {
            counts.read(gpu.device()).await?;
        }
        let mut timings = self.frame_timings(gpu, start, cpu_ms, accel_report).await?;
        timings.phases = FramePhases { readback_ms: ms(t), ..phases };
        timings.skipped = inputs.skipped;
        // The frame ends after its last part: read last, so a pause of the thread between the
        // two readings cannot leave the parts longer than the frame.
        timings.frame_ms = ms(start);
        if let (Some(cache), Some(gpu_ms)) = (self.accel.as_mut(), timings.gpu_ms.as_ref()) {
            let trace_ms: f64 = self.plan.passes.iter().zip(gpu_ms).filter(|(p, _)| p.kind == PassKind::Trace).map(|(_, ms)| ms).sum();
            cache.note_trace_ms(trace_ms);
        }
        self.frame_index += 1;
        Ok(timings)
    }

    /// What the frame's passes record with: each scene pass's draws brought up to date
    /// ([`draws`]: kept while the scene and the camera's position stay; a shadow-map pass's
    /// classes from its slot's light).
    fn frame_inputs<'a>(&mut self, gpu: &Gpu, camera: &Camera, scene: &'a Scene, uniforms: &crate::uniforms::FrameUniforms) -> FrameInputs<'a> {
        let draws = self.scene.as_ref().map_or(&[][..], |s| s.draws());
        for (i, (pass, planned)) in self.passes.iter_mut().zip(&self.plan.passes).enumerate() {
            let Pipeline::Scene(pipelines) = &mut pass.pipeline else { continue };
            let (columns, rows) = planned.tile_grid();
            for tile in 0..columns * rows {
                let light_view_proj = planned
                    .shadow_slot
                    .map(|slot| slot + tile)
                    .filter(|slot| slot_in_use(uniforms.shadow_slots, *slot))
                    .map(|slot| glam::Mat4::from_cols_array_2d(&uniforms.shadow_view_proj[slot as usize]));
                let source = draws::PassDrawSource { pipelines: &mut *pipelines, back_to_front: planned.translucent, tile, light_view_proj };
                self.draws.update_pass(gpu, scene, self.scene_generation, draws, camera.position, i, source);
            }
        }
        let mut inputs = FrameInputs { scene, shadow_slots: uniforms.shadow_slots, merged: gpu.merges_compute_passes(), skipped: Vec::new() };
        inputs.skipped = self.passes_skipped(&inputs);
        inputs
    }

    /// Records every pass of the frame in schedule order: each run of consecutive compute nodes
    /// as one compute pass where `inputs.merged` ([`Executor::compute_run_end`]), the others one
    /// by one.
    fn record_passes(&mut self, gpu: &Gpu, frame: &mut FrameRecording, inputs: &FrameInputs) -> Result<(), RuntimeError> {
        if let Some(timer) = &self.timer {
            timer.skip(&inputs.skipped);
        }
        let mut i = 0;
        while i < self.passes.len() {
            let end = self.compute_run_end(inputs, i);
            if end > i {
                self.record_compute_run(&mut frame.encoder, i..end, &inputs.skipped, &mut frame.cpu_ms);
                i = end;
            } else {
                self.record_pass(gpu, frame, inputs, i)?;
                i += 1;
            }
        }
        Ok(())
    }

    /// Whether pass `i` has nothing to draw this frame: shadow slots no light uses, or a
    /// translucent pass without translucent instances (`scene_raster`).
    fn draws_nothing(&self, inputs: &FrameInputs, i: usize) -> bool {
        let planned = &self.plan.passes[i];
        let nothing_translucent = planned.translucent && self.draws.pass(i, 0).is_none_or(|d| d.runs().is_empty());
        let mut slots = planned.shadow_slots();
        let no_slot_in_use = planned.shadow_slot.is_some() && !slots.any(|slot| slot_in_use(inputs.shadow_slots, slot));
        nothing_translucent || no_slot_in_use
    }

    /// Whether pass `i`'s `runs_when` keeps it from running this frame.
    fn held_back(&self, i: usize) -> bool {
        let Some((condition, r)) = &self.plan.passes[i].runs_when else { return false };
        // Before a count came back, or for one no kept pass writes: the count taken as its whole.
        let (count, whole) = self.run_counts.as_ref().and_then(|c| c.count(*r)).unwrap_or((1, 1));
        !condition.holds(count, whole)
    }

    /// Which passes the frame does not record: held back by `runs_when`, or with nothing to
    /// draw ([`Executor::draws_nothing`]).
    fn passes_skipped(&self, inputs: &FrameInputs) -> Vec<bool> {
        (0..self.passes.len()).map(|i| self.held_back(i) || self.draws_nothing(inputs, i)).collect()
    }

    /// Records pass `i` of the frame, and its CPU milliseconds.
    fn record_pass(&mut self, gpu: &Gpu, frame: &mut FrameRecording, inputs: &FrameInputs, i: usize) -> Result<(), RuntimeError> {
        let t0 = Instant::now();
        if matches!(self.passes[i].pipeline, Pipeline::AccelBuild) {
            frame.accel_report = self.update_accel(gpu, &mut frame.encoder, &mut frame.command_buffers, inputs)?;
            frame.cpu_ms.push(frame.accel_report.as_ref().map(|(_, ms)| *ms).unwrap_or(0.0));
            return Ok(());
        }
        self.zero_buffers_written(&mut frame.encoder, i);
        if matches!(self.passes[i].pipeline, Pipeline::Rust { .. }) {
            self.record_rust_pass(gpu, &mut frame.encoder, i)?;
            frame.cpu_ms.push(t0.elapsed().as_secs_f64() * 1e3);
            return Ok(());
        }
        if inputs.skipped[i] {
            // No timestamps either (`GpuTimer::skip`): its row reads 0 ms.
            frame.cpu_ms.push(0.0);
            return Ok(());
        }
        match &self.passes[i].pipeline {
            Pipeline::AccelBuild | Pipeline::Rust { .. } => unreachable!("recorded above"),
            Pipeline::RayTracing(rt) => self.record_rt_pass(gpu, frame, inputs, i, rt)?,
            Pipeline::Compute(pipeline) => self.record_compute_pass(&mut frame.encoder, i, pipeline),
            Pipeline::Render(pipeline) => self.record_fullscreen_pass(&mut frame.encoder, i, pipeline),
            Pipeline::Scene(pipelines) => self.record_scene_raster_pass(&mut frame.encoder, i, pipelines, inputs.shadow_slots)?,
        }
        frame.cpu_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        Ok(())
    }

    /// Resolves the timestamps, copies the ray counters and submits the frame's command
    /// buffers. Returns the milliseconds of finishing the last encoder.
    fn submit(&self, gpu: &Gpu, mut encoder: wgpu::CommandEncoder, mut command_buffers: Vec<wgpu::CommandBuffer>) -> f64 {
        if let Some(timer) = &self.timer {
            timer.resolve(&mut encoder, self.passes.len() as u32);
        }
        if let Some(cache) = &self.accel {
            cache.copy_stats(&mut encoder);
        }
        if let Some(counts) = &self.run_counts {
            counts.copy(&mut encoder, |r| self.buffer(r));
        }
        let t = Instant::now();
        command_buffers.push(encoder.finish());
        let finish_ms = t.elapsed().as_secs_f64() * 1e3;
        gpu.queue().submit(command_buffers);
        finish_ms
    }

    /// The finished frame's timings: GPU milliseconds per pass, CPU milliseconds, and the ray
    /// counters (one window per trace pass, in schedule order).
    async fn frame_timings(&self, gpu: &Gpu, start: Instant, cpu_ms: Vec<f64>, accel_report: Option<(BuildReport, f64)>) -> Result<FrameTimings, RuntimeError> {
        let gpu_ms = match &self.timer {
            Some(t) => Some(t.read(gpu.device(), self.passes.len() as u32).await?),
            None => None,
        };
        let mut pass_rays = vec![None; self.plan.passes.len()];
        let mut rays = None;
        if let Some(cache) = &self.accel {
            let windows = cache.read_stats(gpu.device()).await?;
            let trace_passes = self.plan.passes.iter().enumerate().filter(|(_, p)| p.kind == PassKind::Trace).map(|(i, _)| i);
            for (i, stats) in trace_passes.zip(&windows) {
                pass_rays[i] = Some(*stats);
            }
            rays = Some(windows.iter().fold(RayStats::default(), |a, b| a.add(b)));
        }
        let frame_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(FrameTimings { gpu_ms, cpu_ms, frame_ms, rays, pass_rays, accel: accel_report.map(|(r, _)| r), phases: FramePhases::default(), skipped: Vec::new() })
    }

    /// The work one frame submits, for the GPU deadline's error: its passes in submission
    /// order with their layer and WGSL files. They are submitted together, so any of them may
    /// be the one that did not end.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    fn frame_work(&self) -> String {
        let passes: Vec<String> = self
            .plan
            .passes
            .iter()
            .filter(|p| p.kind != PassKind::AccelBuild)
            .map(|p| match p.kind {
                PassKind::Rust => format!("`{}` ({}, Rust pass `{}`)", p.name, p.location.file.display(), p.entry),
                _ => format!("`{}` ({}, {})", p.name, p.location.file.display(), p.shader.path.display()),
            })
            .collect();
        match passes.as_slice() {
            [one] => format!("frame {}, pass {one}", self.frame_index),
            _ => format!("frame {}: one of its passes did not end; they were submitted together: {}", self.frame_index, passes.join(", ")),
        }
    }
}
