//! `raygraph bench scale`: speed, build time and memory against the number of unique
//! triangles. Each step is a scene copied N×N×N without de-duplication (every copy with meshes
//! of its own, nothing shared: the acceleration structure is the one the workload graph's
//! `Accel` node asks for, all instances merged into one BVH), from about 10^4 to 3x10^7
//! triangles. Every step is seen from the original scene's views, inside the first copy, so
//! the rows differ by the scene's size alone. Per step and back-end:
//! - GigaRays/s of the scene workload (`graph/bench_rays.ron` from the scene's camera, as
//!   `bench rays` defines it) and of Stress (`graph/bench_primary.ron` from the scene's
//!   `stress` preset or its camera narrowed until it shows no sky);
//! - the first frame's acceleration-structure build: the `Accel` pass's CPU milliseconds
//!   (`compute`: the CPU builder, flattening and upload; `rt-pipeline`: recording the driver's
//!   build) and GPU milliseconds (`rt-pipeline`: the driver's build; `compute`: the copies);
//! - the GPU builder's kernels for the merged layout (`compute` only, up to its
//!   `crate::accel::gpu_build::MAX_GPU_BUILD_TRIANGLES`);
//! - GPU memory per triangle: the device allocator's live bytes after the first frame, minus
//!   before the executor was made, minus the graph's own textures and buffers;
//! - the scene workload frame's wall and GPU milliseconds (medians after the warm-up).
//!
//! A step too large for a back-end (a device limit) is listed with the error, and the run goes
//! on.

use super::rays::{self, RaysConfig};
use super::RunInfo;
use crate::backend::Backend;
use crate::error::RuntimeError;
use crate::graph::compile::{compile_with, Project};
use crate::graph::desc::{ParamValue, PassKind};
use crate::runtime::profiler::median;
use crate::runtime::{Executor, Gpu};
use crate::scene::{LoadOptions, Scene};
use std::fmt::Write;

/// Settings of `raygraph bench scale`.
#[derive(Debug, Clone)]
pub struct ScaleConfig {
    /// (scene, N): the scene copied N×N×N without de-duplication.
    pub steps: Vec<(String, u32)>,
    /// Frame size, frames, the scene workload and the back-ends, as `bench rays` takes them.
    pub rays: RaysConfig,
}

impl ScaleConfig {
    /// Organic x2 and x3 (31k, 106k triangles), then the atrium x1 to x5 (262k to 32.8M).
    pub fn full(rays: RaysConfig) -> Self {
        let steps = [("organic", 2), ("organic", 3), ("atrium", 1), ("atrium", 2), ("atrium", 3), ("atrium", 4), ("atrium", 5)];
        Self { steps: steps.iter().map(|(s, n)| (s.to_string(), *n)).collect(), rays }
    }

    /// Parses `scene:N` steps (`N` 1 when left out).
    pub fn parse_steps(list: &[String]) -> Result<Vec<(String, u32)>, String> {
        list.iter()
            .map(|s| match s.rsplit_once(':') {
                Some((scene, n)) => {
                    n.parse().map(|n: u32| (scene.to_string(), n.max(1))).map_err(|_| format!("`{s}`: the copies per axis after `:` must be a whole number"))
                }
                None => Ok((s.clone(), 1)),
            })
            .collect()
    }
}

/// One step on one back-end.
#[derive(Debug, Clone)]
pub struct ScaleRow {
    /// `scene xN`.
    pub step: String,
    /// Unique triangles.
    pub triangles: usize,
    /// The back-end traced with.
    pub backend: Backend,
    /// GigaRays/s of the scene workload.
    pub workload_grays: f64,
    /// GigaRays/s of Stress.
    pub stress_grays: f64,
    /// The first frame's `Accel` pass: CPU milliseconds.
    pub build_cpu_ms: f64,
    /// The first frame's `Accel` pass: GPU milliseconds.
    pub build_gpu_ms: Option<f64>,
    /// The GPU builder's kernels for the merged layout, or why there is no figure.
    pub gpu_builder: Result<f64, String>,
    /// GPU bytes per triangle (`None` without an allocator report).
    pub bytes_per_triangle: Option<f64>,
    /// The scene workload frame: wall milliseconds.
    pub frame_wall_ms: f64,
    /// The scene workload frame: GPU milliseconds.
    pub frame_gpu_ms: f64,
}

/// The device allocator's live bytes, once freed resources are released.
fn allocated(gpu: &Gpu) -> Option<u64> {
    let _ = gpu.device().poll(wgpu::PollType::wait_indefinitely());
    gpu.device().generate_allocator_report().map(|r| r.total_allocated_bytes)
}

/// The scene workload on `scene` with `backend`: the first frame's build and memory, then the
/// timed frames.
fn workload(gpu: &Gpu, cfg: &RaysConfig, project: &Project, scene: &Scene, backend: Backend) -> Result<ScaleRow, RuntimeError> {
    let plan = compile_with(&cfg.root.join("graph/bench_rays.ron"), project, cfg.size, &rays::workload_options(gpu, backend, cfg))?;
    let graph_bytes = plan.bytes_with_reuse();
    let accel_pass = plan.passes.iter().position(|p| p.kind == PassKind::AccelBuild);
    let before = allocated(gpu);
    let mut exec = Executor::new(gpu, plan, scene)?;
    let first = exec.render(gpu, scene.camera(), scene)?;
    let bytes = allocated(gpu).zip(before).map(|(after, before)| after.saturating_sub(before).saturating_sub(graph_bytes));
    let frames = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, cfg.frames, |_| *scene.camera())?;
    let mut gpu_ms: Vec<f64> = frames.iter().map(super::frame_gpu_ms).collect();
    let mut wall_ms: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
    let mut traced: Vec<f64> = frames.iter().map(|f| f.rays.map_or(0, |r| r.traced()) as f64).collect();
    let frame_gpu_ms = median(&mut gpu_ms);
    Ok(ScaleRow {
        step: String::new(),
        triangles: scene.triangle_count(),
        backend,
        workload_grays: super::grays_per_s(median(&mut traced), frame_gpu_ms),
        stress_grays: f64::NAN,
        build_cpu_ms: first.cpu_ms.get(accel_pass.unwrap_or(usize::MAX)).copied().unwrap_or(f64::NAN),
        build_gpu_ms: accel_pass.and_then(|i| first.gpu_ms.as_ref().map(|g| g[i])),
        gpu_builder: Err("not measured".into()),
        bytes_per_triangle: bytes.map(|b| b as f64 / scene.triangle_count().max(1) as f64),
        frame_wall_ms: median(&mut wall_ms),
        frame_gpu_ms,
    })
}

/// The GPU builder's kernel milliseconds for `scene`'s merged layout (median of 3, after a
/// warm-up), or why there is none.
fn gpu_builder_ms(gpu: &Gpu, scene: &Scene) -> Result<f64, String> {
    use crate::accel::gpu_build::{merged_triangles, GpuBlasBuilder, MAX_GPU_BUILD_TRIANGLES};
    if scene.triangle_count() > MAX_GPU_BUILD_TRIANGLES {
        return Err(format!("over the GPU builder's {MAX_GPU_BUILD_TRIANGLES} triangles"));
    }
    let builder = GpuBlasBuilder::new(gpu.device()).map_err(|e| e.to_string())?;
    let (merged, origin) = crate::accel::layout::merge_instances(scene);
    let input = merged_triangles(&merged, &origin);
    let mut build = || builder.build(gpu.device(), gpu.queue(), &input).map(|b| b.gpu_ms.unwrap_or(f64::NAN)).map_err(|e| RuntimeError::Gpu(e.to_string()));
    crate::runtime::warm_up::WarmUp::for_gpu(gpu, 1).until_settled(gpu, &mut build).map_err(|e| e.to_string())?;
    let mut times = (0..3).map(|_| build()).collect::<Result<Vec<f64>, RuntimeError>>().map_err(|e| e.to_string())?;
    Ok(median(&mut times))
}

/// Runs every step; `progress` sees (done, total, label) after each measurement, `on_rows`
/// the rows so far. Returns the rows and the steps a back-end could not run, with the reason.
pub fn run(
    gpu: &Gpu,
    cfg: &ScaleConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[ScaleRow]),
) -> Result<(Vec<ScaleRow>, Vec<String>), RuntimeError> {
    let rc = &cfg.rays;
    let project = Project { layers_dir: rc.root.join("layers"), shaders_dir: rc.root.join("shaders") };
    let primary = rc.root.join("graph/bench_primary.ron");
    let (mut rows, mut skipped) = (Vec::new(), Vec::new());
    let total = cfg.steps.len() * rc.backends.len();
    for (k, (name, n)) in cfg.steps.iter().enumerate() {
        let (base, _) = crate::scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
        // The copies' own camera frames the whole grid; the original's stays inside copy 0.
        let mut scene = crate::scene::duplicate::duplicate(&base, *n, false);
        *scene.camera_mut() = *base.camera();
        let step = format!("{name} x{n}");
        let stress = rays::stress_camera(gpu, &primary, &project, &scene)?;
        for (b, &backend) in rc.backends.iter().enumerate() {
            let label = format!("{step}: {backend}");
            match measure_step(gpu, rc, &project, &scene, backend, &stress) {
                Ok(mut row) => {
                    row.step = step.clone();
                    rows.push(row);
                }
                Err(RuntimeError::Gpu(e)) => skipped.push(format!("{label}: {}", e.lines().next().unwrap_or_default())),
                Err(e) => return Err(e),
            }
            on_rows(&rows);
            progress(k * rc.backends.len() + b + 1, total, &label);
        }
    }
    Ok((rows, skipped))
}

/// One step on one back-end: the workload, Stress, and on `compute` the GPU builder.
fn measure_step(
    gpu: &Gpu,
    cfg: &RaysConfig,
    project: &Project,
    scene: &Scene,
    backend: Backend,
    stress: &crate::scene::Camera,
) -> Result<ScaleRow, RuntimeError> {
    let mut row = workload(gpu, cfg, project, scene, backend)?;
    let mut options = gpu.compile_options_for(backend);
    options.params.insert(("primary".into(), "rays".into()), ParamValue::Int(cfg.primary_rays));
    let primary = cfg.root.join("graph/bench_primary.ron");
    let work = rays::Workload { graph: &primary, project, options: &options, scene, camera: stress };
    row.stress_grays = rays::measure_rays(gpu, &work, cfg)?;
    row.gpu_builder = if backend == Backend::Compute { gpu_builder_ms(gpu, scene) } else { Err("the driver builds".into()) };
    Ok(row)
}

fn cell(v: Option<f64>, decimals: usize) -> String {
    v.filter(|v| v.is_finite()).map_or("—".into(), |v| format!("{v:.decimals$}"))
}

/// The rows as a markdown table with the steps skipped, with the run's header.
pub fn markdown(info: &RunInfo, rows: &[ScaleRow], skipped: &[String]) -> String {
    let mut s = format!("# bench scale\n\n{}\n", info.markdown());
    s.push_str("| step | unique triangles | back-end | scene workload GR/s | Stress GR/s | build CPU ms | build GPU ms | GPU builder ms | GPU bytes/triangle | frame wall ms | frame GPU ms |\n");
    s.push_str("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let builder = match &r.gpu_builder {
            Ok(ms) => format!("{ms:.3}"),
            Err(why) => format!("— ({why})"),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2} | {:.2} | {:.1} | {} | {} | {} | {:.3} | {:.3} |",
            r.step,
            r.triangles,
            r.backend,
            r.workload_grays,
            r.stress_grays,
            r.build_cpu_ms,
            cell(r.build_gpu_ms, 3),
            builder,
            cell(r.bytes_per_triangle, 1),
            r.frame_wall_ms,
            r.frame_gpu_ms
        );
    }
    if !skipped.is_empty() {
        s.push_str("\nNot run (device limits):\n");
        for k in skipped {
            let _ = writeln!(s, "- {k}");
        }
    }
    s
}

/// The rows as CSV, with the run's header as `#` comments.
pub fn csv(info: &RunInfo, rows: &[ScaleRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("step,triangles,backend,workload_grays,stress_grays,build_cpu_ms,build_gpu_ms,gpu_builder_ms,bytes_per_triangle,frame_wall_ms,frame_gpu_ms\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{:.4},{:.4},{:.3},{},{},{},{:.4},{:.4}",
            r.step,
            r.triangles,
            r.backend,
            r.workload_grays,
            r.stress_grays,
            r.build_cpu_ms,
            cell(r.build_gpu_ms, 4).replace('—', ""),
            r.gpu_builder.as_ref().map_or(String::new(), |ms| format!("{ms:.4}")),
            cell(r.bytes_per_triangle, 2).replace('—', ""),
            r.frame_wall_ms,
            r.frame_gpu_ms
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_parse_with_and_without_copies() {
        let steps = ScaleConfig::parse_steps(&["atrium:3".into(), "box".into()]).unwrap();
        assert_eq!(steps, vec![("atrium".to_string(), 3), ("box".to_string(), 1)]);
        assert!(ScaleConfig::parse_steps(&["atrium:x".into()]).unwrap_err().contains("atrium:x"));
    }
}
