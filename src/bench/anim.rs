//! `raygraph bench anim`: animated scenes, posed for the GPU (node matrices on the CPU,
//! skinning and morphing in the executor's deformation pass), played frame by frame through the paper's scene
//! workload (`graph/bench_rays.ron`: primary rays, one shadow ray and 64 AO rays per pixel) on
//! one back-end, under each of the cache's policies ([`RefitPolicy`]: refit until the SAH
//! cost has grown past the threshold, always refit, always rebuild). Per frame: the CPU time of
//! the pose, the `Accel` pass's GPU and CPU milliseconds (the update of the acceleration
//! structure: refit, rebuild, deformation gather and SAH probe), what it did, the measured SAH
//! growth, the trace passes' GPU milliseconds, rays and GigaRays/s (rays over the trace
//! passes' GPU time, the paper's definition).

use super::RunInfo;
use crate::accel::deform::RefitPolicy;
use crate::backend::Backend;
use crate::graph::compile::compile_with;
use crate::graph::desc::PassKind;
use crate::graph::Project;
use crate::runtime::{Executor, Gpu};
use crate::scene::LoadOptions;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Settings of `raygraph bench anim`.
#[derive(Debug, Clone)]
pub struct AnimConfig {
    /// Animated scenes: built-in names or glTF paths.
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Frames played per scene and policy.
    pub frames: u32,
    /// Frames per second of the clip's clock.
    pub fps: f32,
    /// The back-end.
    pub backend: Backend,
    /// The policies compared.
    pub policies: Vec<RefitPolicy>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

/// One frame of one scene under one policy.
#[derive(Debug, Clone)]
pub struct AnimRow {
    /// The scene.
    pub(crate) scene: String,
    /// The policy's name.
    pub(crate) policy: String,
    /// Frame index.
    pub(crate) frame: u32,
    /// CPU milliseconds of the pose (node matrices; the meshes deform on the GPU).
    pub(crate) pose_ms: f64,
    /// GPU milliseconds of the `Accel` pass.
    pub(crate) accel_gpu_ms: f64,
    /// CPU milliseconds of the `Accel` pass (hashing, CPU builds, uploads, recording).
    pub(crate) accel_cpu_ms: f64,
    /// `refit`, `rebuild`, `rebuild (quality)` or `none`.
    pub(crate) work: &'static str,
    /// SAH cost over the builder's, as measured before this frame's update.
    pub(crate) sah_growth: Option<f64>,
    /// GPU milliseconds of the trace passes.
    pub(crate) trace_ms: f64,
    /// Rays traced.
    pub(crate) rays: u64,
    /// Rays over the trace passes' GPU time, in billions per second.
    pub(crate) grays_per_s: f64,
}

/// Plays every scene under every policy; `on_rows` sees the rows so far after each run.
pub fn run(
    gpu: &Gpu,
    cfg: &AnimConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[AnimRow]),
) -> Result<Vec<AnimRow>, crate::error::RuntimeError> {
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let options = gpu.compile_options_for(cfg.backend);
    let runs: Vec<(&String, RefitPolicy)> = cfg.scenes.iter().flat_map(|s| cfg.policies.iter().map(move |p| (s, *p))).collect();
    let mut rows = Vec::new();
    for (k, (spec, policy)) in runs.iter().enumerate() {
        let (mut scene, _) = crate::scene::open(spec, &LoadOptions::default())?;
        let clip = scene.rig().filter(|r| r.is_animated()).map(|_| 0);
        if clip.is_none() {
            return Err(crate::error::RuntimeError::Gpu(format!("bench anim: scene `{spec}` has no animation")));
        }
        let plan = compile_with(&cfg.root.join("graph/bench_rays.ron"), &project, cfg.size, &options)?;
        let accel_pass = plan.passes().iter().position(|p| p.kind == PassKind::AccelBuild);
        let trace_passes: Vec<usize> = plan.passes().iter().enumerate().filter(|(_, p)| p.kind == PassKind::Trace).map(|(i, _)| i).collect();
        let mut exec = Executor::new(gpu, plan, &scene)?;
        if let Some(cache) = exec.accel_mut() {
            cache.set_refit_policy(*policy);
        }
        let camera = *scene.camera();
        crate::runtime::warm_up::WarmUp::for_gpu(gpu, 1).run(gpu, &mut exec, &scene, &camera)?;
        for frame in 0..cfg.frames {
            let t0 = Instant::now();
            scene.pose_for_gpu(clip, frame as f32 / cfg.fps);
            let pose_ms = t0.elapsed().as_secs_f64() * 1e3;
            let t = exec.render(gpu, &camera, &scene)?;
            let gpu_ms = t.gpu_ms.clone().unwrap_or_default();
            let trace_ms: f64 = trace_passes.iter().filter_map(|&i| gpu_ms.get(i)).sum();
            let rays = t.rays.map(|r| r.traced()).unwrap_or(0);
            let report = t.accel.clone().unwrap_or_default();
            let work = if report.blas_refit || report.blas_refits > 0 {
                "refit"
            } else if report.rebuilt_for_quality {
                "rebuild (quality)"
            } else if report.built_anything() {
                "rebuild"
            } else {
                "none"
            };
            rows.push(AnimRow {
                scene: scene.name().to_string(),
                policy: policy.name(),
                frame,
                pose_ms,
                accel_gpu_ms: accel_pass.and_then(|i| gpu_ms.get(i).copied()).unwrap_or(0.0),
                accel_cpu_ms: accel_pass.and_then(|i| t.cpu_ms.get(i).copied()).unwrap_or(0.0),
                work,
                sah_growth: report.sah_growth,
                trace_ms,
                rays,
                grays_per_s: if trace_ms > 0.0 { rays as f64 / (trace_ms * 1e-3) / 1e9 } else { 0.0 },
            });
        }
        on_rows(&rows);
        progress(k + 1, runs.len(), &format!("{spec}, {}", policy.name()));
    }
    Ok(rows)
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[AnimRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,policy,frame,pose_ms,accel_gpu_ms,accel_cpu_ms,work,sah_growth,trace_ms,rays,grays_per_s\n");
    for r in rows {
        let growth = r.sah_growth.map(|g| format!("{g:.4}")).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{},{},{:.3},{:.4},{:.3},{},{growth},{:.4},{},{:.4}",
            r.scene, r.policy, r.frame, r.pose_ms, r.accel_gpu_ms, r.accel_cpu_ms, r.work, r.trace_ms, r.rays, r.grays_per_s
        );
    }
    s
}

fn median_of(rows: &[&AnimRow], f: impl Fn(&AnimRow) -> f64) -> f64 {
    let mut v: Vec<f64> = rows.iter().map(|r| f(r)).collect();
    crate::runtime::profiler::median(&mut v)
}

/// Per scene and policy: refits and rebuilds, median and largest update milliseconds (GPU and
/// CPU), largest SAH growth, median trace milliseconds and GigaRays/s, and the sum of update
/// and trace milliseconds over the run.
pub fn markdown(info: &RunInfo, rows: &[AnimRow]) -> String {
    let mut s = format!("# bench anim\n\n{}- workload: graph/bench_rays.ron (primary + 1 shadow + 64 AO rays per pixel)\n\n", info.markdown());
    s.push_str("| scene | policy | frames | refits | rebuilds | update GPU ms (median / max) | update CPU ms (median / max) | pose CPU ms | largest SAH growth | trace ms (median) | GigaRays/s (median) | update + trace ms, sum |\n");
    s.push_str("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for r in rows {
        if !keys.contains(&(&r.scene, &r.policy)) {
            keys.push((&r.scene, &r.policy));
        }
    }
    for (scene, policy) in keys {
        let sel: Vec<&AnimRow> = rows.iter().filter(|r| r.scene == scene && r.policy == policy).collect();
        let refits = sel.iter().filter(|r| r.work == "refit").count();
        let rebuilds = sel.iter().filter(|r| r.work.starts_with("rebuild")).count();
        let max = |f: &dyn Fn(&AnimRow) -> f64| sel.iter().map(|r| f(r)).fold(0.0f64, f64::max);
        let growth = sel.iter().filter_map(|r| r.sah_growth).fold(None, |a: Option<f64>, g| Some(a.map_or(g, |a| a.max(g))));
        let total: f64 = sel.iter().map(|r| r.accel_gpu_ms + r.accel_cpu_ms + r.trace_ms).sum();
        let _ = writeln!(
            s,
            "| {scene} | {policy} | {} | {refits} | {rebuilds} | {:.3} / {:.3} | {:.3} / {:.3} | {:.2} | {} | {:.3} | {:.3} | {total:.1} |",
            sel.len(),
            median_of(&sel, |r| r.accel_gpu_ms),
            max(&|r| r.accel_gpu_ms),
            median_of(&sel, |r| r.accel_cpu_ms),
            max(&|r| r.accel_cpu_ms),
            median_of(&sel, |r| r.pose_ms),
            growth.map(|g| format!("x{g:.3}")).unwrap_or_else(|| "—".into()),
            median_of(&sel, |r| r.trace_ms),
            median_of(&sel, |r| r.grays_per_s),
        );
    }
    s.push_str("\nThe update's CPU milliseconds include the hashing of every mesh (change detection) and, for CPU builds, the build; its GPU milliseconds the refit, gather and SAH probe, or the GPU build's kernels.\n");
    s
}

/// `anim_grays.png` (GigaRays/s per frame) and `anim_update.png` (update milliseconds, GPU
/// plus CPU, per frame), one line per scene and policy.
pub fn plots(dir: &Path, rows: &[AnimRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.scene.clone(), r.policy.clone())) {
            keys.push((r.scene.clone(), r.policy.clone()));
        }
    }
    let series = |f: &dyn Fn(&AnimRow) -> f64| -> Vec<Series> {
        keys.iter()
            .map(|(sc, p)| Series {
                name: format!("{sc}, {p}"),
                points: rows.iter().filter(|r| &r.scene == sc && &r.policy == p).map(|r| (r.frame as f64, f(r))).collect(),
            })
            .collect()
    };
    let gr = dir.join("anim_grays.png");
    LinePlot { title: "GigaRays/s while the scene moves", x_label: "frame", y_label: "GigaRays/s", log_x: false, log_y: false, x_labels: None }
        .write(&gr, &series(&|r| r.grays_per_s))?;
    let update = dir.join("anim_update.png");
    LinePlot { title: "Acceleration-structure update per frame", x_label: "frame", y_label: "ms (GPU + CPU)", log_x: false, log_y: true, x_labels: None }
        .write(&update, &series(&|r| (r.accel_gpu_ms + r.accel_cpu_ms).max(1e-3)))?;
    Ok(vec![gr, update])
}
