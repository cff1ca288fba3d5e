//! `raygraph bench build`: the paper's Figure 9. Each scene copied N×N×N (N = 1..max, one BLAS
//! per copy: de-duplication off) is built by every back-end's builder; reported: triangles,
//! BLAS and TLAS build time (CPU builder: measured separately; ray-query: the driver's GPU
//! build, wall time until it finished), SAH cost of the result (CPU builder), and the GPU time
//! of tracing a fixed grid of camera rays through it, so build speed can be weighed against
//! trace speed. Copies beyond a triangle budget are skipped and listed.

use super::RunInfo;
use crate::backend::Backend;
use crate::error::RuntimeError;
use crate::runtime::batch::{BatchTracer, GpuRay};
use crate::runtime::profiler::median;
use crate::runtime::warm_up::WarmUp;
use crate::runtime::Gpu;
use crate::scene::duplicate::duplicate;
use crate::scene::{LoadOptions, Scene};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Settings of `raygraph bench build` (Figure 9).
#[derive(Debug, Clone)]
pub struct BuildBenchConfig {
    /// Built-in scene names or glTF paths.
    pub scenes: Vec<String>,
    /// The largest N of the N×N×N copies.
    pub max_factor: u32,
    /// Duplications with more triangles than this are skipped.
    pub max_triangles: usize,
    /// Camera rays traced through each build (a grid of this size).
    pub rays: (u32, u32),
    /// The back-ends measured.
    pub backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

impl BuildBenchConfig {
    /// The settings of the published figure.
    pub fn paper(root: &Path, backends: Vec<Backend>) -> Self {
        Self {
            scenes: vec!["box".into(), "organic".into(), "atrium".into()],
            max_factor: 10,
            max_triangles: 30_000_000,
            rays: (1024, 1024),
            backends,
            root: root.to_path_buf(),
        }
    }

    /// A small run for tests.
    pub fn quick(root: &Path, backends: Vec<Backend>) -> Self {
        Self { scenes: vec!["box".into(), "organic".into()], max_factor: 2, max_triangles: 100_000, rays: (32, 32), backends, root: root.to_path_buf() }
    }
}

/// One scene at one duplication on one back-end.
#[derive(Debug, Clone)]
pub struct BuildRow {
    /// The scene.
    pub scene: String,
    /// N of the N×N×N copies.
    pub factor: u32,
    /// Triangles of all copies.
    pub triangles: usize,
    /// The back-end.
    pub backend: Backend,
    /// Milliseconds of the BLAS builds.
    pub blas_ms: Option<f64>,
    /// Milliseconds of the TLAS build.
    pub tlas_ms: Option<f64>,
    /// Until the structure was usable on the GPU (CPU build, flattening and upload; or the GPU
    /// build), milliseconds.
    pub total_ms: f64,
    /// SAH cost of the BLASes.
    pub blas_sah: Option<f64>,
    /// SAH cost of the TLAS.
    pub tlas_sah: Option<f64>,
    /// GPU milliseconds of tracing the camera rays.
    pub trace_ms: Option<f64>,
    /// Millions of rays per second of that trace.
    pub mrays_per_s: Option<f64>,
}

/// Camera rays through a `w`×`h` grid from the scene's default camera.
fn camera_rays(scene: &Scene, size: (u32, u32)) -> Vec<GpuRay> {
    let origin = scene.camera().position.into();
    scene.camera().ray_dirs(size, 1).into_iter().map(|d| GpuRay { origin, t_min: 0.0, dir: d.into(), t_max: 3.0e38 }).collect()
}

/// `on_rows` sees the rows finished so far after each one (to keep the results folder current).
pub fn run(
    gpu: &Gpu,
    cfg: &BuildBenchConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[BuildRow]),
) -> Result<(Vec<BuildRow>, Vec<String>), RuntimeError> {
    let shaders = cfg.root.join("shaders");
    let total = cfg.scenes.len() * cfg.max_factor as usize * cfg.backends.len();
    let (mut rows, mut skipped, mut done) = (Vec::new(), Vec::new(), 0);
    for name in &cfg.scenes {
        let (scene, _) = crate::scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
        for n in 1..=cfg.max_factor {
            let triangles = scene.triangle_count() * (n as usize).pow(3);
            if triangles > cfg.max_triangles {
                skipped.push(format!("{name} x{n}: {triangles} triangles over the budget of {}", cfg.max_triangles));
                done += cfg.backends.len();
                progress(done, total, &format!("{name} x{n}: skipped"));
                continue;
            }
            let copies = duplicate(&scene, n, false);
            let rays = camera_rays(&copies, cfg.rays);
            for &backend in &cfg.backends {
                let tracer =
                    match BatchTracer::with_settings(gpu, backend, &copies, &shaders, crate::accel::cache::AccelSettings { dedup: false, merge: false }) {
                        Ok(t) => t,
                        // Too large for the device: recorded, and the bench goes on.
                        Err(e @ RuntimeError::Gpu(_)) => {
                            skipped.push(format!("{name} x{n} on {backend}: {}", e.to_string().lines().next().unwrap_or_default()));
                            done += 1;
                            progress(done, total, &format!("{name} x{n}: {backend} skipped"));
                            continue;
                        }
                        Err(e) => return Err(e),
                    };
                // Warm-up until the trace time settles: pipeline, caches and clocks.
                WarmUp::for_gpu(gpu, 1).until_settled(gpu, || tracer.time_closest(gpu, &rays).map(|(_, ms)| ms.unwrap_or(0.0)))?;
                let (stats, trace_ms) = tracer.time_closest(gpu, &rays)?;
                let b = tracer.build_report();
                let cpu_builder = backend == Backend::Compute;
                rows.push(BuildRow {
                    scene: name.clone(),
                    factor: n,
                    triangles,
                    backend,
                    blas_ms: cpu_builder.then_some(b.blas_ms),
                    tlas_ms: cpu_builder.then_some(b.tlas_ms),
                    total_ms: tracer.build_wall_ms(),
                    blas_sah: b.blas_sah,
                    tlas_sah: b.tlas_sah,
                    trace_ms,
                    mrays_per_s: trace_ms.filter(|ms| *ms > 0.0).map(|ms| stats.traced() as f64 / (ms * 1e-3) / 1e6),
                });
                on_rows(&rows);
                done += 1;
                progress(done, total, &format!("{name} x{n}: {backend}"));
            }
        }
    }
    Ok((rows, skipped))
}

fn opt(v: Option<f64>, decimals: usize) -> String {
    v.map(|x| format!("{x:.decimals$}")).unwrap_or_default()
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[BuildRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,factor,triangles,backend,blas_ms,tlas_ms,total_ms,blas_sah,tlas_sah,trace_ms,mrays_per_s\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.4},{},{},{},{}",
            r.scene,
            r.factor,
            r.triangles,
            r.backend,
            opt(r.blas_ms, 4),
            opt(r.tlas_ms, 4),
            r.total_ms,
            opt(r.blas_sah, 3),
            opt(r.tlas_sah, 3),
            opt(r.trace_ms, 4),
            opt(r.mrays_per_s, 2)
        );
    }
    s
}

/// The rows as a markdown table with the duplications skipped, with the run's header.
pub fn markdown(info: &RunInfo, rows: &[BuildRow], skipped: &[String]) -> String {
    let mut s = format!("# bench build\n\n{}\n", info.markdown());
    s.push_str("| scene | N | triangles | back-end | BLAS ms | TLAS ms | total ms | BLAS SAH | TLAS SAH | trace ms | Mrays/s |\n");
    s.push_str("| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {:.2} | {} | {} | {} | {} |",
            r.scene,
            r.factor,
            r.triangles,
            r.backend,
            opt(r.blas_ms, 2),
            opt(r.tlas_ms, 3),
            r.total_ms,
            opt(r.blas_sah, 1),
            opt(r.tlas_sah, 1),
            opt(r.trace_ms, 3),
            opt(r.mrays_per_s, 1)
        );
    }
    if !skipped.is_empty() {
        s.push_str("\nSkipped (triangle budget or device limits):\n");
        for k in skipped {
            let _ = writeln!(s, "- {k}");
        }
    }
    s
}

/// `build_time.png` (build until usable, against triangles, log-log as the paper's Figure 9)
/// and `build_trace.png` (trace Mrays/s of the result).
pub fn plots(dir: &Path, rows: &[BuildRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut keys: Vec<(String, Backend)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.scene.clone(), r.backend)) {
            keys.push((r.scene.clone(), r.backend));
        }
    }
    let series = |f: &dyn Fn(&BuildRow) -> Option<f64>| -> Vec<Series> {
        keys.iter()
            .map(|(s, b)| Series {
                name: format!("{s}, {b}"),
                points: rows.iter().filter(|r| &r.scene == s && r.backend == *b).filter_map(|r| f(r).map(|y| (r.triangles as f64, y))).collect(),
            })
            .collect()
    };
    let time = dir.join("build_time.png");
    LinePlot { title: "Acceleration-structure build (Figure 9)", x_label: "triangles", y_label: "ms until usable", log_x: true, log_y: true, x_labels: None }
        .write(&time, &series(&|r| Some(r.total_ms)))?;
    let trace = dir.join("build_trace.png");
    LinePlot { title: "Trace speed of the built structure", x_label: "triangles", y_label: "Mrays/s", log_x: true, log_y: true, x_labels: None }
        .write(&trace, &series(&|r| r.mrays_per_s))?;
    Ok(vec![time, trace])
}

/// The merged layout's GPU refit against its CPU rebuild, per scene (no duplication): the scene
/// through `graph/bench_primary.ron` (`Accel(merge: true)`, one primary ray per pixel), built
/// once, then every instance moved a little before each of `frames` frames.
#[derive(Debug, Clone)]
pub struct RefitRow {
    /// The scene.
    pub scene: String,
    /// Triangles of the merged layout.
    pub triangles: usize,
    /// Tree levels, and the refit's dispatches (large levels one each, runs of small ones one).
    pub levels: usize,
    /// Dispatches of the refit.
    pub dispatches: usize,
    /// CPU milliseconds of the first build (merge and binned-SAH build).
    pub rebuild_ms: f64,
    /// GPU milliseconds of the `Accel` pass on the refitted frames (median, min).
    pub refit_gpu_ms: Option<(f64, f64)>,
    /// CPU milliseconds of the cache's update on those frames (change detection and recording).
    pub refit_cpu_ms: f64,
}

/// The refit against the rebuild of every scene of `cfg`, over `frames` moved frames.
pub fn run_refit(gpu: &Gpu, cfg: &BuildBenchConfig, frames: u32) -> Result<Vec<RefitRow>, RuntimeError> {
    use crate::graph::compile::{compile_with, Project};
    use crate::graph::desc::PassKind;
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let graph = cfg.root.join("graph/bench_primary.ron");
    // `rt/primary_n.wgsl` casts perspective rays only (src/bench/rays.rs says why).
    let primary_camera = |scene: &crate::scene::Scene| crate::scene::Camera { orthographic: None, ..*scene.camera() };
    let mut options = gpu.compile_options_for(Backend::Compute);
    options.params.insert(("primary".into(), "rays".into()), crate::graph::desc::ParamValue::Int(1));
    let mut rows = Vec::new();
    for name in &cfg.scenes {
        let (mut scene, _) = crate::scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
        let plan = compile_with(&graph, &project, (64, 64), &options)?;
        let accel_pass = plan.passes.iter().position(|p| p.kind == PassKind::AccelBuild);
        let mut exec = crate::runtime::Executor::new(gpu, plan, &scene)?;
        let first = exec.render(gpu, &primary_camera(&scene), &scene)?;
        let rebuild_ms = first.accel.as_ref().map(|r| r.blas_ms).unwrap_or(0.0);
        WarmUp::for_gpu(gpu, 1).run(gpu, &mut exec, &scene, &primary_camera(&scene))?;
        let radius = 0.5 * scene.bounds().diagonal();
        let base: Vec<_> = scene.instances().iter().map(|i| i.transform).collect();
        let (mut gpu_ms, mut cpu_ms) = (Vec::new(), Vec::new());
        for f in 0..frames.max(1) {
            let offset = glam::Vec3::new((f as f32 * 0.7).sin(), 0.0, (f as f32 * 0.7).cos()) * (1e-3 * radius);
            for (inst, t) in scene.instances_mut().iter_mut().zip(&base) {
                inst.transform = glam::Mat4::from_translation(offset) * *t;
            }
            let t = exec.render(gpu, &primary_camera(&scene), &scene)?;
            let report = t.accel.clone().unwrap_or_default();
            if !report.blas_refit {
                return Err(RuntimeError::Gpu(format!(
                    "bench build: moving the instances of `{name}` did not refit the merged layout ({})",
                    report.describe()
                )));
            }
            cpu_ms.push(report.cpu_ms);
            if let (Some(ms), Some(i)) = (&t.gpu_ms, accel_pass) {
                gpu_ms.push(ms[i]);
            }
        }
        let (levels, dispatches) = exec.accel().and_then(|a| a.refit_shape()).unwrap_or((0, 0));
        let min = gpu_ms.iter().copied().fold(f64::INFINITY, f64::min);
        let refit_gpu_ms = (!gpu_ms.is_empty()).then(|| (median(&mut gpu_ms), min));
        rows.push(RefitRow {
            scene: name.clone(),
            triangles: scene.triangle_count(),
            levels,
            dispatches,
            rebuild_ms,
            refit_gpu_ms,
            refit_cpu_ms: median(&mut cpu_ms),
        });
    }
    Ok(rows)
}

/// The rows as a markdown table, with the run's header.
pub fn refit_markdown(info: &RunInfo, rows: &[RefitRow]) -> String {
    let mut s = format!("# bench build: merged layout, GPU refit against CPU rebuild\n\n{}\n", info.markdown());
    s.push_str("| scene | triangles | tree levels | dispatches | CPU rebuild ms | GPU refit ms (median) | GPU refit ms (min) | CPU ms per refit frame |\n");
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {} | {} | {:.3} |",
            r.scene,
            r.triangles,
            r.levels,
            r.dispatches,
            r.rebuild_ms,
            opt(r.refit_gpu_ms.map(|m| m.0), 4),
            opt(r.refit_gpu_ms.map(|m| m.1), 4),
            r.refit_cpu_ms
        );
    }
    s
}

/// The rows as CSV, with the run's header.
pub fn refit_csv(info: &RunInfo, rows: &[RefitRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,triangles,levels,dispatches,rebuild_ms,refit_gpu_ms_median,refit_gpu_ms_min,refit_cpu_ms\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{:.4},{},{},{:.4}",
            r.scene,
            r.triangles,
            r.levels,
            r.dispatches,
            r.rebuild_ms,
            opt(r.refit_gpu_ms.map(|m| m.0), 5),
            opt(r.refit_gpu_ms.map(|m| m.1), 5),
            r.refit_cpu_ms
        );
    }
    s
}

/// The GPU builder (H-PLOC or the PLOC rounds, [`crate::accel::gpu_build`]) against the CPU binned-SAH builder on
/// each scene's merged layout: GPU milliseconds of the build (median and min of `builds`), its
/// rounds and depth, and both trees' SAH cost.
#[derive(Debug, Clone)]
pub struct GpuBuildRow {
    /// The scene.
    pub scene: String,
    /// Triangles of the merged layout.
    pub triangles: usize,
    /// GPU milliseconds of the build (median, min).
    pub gpu_ms: Option<(f64, f64)>,
    /// Median GPU milliseconds of each `crate::accel::gpu_build::Phase`.
    pub phase_ms: Option<[f64; 4]>,
    /// Nearest-neighbour rounds of the build (H-PLOC: summed over its ranges).
    pub rounds: u32,
    /// Depth of the deepest leaf.
    pub depth: u32,
    /// CPU milliseconds of `Blas::build` of the merged mesh (median of 3).
    pub cpu_ms: f64,
    /// Wall milliseconds of the input records, the build and a read-back of the whole tree
    /// after merging the instances (median): what a cache rebuild did before the tree stayed on
    /// the GPU, and what a caller that needs the tree on the CPU pays.
    pub wall_ms: f64,
    /// Wall milliseconds of an [`crate::accel::cache::AccelCache`] rebuild of the merged layout
    /// on the GPU builder, nothing read back but a few words (median): `update` after a mesh
    /// edit (hashing, merging, input records, build, the TLAS words), then the submission and
    /// the wait for the GPU. `None` where the cache builds the scene on the CPU (fewer than
    /// `crate::accel::cache::GPU_BUILD_MIN_TRIANGLES` triangles).
    pub cache_rebuild_ms: Option<f64>,
    /// Of that rebuild (medians): the change detection (`BuildReport::hash_ms`, which also
    /// counts the alpha flags' update before it), the whole `update` call
    /// (`BuildReport::cpu_ms`, the build's own waits for its few words included), and the
    /// time until the built arrays were in place (`BuildReport::blas_ms`), milliseconds.
    pub cache_rebuild_parts: Option<[f64; 3]>,
    /// SAH cost of the GPU-built tree.
    pub gpu_sah: f64,
    /// SAH cost of the CPU-built tree.
    pub cpu_sah: f64,
}

/// `builds` GPU builds of every scene of `cfg`'s merged layout.
pub fn run_gpu_builds(gpu: &Gpu, cfg: &BuildBenchConfig, builds: u32) -> Result<Vec<GpuBuildRow>, RuntimeError> {
    use crate::accel::bvh::{Blas, BuildConfig};
    use crate::accel::gpu_build::{layout_sah_cost, merged_triangles, read_bytes, GpuBlasBuilder};
    use crate::accel::layout::{merge, merge_instances, GpuBvhNode};
    let fail = |e: crate::accel::gpu_build::GpuBuildError| RuntimeError::Gpu(format!("bench build: GPU builder: {e}"));
    let builder = GpuBlasBuilder::new(gpu.device()).map_err(fail)?;
    let mut rows = Vec::new();
    for name in &cfg.scenes {
        let (scene, _) = crate::scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
        let (merged, origin) = merge_instances(&scene);
        let input = merged_triangles(&merged, &origin);
        if input.is_empty() {
            continue;
        }
        let mut cpu_ms = Vec::new();
        let mut cpu_blas = None;
        for _ in 0..3 {
            let t = std::time::Instant::now();
            cpu_blas = Some(Blas::build(&merged, &BuildConfig::default()));
            cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let cpu = merge(&merged, &origin, cpu_blas.unwrap_or_default());
        let (mut times, mut phases, mut walls, mut last) = (Vec::new(), vec![Vec::new(); 4], Vec::new(), None);
        // Warm-up until the build's kernel time settles (clocks, caches).
        WarmUp::for_gpu(gpu, 1).until_settled(gpu, || {
            let b = builder.build(gpu.device(), gpu.queue(), &input).map_err(fail)?;
            Ok::<f64, RuntimeError>(b.gpu_ms.unwrap_or(0.0))
        })?;
        // The kernels timed back to back (a read-back between them would leave the GPU idle
        // for tens of milliseconds and its clocks falling), then the wall time with read-backs.
        for _ in 0..builds.max(1) {
            let b = builder.build(gpu.device(), gpu.queue(), &input).map_err(fail)?;
            times.extend(b.gpu_ms);
            for (all, ms) in phases.iter_mut().zip(b.phase_ms.into_iter().flatten()) {
                all.push(ms);
            }
        }
        for _ in 0..builds.max(1) {
            let t = std::time::Instant::now();
            let b = builder.build(gpu.device(), gpu.queue(), &merged_triangles(&merged, &origin)).map_err(fail)?;
            b.read_back(gpu.device(), gpu.queue()).map_err(fail)?;
            walls.push(t.elapsed().as_secs_f64() * 1e3);
            last = Some(b);
        }
        let Some(b) = last else { continue };
        let nodes = read_bytes(gpu.device(), gpu.queue(), &b.nodes, 0, b.node_count as u64 * 32).map_err(fail)?;
        let nodes: &[GpuBvhNode] = bytemuck::cast_slice(&nodes);
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        let rebuild = cache_rebuild_ms(gpu, &scene, builds.max(1))?;
        rows.push(GpuBuildRow {
            scene: name.clone(),
            triangles: input.len(),
            gpu_ms: (!times.is_empty()).then(|| (median(&mut times), min)),
            phase_ms: (!times.is_empty()).then(|| [0, 1, 2, 3].map(|p| median(&mut phases[p]))),
            rounds: b.rounds,
            depth: b.depth,
            cpu_ms: median(&mut cpu_ms),
            wall_ms: median(&mut walls),
            cache_rebuild_ms: rebuild.map(|r| r.0),
            cache_rebuild_parts: rebuild.map(|r| r.1),
            gpu_sah: layout_sah_cost(nodes),
            cpu_sah: layout_sah_cost(&cpu.blas_nodes),
        });
    }
    Ok(rows)
}

/// Wall milliseconds of `builds` rebuilds of `scene`'s merged layout by an [`AccelCache`] on
/// the GPU builder (median; [`GpuBuildRow::cache_rebuild_ms`]), after one update that makes
/// the pipelines and a warm-up of rebuilds until their time settles; `None` if the cache
/// builds it on the CPU.
///
/// [`AccelCache`]: crate::accel::cache::AccelCache
fn cache_rebuild_ms(gpu: &Gpu, scene: &Scene, builds: u32) -> Result<Option<(f64, [f64; 3])>, RuntimeError> {
    use crate::accel::cache::{AccelCache, AccelSettings, BuildReport, MergedBuilder};
    let mut cache = AccelCache::new(gpu.device(), Backend::Compute, AccelSettings { dedup: true, merge: true }, 1);
    cache.set_merged_builder(MergedBuilder::Gpu);
    let mut scene = scene.clone();
    let mut k = 0u32;
    // One vertex moved up and down by turns: every update is a rebuild of the whole tree.
    let mut rebuild = || -> Result<(f64, BuildReport), RuntimeError> {
        if let Some(i) = scene.meshes().iter().position(|m| !m.vertices.is_empty()) {
            scene.mesh_mut(i).vertices[0].position[1] += if k % 2 == 0 { 1e-4 } else { -1e-4 };
        }
        k += 1;
        let t = std::time::Instant::now();
        let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("bench cache rebuild") });
        let report = cache.update(gpu.device(), gpu.queue(), &mut encoder, &scene)?;
        gpu.queue().submit([encoder.finish()]);
        gpu.device().poll(wgpu::PollType::wait_indefinitely()).map_err(|e| RuntimeError::Gpu(format!("bench build: cache rebuild: {e}")))?;
        Ok((t.elapsed().as_secs_f64() * 1e3, report))
    };
    // The first update makes the pipelines (and may build on the CPU: then nothing to time).
    if !rebuild()?.1.blas_gpu_built {
        return Ok(None);
    }
    WarmUp::for_gpu(gpu, 1).until_settled(gpu, || rebuild().map(|(ms, _)| ms))?;
    let (mut walls, mut parts) = (Vec::new(), [Vec::new(), Vec::new(), Vec::new()]);
    for _ in 0..builds {
        let (ms, report) = rebuild()?;
        walls.push(ms);
        for (all, ms) in parts.iter_mut().zip([report.hash_ms, report.cpu_ms, report.blas_ms]) {
            all.push(ms);
        }
    }
    Ok(Some((median(&mut walls), parts.map(|mut p| median(&mut p)))))
}

/// The rows as a markdown table, with the run's header.
pub fn gpu_build_markdown(info: &RunInfo, rows: &[GpuBuildRow]) -> String {
    let mut s = format!(
        "# bench build: merged layout, GPU builder ({}) against the CPU binned-SAH build\n\n{}\nWith H-PLOC, its one dispatch is the phases' \"rounds\" and the finish is 0; \"rounds\" counts its ranges' merging rounds.\n\n",
        crate::accel::gpu_build::builder_name(),
        info.markdown()
    );
    s.push_str(
        "| scene | triangles | GPU build ms (median) | GPU build ms (min) | sort / rounds / finish / layout ms | rounds | depth | wall ms, build + read-back | cache rebuild wall ms, no read-back | of which hash / update / arrays placed ms | CPU build ms | SAH cost, GPU | SAH cost, CPU | GPU/CPU SAH |\n",
    );
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let phases = r.phase_ms.map(|p| p.map(|ms| format!("{ms:.3}")).join(" / ")).unwrap_or_else(|| "—".into());
        let parts = r.cache_rebuild_parts.map(|p| p.map(|ms| format!("{ms:.2}")).join(" / ")).unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {phases} | {} | {} | {:.1} | {} | {parts} | {:.1} | {:.2} | {:.2} | {:.3} |",
            r.scene,
            r.triangles,
            opt(r.gpu_ms.map(|m| m.0), 3),
            opt(r.gpu_ms.map(|m| m.1), 3),
            r.rounds,
            r.depth,
            r.wall_ms,
            opt(r.cache_rebuild_ms, 2),
            r.cpu_ms,
            r.gpu_sah,
            r.cpu_sah,
            r.gpu_sah / r.cpu_sah
        );
    }
    s
}

/// The rows as CSV, with the run's header.
pub fn gpu_build_csv(info: &RunInfo, rows: &[GpuBuildRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,triangles,gpu_ms_median,gpu_ms_min,sort_ms,rounds_ms,finish_ms,layout_ms,rounds,depth,wall_ms,cache_rebuild_ms,rebuild_hash_ms,rebuild_update_ms,rebuild_placed_ms,cpu_ms,gpu_sah,cpu_sah\n");
    for r in rows {
        let phase = |p: usize| opt(r.phase_ms.map(|m| m[p]), 4);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{:.3},{},{},{},{},{:.3},{:.4},{:.4}",
            r.scene,
            r.triangles,
            opt(r.gpu_ms.map(|m| m.0), 4),
            opt(r.gpu_ms.map(|m| m.1), 4),
            phase(0),
            phase(1),
            phase(2),
            phase(3),
            r.rounds,
            r.depth,
            r.wall_ms,
            opt(r.cache_rebuild_ms, 3),
            opt(r.cache_rebuild_parts.map(|p| p[0]), 3),
            opt(r.cache_rebuild_parts.map(|p| p[1]), 3),
            opt(r.cache_rebuild_parts.map(|p| p[2]), 3),
            r.cpu_ms,
            r.gpu_sah,
            r.cpu_sah
        );
    }
    s
}

/// The CPU binned-SAH build of each scene's instances merged into one BLAS (what
/// `Accel(merge: true)` rebuilds on a change): `Blas::build` from the merged mesh, triangle
/// classification included.
#[derive(Debug, Clone)]
pub struct CpuBuildRow {
    /// The scene.
    pub scene: String,
    /// Triangles of the merged mesh.
    pub triangles: usize,
    /// rayon's worker threads.
    pub threads: usize,
    /// The first build in the process (fresh memory: page faults included).
    pub first_ms: f64,
    /// Median and minimum of the builds after it.
    pub median_ms: f64,
    /// Minimum milliseconds of the builds after the first.
    pub min_ms: f64,
    /// Builds timed.
    pub builds: u32,
    /// SAH cost of the tree.
    pub sah: f64,
    /// Depth of the deepest leaf.
    pub depth: usize,
}

/// `builds` CPU builds of every scene of `cfg`'s merged mesh.
pub fn run_cpu_builds(cfg: &BuildBenchConfig, builds: u32) -> Result<Vec<CpuBuildRow>, RuntimeError> {
    use crate::accel::bvh::{Blas, BuildConfig};
    use crate::accel::layout::merge_instances;
    let mut rows = Vec::new();
    for name in &cfg.scenes {
        let (scene, _) = crate::scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
        let (merged, _) = merge_instances(&scene);
        let mut times = Vec::new();
        let mut last = Blas::default();
        for _ in 0..=builds.max(1) {
            let t = std::time::Instant::now();
            last = Blas::build(&merged, &BuildConfig::default());
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let first_ms = times.remove(0);
        let min_ms = times.iter().copied().fold(f64::INFINITY, f64::min);
        rows.push(CpuBuildRow {
            scene: name.clone(),
            triangles: merged.triangle_count(),
            threads: rayon::current_num_threads(),
            first_ms,
            median_ms: median(&mut times),
            min_ms,
            builds: builds.max(1),
            sah: last.bvh.sah_cost() as f64,
            depth: last.bvh.depth(),
        });
    }
    Ok(rows)
}

/// The rows as a markdown table, with the run's header.
pub fn cpu_build_markdown(info: &RunInfo, rows: &[CpuBuildRow]) -> String {
    let mut s = format!("# bench build: CPU binned-SAH build of the merged scene (one BLAS)\n\n{}\n", info.markdown());
    s.push_str("| scene | triangles | threads | first build ms | median ms | min ms | builds | SAH cost | depth |\n");
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {:.1} | {:.1} | {} | {:.3} | {} |",
            r.scene, r.triangles, r.threads, r.first_ms, r.median_ms, r.min_ms, r.builds, r.sah, r.depth
        );
    }
    s
}

/// The rows as CSV, with the run's header.
pub fn cpu_build_csv(info: &RunInfo, rows: &[CpuBuildRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,triangles,threads,first_ms,median_ms,min_ms,builds,sah,depth\n");
    for r in rows {
        let _ =
            writeln!(s, "{},{},{},{:.3},{:.3},{:.3},{},{:.4},{}", r.scene, r.triangles, r.threads, r.first_ms, r.median_ms, r.min_ms, r.builds, r.sah, r.depth);
    }
    s
}
