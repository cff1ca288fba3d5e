//! The soak run (`raygraph soak`): thousands of headless frames while the scene, the graph and
//! a shader change, checking at the end of every cycle that process memory and the live GPU
//! objects stay flat and that the image stays finite.
//!
//! A cycle of `cycle` frames, with `c = cycle`:
//!
//! - frames `[0, c/4)`: every instance moves (the acceleration structure refits or rebuilds,
//!   the uploaded instance records are rewritten); at `c/4` they are back in place;
//! - `c/4`: a sphere mesh and an instance of it are added; `c/2`: removed again;
//! - `5c/8`: the graph is hot-swapped to the second graph; `7c/8`: back to the first;
//! - `3c/4`: a WGSL file the graph uses is broken: recompiling must fail with an error naming
//!   that file, and the running graph keeps rendering; `3c/4 + 1`: the file is restored and the
//!   recompiled graph takes over;
//! - `c - 1`: the scene and graph are as at the start, and the check runs.
//!
//! The graphs, layers and shaders are copied into a private temporary folder first, so the
//! user's files are never touched. The first check is the reference: later checks must show
//! the same number of live buffers, textures, views, bind groups, pipelines and shader modules
//! (wgpu's registry report), a resident set within `rss_tolerance_mib` of it, and a finite HDR
//! image.
//!
//! No check passes without its input: a check made where wgpu gives no registry report, or on a
//! graph without the HDR resource (`SoakConfig::hdr_resource`), is a failure saying so
//! (`Check::failures`). Every check also records the GPU memory of wgpu's allocator report
//! (`GpuMemory`) where the back-end has one; it is reported, not judged.

use crate::backend::Backend;
use crate::error::{GraphError, RuntimeError};
use crate::graph::compile::{compile_with, CompileOptions, Plan, Project};
use crate::runtime::{Executor, Gpu};
use crate::scene::{LoadOptions, Mesh, Scene};
use glam::{Mat4, Vec3};
use std::path::{Path, PathBuf};

/// What a soak run does.
#[derive(Debug, Clone)]
pub struct SoakConfig {
    /// Built-in scene name or glTF path.
    pub scene: String,
    /// Frames to run.
    pub frames: u32,
    /// Frames per cycle (at least 16).
    pub cycle: u32,
    /// Frame size.
    pub size: (u32, u32),
    /// Folder holding `graph/`, `layers/` and `shaders/` (copied before the run).
    pub root: PathBuf,
    /// The graph that runs at every check, and the one swapped in for part of each cycle
    /// (paths relative to `root`).
    pub graphs: [PathBuf; 2],
    /// The WGSL file broken and restored in every cycle (relative to `root/shaders`).
    pub broken_shader: PathBuf,
    /// Allowed growth of the resident set over the first check, in MiB.
    pub rss_tolerance_mib: f64,
    /// The traversal back-end (`None`: selected).
    pub backend: Option<Backend>,
    /// The HDR resource (`node.output`) whose texels must all be finite at every check; a
    /// graph without it fails the check.
    pub hdr_resource: String,
}

impl SoakConfig {
    /// The default soak of `frames` frames in cycles of `cycle`, on a copy of `root`.
    pub fn new(root: &Path, frames: u32, cycle: u32, size: (u32, u32)) -> Self {
        Self {
            scene: "default".into(),
            frames,
            cycle: cycle.max(16),
            size,
            root: root.to_path_buf(),
            graphs: [PathBuf::from("graph/hybrid.ron"), PathBuf::from("graph/full_rt.ron")],
            broken_shader: PathBuf::from("resolve/resolve.wgsl"),
            rss_tolerance_mib: 32.0,
            backend: None,
            hdr_resource: "resolve.hdr".into(),
        }
    }

    /// One line for the report: frames, cycle, size and scene.
    pub fn describe(&self) -> String {
        format!("{} frames in cycles of {} at {}x{}, scene {}", self.frames, self.cycle, self.size.0, self.size.1, self.scene)
    }
}

/// Live wgpu objects (kept by the application), from the registry report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LiveObjects {
    /// Buffers.
    pub(crate) buffers: usize,
    /// Textures.
    pub(crate) textures: usize,
    /// Texture views.
    pub(crate) texture_views: usize,
    /// Samplers.
    pub(crate) samplers: usize,
    /// Bind groups.
    pub(crate) bind_groups: usize,
    /// Bind group layouts.
    pub(crate) bind_group_layouts: usize,
    /// Compute pipelines.
    pub(crate) compute_pipelines: usize,
    /// Render pipelines.
    pub(crate) render_pipelines: usize,
    /// Shader modules.
    pub(crate) shader_modules: usize,
}

impl LiveObjects {
    /// The counts of `gpu`'s instance (`None` where wgpu has no report).
    pub fn of(gpu: &Gpu) -> Option<Self> {
        let report = gpu.instance().generate_report()?;
        let hub = report.hub_report();
        Some(Self {
            buffers: hub.buffers.num_kept_from_user,
            textures: hub.textures.num_kept_from_user,
            texture_views: hub.texture_views.num_kept_from_user,
            samplers: hub.samplers.num_kept_from_user,
            bind_groups: hub.bind_groups.num_kept_from_user,
            bind_group_layouts: hub.bind_group_layouts.num_kept_from_user,
            compute_pipelines: hub.compute_pipelines.num_kept_from_user,
            render_pipelines: hub.render_pipelines.num_kept_from_user,
            shader_modules: hub.shader_modules.num_kept_from_user,
        })
    }

    /// One line for the report.
    pub fn describe(&self) -> String {
        format!(
            "{} buffers, {} textures, {} views, {} samplers, {} bind groups, {} layouts, {}+{} pipelines, {} shader modules",
            self.buffers,
            self.textures,
            self.texture_views,
            self.samplers,
            self.bind_groups,
            self.bind_group_layouts,
            self.compute_pipelines,
            self.render_pipelines,
            self.shader_modules
        )
    }
}

/// GPU memory from wgpu's allocator report (the device's memory allocator).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuMemory {
    /// Bytes in live allocations.
    pub allocated: u64,
    /// Bytes of the memory blocks the allocator holds, used or not.
    pub reserved: u64,
}

impl GpuMemory {
    /// The report of `gpu`'s device (`None` where the back-end has no allocator report).
    pub fn of(gpu: &Gpu) -> Option<Self> {
        let report = gpu.device().generate_allocator_report()?;
        Some(Self { allocated: report.total_allocated_bytes, reserved: report.total_reserved_bytes })
    }

    /// `allocated/reserved` in MiB, for the report.
    pub fn describe(&self) -> String {
        let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
        format!("{:.1}/{:.1}", mib(self.allocated), mib(self.reserved))
    }
}

/// One end-of-cycle check.
#[derive(Debug, Clone)]
pub struct Check {
    /// The frame of the check.
    pub frame: u32,
    /// Resident set, MiB.
    pub rss_mib: f64,
    /// Live wgpu objects (`None`: wgpu gave no registry report, a failure).
    pub live: Option<LiveObjects>,
    /// Every texel of the HDR image is finite (`None`: the graph has no HDR resource, a
    /// failure).
    pub finite: Option<bool>,
    /// GPU memory from wgpu's allocator report (`None`: the back-end has none; not judged).
    pub gpu_memory: Option<GpuMemory>,
    /// Seconds since the start.
    pub seconds: f64,
}

impl Check {
    /// What this check finds wrong, one line each, given the first check (the reference;
    /// `None` when this is the first) and the allowed resident-set growth. A missing input (no
    /// registry report, no HDR image) is a failure, never a pass.
    pub fn failures(&self, first: Option<&Check>, rss_tolerance_mib: f64, hdr_resource: &str) -> Vec<String> {
        let mut failures = Vec::new();
        let frame = self.frame;
        match (self.live, first.map(|f| f.live)) {
            (None, _) => failures.push(format!(
                "frame {frame}: live GPU objects not checked: wgpu gave no registry report (Instance::generate_report), so a leak could not be seen"
            )),
            (Some(now), Some(Some(then))) if now != then => {
                failures.push(format!("frame {frame}: live GPU objects changed: {} (first check: {})", now.describe(), then.describe()))
            }
            _ => {}
        }
        if let Some(first) = first {
            if self.rss_mib - first.rss_mib > rss_tolerance_mib {
                failures.push(format!(
                    "frame {frame}: resident memory grew by {:.1} MiB (from {:.1} to {:.1} MiB; tolerance {rss_tolerance_mib} MiB)",
                    self.rss_mib - first.rss_mib,
                    first.rss_mib,
                    self.rss_mib
                ));
            }
        }
        match self.finite {
            None => failures.push(format!("frame {frame}: the finite-image check has no input: the graph has no HDR resource `{hdr_resource}`")),
            Some(false) => failures.push(format!("frame {frame}: the HDR image `{hdr_resource}` has a non-finite texel")),
            Some(true) => {}
        }
        failures
    }

    /// The check as one line of the soak's log: frame, seconds, resident set, finite image,
    /// GPU memory and live objects.
    pub fn log_line(&self) -> String {
        let finite = self.finite.map(|f| f.to_string()).unwrap_or_else(|| "no HDR".into());
        let memory = self.gpu_memory.map(|m| m.describe()).unwrap_or_else(|| "-".into());
        let live = self.live.map(|l| l.describe()).unwrap_or_else(|| "(no registry report)".into());
        format!("{:>7} {:>9.1} {:>8.1} {:>7} {:>15}  {live}", self.frame, self.seconds, self.rss_mib, finite, memory)
    }

    /// The header of `log_line`'s columns.
    pub fn log_header() -> String {
        format!("{:>7} {:>9} {:>8} {:>7} {:>15}  live GPU objects", "frame", "seconds", "RSS MiB", "finite", "GPU MiB al/res")
    }
}

/// Counts of what happened, and what failed.
#[derive(Debug, Clone, Default)]
pub struct SoakReport {
    /// The end-of-cycle checks.
    pub checks: Vec<Check>,
    /// Frames rendered.
    pub frames: u32,
    /// Frames with moved instances.
    pub moved_frames: u32,
    /// Meshes added.
    pub meshes_added: u32,
    /// Meshes removed.
    pub meshes_removed: u32,
    /// Graph swaps.
    pub graph_swaps: u32,
    /// Shader breakages seen as errors.
    pub shader_errors: u32,
    /// Shader fixes picked up.
    pub shader_fixes: u32,
    /// The first shader error seen, as the user would read it.
    pub shader_error_example: Option<String>,
    /// What failed, one line each (empty: the soak passed).
    pub failures: Vec<String>,
}

/// Resident set size of this process in MiB (Linux `/proc/self/statm`; 0 elsewhere).
pub fn rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1).and_then(|p| p.parse::<f64>().ok()))
        .map(|pages| pages * 4096.0 / (1024.0 * 1024.0))
        .unwrap_or(0.0)
}

/// The private copy of the project, removed when dropped.
struct Workdir(PathBuf);

impl Drop for Workdir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn copy_dir(from: &Path, to: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(to)?;
    for entry in std::fs::read_dir(from)? {
        let entry = entry?;
        let target = to.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            copy_dir(&entry.path(), &target)?;
        } else {
            std::fs::copy(entry.path(), &target)?;
        }
    }
    Ok(())
}

fn io_error(path: &Path, e: std::io::Error) -> RuntimeError {
    RuntimeError::Output { path: path.to_path_buf(), source: e }
}

/// Runs the soak; `on_check` sees every check as it is made. Failures of the checks are
/// collected in the report; an `Err` is a frame or a compile that should have worked and did not.
pub fn run(gpu: &Gpu, cfg: &SoakConfig, mut on_check: impl FnMut(&Check, &SoakReport)) -> Result<SoakReport, RuntimeError> {
    let work = Workdir(std::env::temp_dir().join(format!("raygraph-soak-{}", std::process::id())));
    for dir in ["graph", "layers", "shaders"] {
        copy_dir(&cfg.root.join(dir), &work.0.join(dir)).map_err(|e| io_error(&work.0.join(dir), e))?;
    }
    let mut soak = Soak::new(gpu, cfg, &work.0)?;
    let c = cfg.cycle;
    for f in 0..cfg.frames {
        let p = f % c;
        soak.change(f, p)?;
        soak.exec.render(gpu, &soak.scene.camera(), &soak.scene)?;
        soak.report.frames = f + 1;
        if p == c - 1 {
            let check = soak.check(f)?;
            on_check(&check, &soak.report);
        }
    }
    let mut report = soak.report;
    if report.checks.len() < 2 {
        report.failures.push(format!("{} frames make {} checks of a {}-frame cycle: at least two are needed", cfg.frames, report.checks.len(), c));
    }
    Ok(report)
}

/// A soak under way: the private copy of the project, the scene as changed so far, the running
/// graph and the report.
struct Soak<'a> {
    gpu: &'a Gpu,
    cfg: &'a SoakConfig,
    project: Project,
    options: CompileOptions,
    /// The two graphs, in the private copy.
    graphs: [PathBuf; 2],
    /// The scene as loaded.
    base: Scene,
    /// The scene with this frame's changes.
    scene: Scene,
    /// The centre of the scene's bounds.
    center: Vec3,
    /// Half the diagonal of the scene's bounds (the diagonal taken as at least 0.001).
    radius: f32,
    /// The mesh added and removed in every cycle.
    sphere: Mesh,
    /// The WGSL file broken and restored, in the private copy.
    shader: PathBuf,
    /// Its text as copied.
    good_wgsl: String,
    /// The graph running (an index of `graphs`).
    current: usize,
    exec: Executor,
    report: SoakReport,
    start: std::time::Instant,
}

impl<'a> Soak<'a> {
    /// Loads the scene and compiles the first graph of the copy of the project at `work`.
    fn new(gpu: &'a Gpu, cfg: &'a SoakConfig, work: &Path) -> Result<Self, RuntimeError> {
        let project = Project { layers_dir: work.join("layers"), shaders_dir: work.join("shaders") };
        let options = match cfg.backend {
            Some(b) => gpu.compile_options_for(b),
            None => gpu.compile_options(),
        };
        let graphs = cfg.graphs.clone().map(|g| work.join(g));
        let (base, _) = crate::scene::open(&cfg.scene, &LoadOptions { textures: true, ..Default::default() })?;
        let scene: Scene = base.clone();
        let b = base.bounds();
        let (center, radius) = (b.center(), 0.5 * b.diagonal().max(1e-3));
        let sphere = crate::scene::builtin::sphere("soak sphere", 12, 24);
        let shader = project.shaders_dir.join(&cfg.broken_shader);
        let good_wgsl = std::fs::read_to_string(&shader).map_err(|e| io_error(&shader, e))?;
        let exec = Executor::new(gpu, compile_with(&graphs[0], &project, cfg.size, &options)?, &scene)?;
        let report = SoakReport::default();
        let start = std::time::Instant::now();
        Ok(Self { gpu, cfg, project, options, graphs, base, scene, center, radius, sphere, shader, good_wgsl, current: 0, exec, report, start })
    }

    /// Compiles the graph `graphs[index]`.
    fn compile(&self, index: usize) -> Result<Plan, GraphError> {
        compile_with(&self.graphs[index], &self.project, self.cfg.size, &self.options)
    }

    /// Makes the change due at frame `f`, the cycle's frame `p`.
    fn change(&mut self, f: u32, p: u32) -> Result<(), RuntimeError> {
        let c = self.cfg.cycle;
        if p < c / 4 {
            self.move_instances(f);
        } else if p == c / 4 {
            self.add_sphere();
        } else if p == c / 2 {
            self.scene.instances_mut().pop();
            self.scene.pop_mesh();
            self.report.meshes_removed += 1;
        } else if p == 5 * c / 8 || p == 7 * c / 8 {
            self.current = 1 - self.current;
            self.exec = Executor::new(self.gpu, self.compile(self.current)?, &self.scene)?;
            self.report.graph_swaps += 1;
        } else if p == 3 * c / 4 {
            self.break_shader(f)?;
        } else if p == 3 * c / 4 + 1 {
            std::fs::write(&self.shader, &self.good_wgsl).map_err(|e| io_error(&self.shader, e))?;
            self.exec = Executor::new(self.gpu, self.compile(self.current)?, &self.scene)?;
            self.report.shader_fixes += 1;
        }
        Ok(())
    }

    /// Moves every instance sideways, by an offset that turns with the frame.
    fn move_instances(&mut self, f: u32) {
        let phase = f as f32 * 0.37;
        let offset = Vec3::new(phase.sin(), 0.0, phase.cos()) * (0.05 * self.radius);
        for (inst, orig) in self.scene.instances_mut().iter_mut().zip(self.base.instances().iter()) {
            inst.transform = Mat4::from_translation(offset) * orig.transform;
        }
        self.report.moved_frames += 1;
    }

    /// Puts the instances back in place and adds the sphere and an instance of it.
    fn add_sphere(&mut self) {
        for (inst, orig) in self.scene.instances_mut().iter_mut().zip(self.base.instances().iter()) {
            inst.transform = orig.transform;
        }
        let mesh = self.scene.push_mesh(self.sphere.clone());
        let at = Mat4::from_translation(self.center + Vec3::Y * (0.25 * self.radius)) * Mat4::from_scale(Vec3::splat(0.2 * self.radius));
        self.scene.instances_mut().push(crate::scene::Instance { mesh, material: 0, transform: at });
        self.report.meshes_added += 1;
    }

    /// Breaks the shader: compiling the running graph must fail with an error naming it.
    fn break_shader(&mut self, f: u32) -> Result<(), RuntimeError> {
        let shader = &self.shader;
        let broken = format!("{}\nfn broken_on_purpose( {{\n", self.good_wgsl);
        std::fs::write(shader, broken).map_err(|e| io_error(shader, e))?;
        match self.compile(self.current) {
            Ok(_) => self.report.failures.push(format!("frame {f}: a graph using the broken {} compiled", shader.display())),
            Err(e) => {
                let message = e.to_string();
                if !message.contains(&shader.display().to_string()) {
                    self.report.failures.push(format!("frame {f}: the shader error does not name {}: {message}", shader.display()));
                }
                self.report.shader_error_example.get_or_insert(message);
                self.report.shader_errors += 1;
            }
        }
        Ok(())
    }

    /// The end-of-cycle check after frame `f`, judged against the first and added to the report.
    fn check(&mut self, f: u32) -> Result<Check, RuntimeError> {
        let (gpu, cfg) = (self.gpu, self.cfg);
        let finite = match self.exec.plan().resource_by_name(&cfg.hdr_resource) {
            Some(r) => Some(self.exec.read_texture_f32(gpu, r)?.2.iter().all(|t| t.iter().all(|x| x.is_finite()))),
            None => None,
        };
        let check = Check {
            frame: f + 1,
            rss_mib: rss_mib(),
            live: LiveObjects::of(gpu),
            finite,
            gpu_memory: GpuMemory::of(gpu),
            seconds: self.start.elapsed().as_secs_f64(),
        };
        self.report.failures.extend(check.failures(self.report.checks.first(), cfg.rss_tolerance_mib, &cfg.hdr_resource));
        self.report.checks.push(check.clone());
        Ok(check)
    }
}
