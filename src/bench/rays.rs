//! `raygraph bench rays`: the paper's Table 3. For every back-end the adapter has and every
//! scene: the scene workload (`graph/bench_rays.ron`: primary rays, one shadow ray and N AO
//! rays of a stated length per pixel) from the scene's default camera; then, on the last scene,
//! with M jittered primary rays per pixel and no shading (`graph/bench_primary.ron`): Miss
//! (outside) into the empty sky above the scene's box, Miss (inside) from the scene's
//! `miss_inside` camera preset (rays that cross the scene and hit nothing; the atrium's looks up
//! through its open roof), and Stress from its `stress` preset or, for a scene without one, its
//! camera narrowed until it shows no sky. A Miss row that hits or a Stress row under 99% hits
//! is an error, not a row. FPS from the median GPU time of all passes per frame, the wall-clock
//! time beside it; rays per pixel (in all and per trace pass) and GigaRays/s from the rays
//! counted on the GPU; RFPS is the raster graph's frame rate on the same view.

use super::RunInfo;
use crate::backend::Backend;
use crate::graph::compile::{compile_with, CompileOptions};
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::profiler::median;
use crate::runtime::{Executor, Gpu};
use crate::scene::{Camera, LoadOptions, Scene};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Settings of `raygraph bench rays` (Table 3).
#[derive(Debug, Clone)]
pub struct RaysConfig {
    /// Built-in scene names or glTF paths.
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Timed frames per measurement (after the warm-up).
    pub frames: u32,
    /// Untimed frames before each measurement at least (the warm-up goes on until the frame
    /// time settles: [`crate::runtime::warm_up`]).
    pub warmup: u32,
    /// AO rays per pixel.
    pub ao_rays: i64,
    /// AO ray length as a fraction of the scene's bounding radius (`rt_ao`'s `range_scale`).
    pub ao_length: f64,
    /// Primary rays per pixel of the Miss and Stress tests.
    pub primary_rays: i64,
    /// The back-ends measured.
    pub backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
    /// Fractions of the frame each scene is also measured at: its camera moved along its view
    /// axis until its surfaces cover that fraction of the pixels (`coverage_view`).
    pub coverages: Vec<f64>,
    /// Layer substitutions of the scene workload, `layer -> variant` (`CompileOptions::layers`):
    /// `rt_ao -> rt_ao_compacted` measures that AO schedule.
    pub layers: BTreeMap<String, String>,
}

impl RaysConfig {
    /// The paper's settings: box, organic, atrium at 2560x1440, 64 AO rays, 64 primary rays.
    pub fn paper(root: &Path, backends: Vec<Backend>) -> Self {
        Self {
            scenes: vec!["box".into(), "organic".into(), "atrium".into()],
            size: (2560, 1440),
            frames: 10,
            warmup: 2,
            ao_rays: 64,
            ao_length: 0.05,
            primary_rays: 64,
            backends,
            root: root.to_path_buf(),
            coverages: Vec::new(),
            layers: BTreeMap::new(),
        }
    }

    /// A size that runs in seconds on a CPU (CI).
    pub fn quick(root: &Path, backends: Vec<Backend>) -> Self {
        Self {
            scenes: vec!["box".into(), "organic".into(), "atrium".into()],
            size: (48, 27),
            frames: 2,
            warmup: 1,
            ao_rays: 4,
            ao_length: 0.05,
            primary_rays: 4,
            backends,
            root: root.to_path_buf(),
            coverages: Vec::new(),
            layers: BTreeMap::new(),
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone)]
pub struct RaysRow {
    /// The scene's name for a scene workload row; `Miss (outside)`, `Miss (inside)` or
    /// `Stress`.
    pub test: String,
    /// The scene it ran on.
    pub scene: String,
    /// The camera: the scene's own, a named preset, or how it was derived.
    pub camera: String,
    /// The back-end.
    pub backend: Backend,
    /// Frames per second.
    pub fps: f64,
    /// GPU milliseconds per frame (the sum of the passes' timestamps).
    pub gpu_ms: f64,
    /// Wall-clock milliseconds per frame (recording, submission and the wait for the GPU).
    pub wall_ms: f64,
    /// Rays traced per frame.
    pub rays_per_frame: u64,
    /// Rays per pixel.
    pub rays_per_pixel: f64,
    /// GigaRays per second.
    pub grays_per_s: f64,
    /// Fraction of rays that hit.
    pub hit_fraction: f64,
    /// The raster graph's frame rate on the same view (scene rows).
    pub rfps: Option<f64>,
    /// Median GPU milliseconds of each pass of the measured graph, in schedule order.
    pub passes: Vec<(String, f64)>,
    /// Rays per pixel of each trace pass (by ray type: primary, shadow, AO), schedule order.
    pub rays_by_pass: Vec<(String, f64)>,
    /// The frame's GPU ms on every executor the row was measured on, in order (the row reports
    /// one of them: [`super::repeat::Repeats::chosen`]).
    pub executors_ms: Vec<f64>,
}

/// What one measurement gives: the frame's median GPU ms, median rays and hits per frame, and
/// each pass's median GPU ms.
struct Measured {
    gpu_ms: f64,
    wall_ms: f64,
    rays: u64,
    hits: u64,
    passes: Vec<(String, f64)>,
    /// Rays per pixel of each trace pass.
    rays_by_pass: Vec<(String, f64)>,
    /// The GPU ms of every executor the row was measured on, in order.
    executors_ms: Vec<f64>,
}

/// What a measurement renders: the graph, compiled with `options`, over `scene` from `camera`.
pub(crate) struct Workload<'a> {
    pub graph: &'a Path,
    pub project: &'a Project,
    pub options: &'a CompileOptions,
    pub scene: &'a Scene,
    pub camera: &'a Camera,
}

/// [`measure_once`] on executors built one after the other until two agree
/// ([`super::repeat::Repeats`]): the chosen measurement, with every executor's GPU ms.
fn measure(gpu: &Gpu, work: &Workload, cfg: &RaysConfig) -> Result<Measured, crate::error::RuntimeError> {
    let repeats = super::repeat::Repeats::for_gpu(gpu);
    let (m, executors_ms) = repeats.run(|| {
        measure_once(gpu, work, cfg).map(|m| {
            let ms = m.gpu_ms;
            (m, ms)
        })
    })?;
    Ok(Measured { executors_ms, ..m })
}

/// Median GPU milliseconds of a frame (all passes) and of each pass, median rays per frame,
/// on one executor.
fn measure_once(gpu: &Gpu, work: &Workload, cfg: &RaysConfig) -> Result<Measured, crate::error::RuntimeError> {
    let plan = compile_with(work.graph, work.project, cfg.size, work.options)?;
    let mut exec = Executor::new(gpu, plan, work.scene)?;
    let camera = *work.camera;
    let frames = super::timed_frames(gpu, &mut exec, work.scene, cfg.warmup, cfg.frames, |_| camera)?;
    let mut gpu_ms: Vec<f64> = frames.iter().map(super::frame_gpu_ms).collect();
    let mut wall_ms: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
    let mut rays: Vec<f64> = frames.iter().map(|f| f.rays.map(|r| r.traced()).unwrap_or(0) as f64).collect();
    let mut hits: Vec<f64> = frames.iter().map(|f| f.rays.map(|r| r.hits).unwrap_or(0) as f64).collect();
    // Per pass: the same medians `render --report` writes.
    let names: Vec<(String, &'static str)> = exec.plan().passes.iter().map(|p| (p.name.clone(), p.kind.name())).collect();
    let report = crate::runtime::report::Report::new(&names, cfg.size.0 as u64 * cfg.size.1 as u64, &frames);
    let passes = report.passes.iter().map(|p| (p.name.clone(), p.gpu_ms.map_or(f64::NAN, |g| g.median))).collect();
    let rays_by_pass = report.passes.iter().filter_map(|p| Some((p.name.clone(), p.rays_per_pixel?))).collect();
    Ok(Measured {
        gpu_ms: median(&mut gpu_ms),
        wall_ms: median(&mut wall_ms),
        rays: median(&mut rays) as u64,
        hits: median(&mut hits) as u64,
        passes,
        rays_by_pass,
        executors_ms: Vec::new(),
    })
}

/// Where and how a row was measured: the scene and the camera's description.
struct View<'a> {
    scene: &'a Scene,
    camera: Camera,
    described: String,
}

fn row(test: &str, view: &View, backend: Backend, cfg: &RaysConfig, m: Measured, rfps: Option<f64>) -> RaysRow {
    let Measured { gpu_ms: ms, wall_ms, rays, hits, passes, rays_by_pass, executors_ms } = m;
    let pixels = cfg.size.0 as f64 * cfg.size.1 as f64;
    RaysRow {
        test: test.into(),
        scene: view.scene.name().to_string(),
        camera: view.described.clone(),
        rays_by_pass,
        backend,
        fps: 1000.0 / ms,
        gpu_ms: ms,
        wall_ms,
        rays_per_frame: rays,
        rays_per_pixel: rays as f64 / pixels,
        grays_per_s: super::grays_per_s(rays as f64, ms),
        hit_fraction: if rays > 0 { hits as f64 / rays as f64 } else { 0.0 },
        rfps,
        passes,
        executors_ms,
    }
}

/// The compile options of the scene workload (`graph/bench_rays.ron`) on `backend`: `cfg`'s AO
/// rays and length, and its layer substitutions.
pub(crate) fn workload_options(gpu: &Gpu, backend: Backend, cfg: &RaysConfig) -> CompileOptions {
    let mut options = gpu.compile_options_for(backend);
    options.layers.extend(cfg.layers.clone());
    options.params.insert(("ao".into(), "rays".into()), ParamValue::Int(cfg.ao_rays));
    options.params.insert(("ao".into(), "range_scale".into()), ParamValue::Float(cfg.ao_length));
    options
}

/// The Stress camera of `scene` ([`stress_view`]), for other benches.
pub(crate) fn stress_camera(gpu: &Gpu, primary: &Path, project: &Project, scene: &Scene) -> Result<Camera, crate::error::RuntimeError> {
    stress_view(gpu, primary, project, scene).map(|v| v.camera)
}

/// GigaRays/s of a workload (median rays over median GPU time), for other
/// benches.
pub(crate) fn measure_rays(gpu: &Gpu, work: &Workload, cfg: &RaysConfig) -> Result<f64, crate::error::RuntimeError> {
    let m = measure(gpu, work, cfg)?;
    Ok(super::grays_per_s(m.rays as f64, m.gpu_ms))
}

/// The camera preset a scene names its Stress view with.
pub const STRESS_PRESET: &str = "stress";
/// The camera preset a scene names its Miss (inside) view with.
pub const MISS_INSIDE_PRESET: &str = "miss_inside";
/// A Stress row must hit with at least this fraction of its rays.
pub(crate) const STRESS_MIN_HITS: f64 = 0.99;
/// The probe that derives a Stress view: frame size and rays per pixel, the hit fraction it
/// asks for (above [`STRESS_MIN_HITS`], as the probe sees fewer rays), and how many times the
/// field of view is halved at most.
const PROBE_SIZE: (u32, u32) = (64, 36);
const PROBE_RAYS: i64 = 16;
const PROBE_MIN_HITS: f64 = 0.999;
const STRESS_NARROWINGS: i32 = 6;

/// The probe of [`coverage_view`]: frame size (1 primary ray per pixel), the tolerance on the
/// covered fraction (relative), and the most moves it makes.
const COVERAGE_PROBE_SIZE: (u32, u32) = (256, 144);
const COVERAGE_TOLERANCE: f64 = 0.15;
const COVERAGE_MOVES: u32 = 8;

/// `scene`'s camera moved along its view axis (towards its target or away from it) until its
/// surfaces cover `coverage` of the pixels, within 15%: a probe (256x144, 1 primary ray per
/// pixel, `primary`'s graph) measures the covered fraction, and the distance to the target is
/// scaled by the square root of the ratio (a surface's pixels go as the inverse square of the
/// distance) until it is near enough. An error when it does not get there.
fn coverage_view<'a>(gpu: &Gpu, primary: &Path, project: &Project, scene: &'a Scene, coverage: f64) -> Result<View<'a>, crate::error::RuntimeError> {
    let mut options = gpu.compile_options();
    options.params.insert(("primary".into(), "rays".into()), ParamValue::Int(1));
    let mut exec = Executor::new(gpu, compile_with(primary, project, COVERAGE_PROBE_SIZE, &options)?, scene)?;
    let base = Camera { orthographic: None, ..*scene.camera() };
    let (mut scale, mut covered) = (1.0f64, 0.0);
    for _ in 0..COVERAGE_MOVES {
        let camera = base.moved_back(scale as f32);
        let frame = exec.render(gpu, &camera, scene)?;
        covered = frame.rays.map_or(0.0, |r| r.hits as f64 / r.traced().max(1) as f64);
        if (covered - coverage).abs() <= COVERAGE_TOLERANCE * coverage {
            let described = format!("the scene's camera {scale:.2}x as far from its target: {:.1}% of the pixels covered", covered * 100.0);
            return Ok(View { scene, camera, described });
        }
        scale *= (covered.max(1e-4) / coverage).sqrt().clamp(0.25, 4.0);
    }
    Err(crate::error::RuntimeError::NotTheTest(format!(
        "no view of `{}` covering {:.1}% of the frame: moving its camera along its view axis ended at {:.1}%",
        scene.name(),
        coverage * 100.0,
        covered * 100.0
    )))
}

/// A camera of `scene` that sees it cover `coverage` of the frame (its own camera moved along its
/// view axis; [`coverage_view`]), for other benches.
pub(crate) fn coverage_camera(gpu: &Gpu, root: &Path, scene: &Scene, coverage: f64) -> Result<Camera, crate::error::RuntimeError> {
    let project = Project { layers_dir: root.join("layers"), shaders_dir: root.join("shaders") };
    Ok(coverage_view(gpu, &root.join("graph/bench_primary.ron"), &project, scene, coverage)?.camera)
}

/// The camera of the Miss (outside) test: above the scene's box, looking straight up.
pub fn miss_outside_camera(scene: &Scene) -> Camera {
    let b = scene.bounds();
    let (c, r) = (b.center(), 0.5 * b.diagonal().max(1e-3));
    Camera { up: glam::Vec3::Z, ..Camera::look(glam::Vec3::new(c.x, b.max.y + r, c.z), glam::Vec3::new(c.x, b.max.y + 3.0 * r, c.z), 60.0, r * 1e-3, r * 10.0) }
}

/// The Stress view of `scene`: its `stress` camera preset, or else its own camera with the field
/// of view halved until a probe (64x36, 16 rays per pixel, `primary`'s graph) hits with 99.9% of
/// its rays. An error when no narrowing gets there (the scene shows sky behind everything its
/// camera looks at).
fn stress_view<'a>(gpu: &Gpu, primary: &Path, project: &Project, scene: &'a Scene) -> Result<View<'a>, crate::error::RuntimeError> {
    if let Ok(camera) = scene.preset(STRESS_PRESET) {
        return Ok(View { scene, camera, described: format!("preset `{STRESS_PRESET}`") });
    }
    let mut options = gpu.compile_options();
    options.params.insert(("primary".into(), "rays".into()), ParamValue::Int(PROBE_RAYS));
    let mut exec = Executor::new(gpu, compile_with(primary, project, PROBE_SIZE, &options)?, scene)?;
    let mut best = 0.0f64;
    let mut camera = *scene.camera();
    for k in 0..=STRESS_NARROWINGS {
        // The primary-ray kernel (`rt/primary_n.wgsl`) casts perspective rays only (each ray's
        // origin set up per ray cost its Miss rows 6-10% on the H200): a file whose first
        // camera is orthographic is narrowed as a perspective camera at its place.
        camera = Camera { fov_y: scene.camera().fov_y / 2f32.powi(k), orthographic: None, ..*scene.camera() };
        let frame = exec.render(gpu, &camera, scene)?;
        let hits = frame.rays.map_or(0.0, |r| r.hits as f64 / r.traced().max(1) as f64);
        if hits >= PROBE_MIN_HITS {
            let described = format!("derived: the scene's camera narrowed to {:.1} deg", camera.fov_y.to_degrees());
            log::info!("Stress on `{}`: no `{STRESS_PRESET}` camera preset, so {described}", scene.name());
            return Ok(View { scene, camera, described });
        }
        best = best.max(hits);
    }
    Err(crate::error::RuntimeError::NotTheTest(format!(
        "no Stress view on `{}`: it has no `{STRESS_PRESET}` camera preset, and its camera narrowed down to {:.2} deg hits with {:.1}% of its rays at best ({}% needed: a Stress view shows no sky)",
        scene.name(),
        camera.fov_y.to_degrees(),
        100.0 * best,
        100.0 * PROBE_MIN_HITS
    )))
}

/// What a Miss or Stress row must measure to be one.
#[derive(Clone, Copy)]
enum Expect {
    /// Every ray misses.
    NoHits,
    /// At least [`STRESS_MIN_HITS`] of the rays hit.
    Hits,
}

impl Expect {
    fn check(self, row: &RaysRow) -> Result<(), crate::error::RuntimeError> {
        let what = match self {
            Expect::NoHits if row.hit_fraction > 0.0 => "a Miss view must miss with every ray",
            Expect::Hits if row.hit_fraction < STRESS_MIN_HITS => "a Stress view must hit with 99% of its rays: it shows no sky",
            _ => return Ok(()),
        };
        Err(crate::error::RuntimeError::NotTheTest(format!(
            "{} on `{}` ({}), {}: {:.4} of the rays hit; {what}",
            row.test, row.scene, row.camera, row.backend, row.hit_fraction
        )))
    }
}

/// The Miss (outside), Miss (inside) (where the scene has a `miss_inside` preset) and Stress
/// rows on `scene`, for every back-end; `step` sees the rows after each one.
fn ray_tests(
    gpu: &Gpu,
    cfg: &RaysConfig,
    project: &Project,
    primary: &Path,
    scene: &Scene,
    rows: &mut Vec<RaysRow>,
    step: &mut dyn FnMut(&[RaysRow], String),
) -> Result<(), crate::error::RuntimeError> {
    let mut views =
        vec![("Miss (outside)", View { scene, camera: miss_outside_camera(scene), described: "above the scene's box looking up".into() }, Expect::NoHits)];
    match scene.preset(MISS_INSIDE_PRESET) {
        Ok(camera) => views.push(("Miss (inside)", View { scene, camera, described: format!("preset `{MISS_INSIDE_PRESET}`") }, Expect::NoHits)),
        Err(_) => log::info!("no Miss (inside) row: scene `{}` has no `{MISS_INSIDE_PRESET}` camera preset", scene.name()),
    }
    views.push(("Stress", stress_view(gpu, primary, project, scene)?, Expect::Hits));
    for &backend in &cfg.backends {
        let mut options = gpu.compile_options_for(backend);
        options.params.insert(("primary".into(), "rays".into()), ParamValue::Int(cfg.primary_rays));
        for (test, view, expect) in &views {
            let work = Workload { graph: primary, project, options: &options, scene, camera: &view.camera };
            let m = measure(gpu, &work, cfg)?;
            let r = row(test, view, backend, cfg, m, None);
            expect.check(&r)?;
            rows.push(r);
            step(rows, format!("{test}: {backend}"));
        }
    }
    Ok(())
}

/// Runs the table; `progress` is called after every measurement with (done, total, label).
/// `on_rows` sees the rows finished so far after each one (to keep the results folder current).
pub fn run(
    gpu: &Gpu,
    cfg: &RaysConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[RaysRow]),
) -> Result<Vec<RaysRow>, crate::error::RuntimeError> {
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let workload = cfg.root.join("graph/bench_rays.ron");
    let primary = cfg.root.join("graph/bench_primary.ron");
    let raster = cfg.root.join("graph/raster.ron");
    let total = cfg.scenes.len() * (cfg.backends.len() * (1 + cfg.coverages.len()) + 1) + 3 * cfg.backends.len();
    let mut done = 0;
    let mut rows = Vec::new();
    let mut step = |rows: &[RaysRow], label: String| {
        on_rows(rows);
        done += 1;
        progress(done, total, &label);
    };
    let mut last_scene = None;
    for name in &cfg.scenes {
        let (scene, _) = crate::scene::open(name, &LoadOptions { textures: true, ..Default::default() })?;
        let view = View { scene: &scene, camera: *scene.camera(), described: "the scene's camera".into() };
        let raster_options = gpu.compile_options();
        let work = Workload { graph: &raster, project: &project, options: &raster_options, scene: &scene, camera: scene.camera() };
        let raster_ms = measure(gpu, &work, cfg)?.gpu_ms;
        step(&rows, format!("{name}: raster"));
        for &backend in &cfg.backends {
            let options = workload_options(gpu, backend, cfg);
            let m = measure(gpu, &Workload { graph: &workload, options: &options, ..work }, cfg)?;
            rows.push(row(name, &view, backend, cfg, m, Some(1000.0 / raster_ms)));
            step(&rows, format!("{name}: {backend}"));
        }
        for &coverage in &cfg.coverages {
            let view = coverage_view(gpu, &primary, &project, &scene, coverage)?;
            for &backend in &cfg.backends {
                let options = workload_options(gpu, backend, cfg);
                let m = measure(gpu, &Workload { graph: &workload, options: &options, camera: &view.camera, ..work }, cfg)?;
                rows.push(row(&format!("{name} at {:.0}%", coverage * 100.0), &view, backend, cfg, m, None));
                step(&rows, format!("{name} at {:.0}%: {backend}", coverage * 100.0));
            }
        }
        last_scene = Some(scene);
    }
    if let Some(scene) = last_scene {
        ray_tests(gpu, cfg, &project, &primary, &scene, &mut rows, &mut step)?;
    }
    Ok(rows)
}

/// Every row's passes as CSV: test, back-end, pass, median GPU ms (with the run header as `#`
/// comments), to see where a row's time goes.
pub fn passes_csv(info: &RunInfo, rows: &[RaysRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("test,backend,pass,gpu_ms\n");
    for r in rows {
        for (pass, ms) in &r.passes {
            let _ = writeln!(s, "{},{},{},{:.4}", r.test, r.backend, pass, ms);
        }
    }
    s
}

/// What the workload and the columns are, for the results' headers (with the layers the
/// scene workload substituted, if any).
pub fn definitions(cfg: &RaysConfig) -> String {
    let substituted: Vec<String> = cfg.layers.iter().map(|(layer, variant)| format!("`{layer}` compiled from `layers/{variant}.ron`")).collect();
    let substituted = if substituted.is_empty() { String::new() } else { format!(" Scene workload layers: {}.", substituted.join(", ")) };
    let text = format!(
        "Scene workload (`graph/bench_rays.ron`): per pixel 1 primary ray, and where it hits 1 shadow ray and {} AO rays of length {} x the scene's bounding radius. Miss (outside): rays from above the scene's box pointing away from it; Miss (inside): from the scene's `miss_inside` camera preset, rays that cross the scene and hit nothing; Stress: the scene's `stress` camera preset, or its camera narrowed until it shows no sky; all three (`graph/bench_primary.ron`) with {} jittered primary rays per pixel, on the last scene listed. FPS = 1000 / GPU ms (the sum of the passes' timestamps); wall ms = the frame's wall-clock time (recording, submission, the wait); RFPS = the Rasterization graph's 1000 / GPU ms on the scene's view. Timed frames follow a warm-up that lasts until the frame time has settled. On a hardware GPU each row is measured on executors built one after the other until two agree within 3% (at most four), and reports the faster of the two, or the median of the four when no two agree (GPU ms per executor: every one in order, marked where none agree).",
        cfg.ao_rays, cfg.ao_length, cfg.primary_rays
    );
    text + &substituted
}

/// The table as CSV (with the run header and [`definitions`] as `#` comments).
pub fn csv(info: &RunInfo, cfg: &RaysConfig, rows: &[RaysRow]) -> String {
    let mut s = info.csv_comment();
    let _ = writeln!(s, "# {}", definitions(cfg));
    s.push_str(
        "test,scene,camera,backend,fps,gpu_ms,wall_ms,rays_per_frame,rays_per_pixel,grays_per_s,hit_fraction,rfps,rays_per_pixel_by_pass,executors_gpu_ms\n",
    );
    let field = |t: &str| t.replace(',', ";");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{:.4},{:.4},{:.4},{},{:.3},{:.5},{:.4},{},{},{}",
            field(&r.test),
            field(&r.scene),
            field(&r.camera),
            r.backend,
            r.fps,
            r.gpu_ms,
            r.wall_ms,
            r.rays_per_frame,
            r.rays_per_pixel,
            r.grays_per_s,
            r.hit_fraction,
            r.rfps.map(|f| format!("{f:.3}")).unwrap_or_default(),
            by_pass(r, ";"),
            executors(r, ";")
        );
    }
    s
}

/// The GPU ms of every executor a row was measured on, joined by `sep`.
fn executors(r: &RaysRow, sep: &str) -> String {
    r.executors_ms.iter().map(|ms| format!("{ms:.3}")).collect::<Vec<_>>().join(sep)
}

/// The markdown's executor cell: every executor's GPU ms, and where several were measured and
/// no two agreed, a note that the row is their median, not a confirmed figure.
fn executors_cell(r: &RaysRow) -> String {
    let repeats = super::repeat::Repeats::GPU;
    let unconfirmed = r.executors_ms.len() > 1 && !repeats.agreed(&r.executors_ms);
    let note = if unconfirmed { format!(" (none within {:.0}%: the median)", repeats.tolerance * 100.0) } else { String::new() };
    executors(r, ", ") + &note
}

/// A row's rays per pixel by trace pass, `pass=value` joined by `sep`.
fn by_pass(r: &RaysRow, sep: &str) -> String {
    r.rays_by_pass.iter().map(|(pass, v)| format!("{pass}={v:.2}")).collect::<Vec<_>>().join(sep)
}

/// The table as markdown, with the paper's RTX 2080 Ti figures beside it.
pub fn markdown(info: &RunInfo, cfg: &RaysConfig, rows: &[RaysRow]) -> String {
    let paper = |test: &str| match test {
        "box" => "12.82",
        "organic" => "5.50",
        "atrium" => "7.09",
        "Miss (outside)" => "12.52",
        "Stress" => "6.25",
        _ => "",
    };
    let mut s = format!("# bench rays\n\n{}\n{}\n\n", info.markdown(), definitions(cfg));
    s.push_str("| test | back-end | FPS | GPU ms | wall ms | rays/pixel | GigaRays/s | hit fraction | RFPS | paper GR/s (RTX 2080 Ti) | scene | camera | rays/pixel by pass | GPU ms per executor |\n");
    s.push_str("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- | --- | --- |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.3} | {:.3} | {:.2} | {:.3} | {:.3} | {} | {} | {} | {} | {} | {} |",
            r.test,
            r.backend,
            r.fps,
            r.gpu_ms,
            r.wall_ms,
            r.rays_per_pixel,
            r.grays_per_s,
            r.hit_fraction,
            r.rfps.map(|f| format!("{f:.1}")).unwrap_or_else(|| "—".into()),
            paper(&r.test),
            r.scene,
            r.camera,
            by_pass(r, ", "),
            executors_cell(r)
        );
    }
    s
}

/// `rays.png`: GigaRays/s per test and back-end beside the paper's RTX 2080 Ti (log scale).
pub fn plots(dir: &Path, rows: &[RaysRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut tests: Vec<String> = Vec::new();
    for r in rows {
        if !tests.contains(&r.test) {
            tests.push(r.test.clone());
        }
    }
    let mut backends: Vec<Backend> = Vec::new();
    for r in rows {
        if !backends.contains(&r.backend) {
            backends.push(r.backend);
        }
    }
    let paper = [("box", 12.82), ("organic", 5.50), ("atrium", 7.09), ("Miss (outside)", 12.52), ("Stress", 6.25)];
    let mut series: Vec<Series> = backends
        .iter()
        .map(|b| Series {
            name: format!("raygraph {b}"),
            points: rows.iter().filter(|r| r.backend == *b).map(|r| (tests.iter().position(|t| *t == r.test).unwrap_or(0) as f64, r.grays_per_s)).collect(),
        })
        .collect();
    series.push(Series {
        name: "paper, RTX 2080 Ti".into(),
        points: tests.iter().enumerate().filter_map(|(i, t)| paper.iter().find(|(n, _)| n == t).map(|(_, g)| (i as f64, *g))).collect(),
    });
    let path = dir.join("rays.png");
    LinePlot { title: "GigaRays/s (Table 3)", x_label: "test", y_label: "GigaRays/s", log_x: false, log_y: true, x_labels: Some(&tests) }
        .write(&path, &series)?;
    Ok(vec![path])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hits(test: &str, hit_fraction: f64) -> RaysRow {
        RaysRow {
            test: test.into(),
            scene: "s".into(),
            camera: "c".into(),
            backend: Backend::Compute,
            fps: 1.0,
            gpu_ms: 1.0,
            wall_ms: 1.0,
            rays_per_frame: 100,
            rays_per_pixel: 1.0,
            grays_per_s: 1.0,
            hit_fraction,
            rfps: None,
            passes: Vec::new(),
            rays_by_pass: Vec::new(),
            executors_ms: vec![1.0],
        }
    }

    #[test]
    fn a_miss_row_that_hits_and_a_stress_row_with_sky_are_errors() {
        assert!(Expect::NoHits.check(&hits("Miss (inside)", 0.0)).is_ok());
        let e = Expect::NoHits.check(&hits("Miss (inside)", 0.0001)).unwrap_err().to_string();
        assert!(e.contains("Miss (inside) on `s` (c)") && e.contains("must miss with every ray"), "{e}");
        assert!(Expect::Hits.check(&hits("Stress", 0.99)).is_ok());
        let e = Expect::Hits.check(&hits("Stress", 0.95)).unwrap_err().to_string();
        assert!(e.contains("0.9500 of the rays hit") && e.contains("shows no sky"), "{e}");
    }
}
