//! `raygraph bench rays`: the paper's Table 3. For every back-end the adapter has and every
//! scene: the scene workload (`graph/bench_rays.ron`: primary rays, one shadow ray and N AO
//! rays per pixel) from the scene's default camera, then the Miss test (M primary rays per
//! pixel into the empty sky) and the Stress test (M primary rays per pixel that all hit, no
//! shading: `graph/bench_primary.ron`) on the last scene. FPS from the median GPU time of all
//! passes per frame; rays per pixel and GigaRays/s from the rays counted on the GPU; RFPS is
//! the raster graph's frame rate on the same view.

use super::RunInfo;
use crate::backend::Backend;
use crate::graph::compile::{compile_with, CompileOptions};
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::profiler::median;
use crate::runtime::{Executor, Gpu};
use crate::scene::{Camera, LoadOptions, Scene};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Settings of `raygraph bench rays` (Table 3).
#[derive(Debug, Clone)]
pub struct RaysConfig {
    /// Built-in scene names or glTF paths.
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Timed frames per measurement (after `warmup` frames).
    pub frames: u32,
    /// Untimed frames before each measurement.
    pub(crate) warmup: u32,
    /// AO rays per pixel.
    pub ao_rays: i64,
    /// AO ray length as a fraction of the scene's bounding radius (`rt_ao`'s `range_scale`).
    pub ao_length: f64,
    /// Primary rays per pixel of the Miss and Stress tests.
    pub primary_rays: i64,
    /// The back-ends measured.
    pub(crate) backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
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
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone)]
pub struct RaysRow {
    /// Scene name, `Miss` or `Stress`.
    pub test: String,
    /// The back-end.
    pub(crate) backend: Backend,
    /// Frames per second.
    pub(crate) fps: f64,
    /// GPU milliseconds per frame (the sum of the passes' timestamps).
    pub(crate) gpu_ms: f64,
    /// Wall-clock milliseconds per frame (recording, submission and the wait for the GPU).
    pub(crate) wall_ms: f64,
    /// Rays traced per frame.
    pub(crate) rays_per_frame: u64,
    /// Rays per pixel.
    pub(crate) rays_per_pixel: f64,
    /// GigaRays per second.
    pub(crate) grays_per_s: f64,
    /// Fraction of rays that hit.
    pub hit_fraction: f64,
    /// The raster graph's frame rate on the same view (scene rows).
    pub rfps: Option<f64>,
    /// Median GPU milliseconds of each pass of the measured graph, in schedule order.
    pub passes: Vec<(String, f64)>,
}

/// What one measurement gives: the frame's median GPU ms, median rays and hits per frame, and
/// each pass's median GPU ms.
struct Measured {
    gpu_ms: f64,
    wall_ms: f64,
    rays: u64,
    hits: u64,
    passes: Vec<(String, f64)>,
}

/// Median GPU milliseconds of a frame (all passes) and of each pass, median rays per frame.
fn measure(
    gpu: &Gpu,
    graph: &Path,
    project: &Project,
    options: &CompileOptions,
    scene: &Scene,
    camera: &Camera,
    cfg: &RaysConfig,
) -> Result<Measured, crate::error::RuntimeError> {
    let plan = compile_with(graph, project, cfg.size, options)?;
    let mut exec = Executor::new(gpu, plan, scene)?;
    let frames = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, cfg.frames, |_| *camera)?;
    let mut gpu_ms: Vec<f64> = frames.iter().map(super::frame_gpu_ms).collect();
    let mut wall_ms: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
    let mut rays: Vec<f64> = frames.iter().map(|f| f.rays.map(|r| r.traced()).unwrap_or(0) as f64).collect();
    let mut hits: Vec<f64> = frames.iter().map(|f| f.rays.map(|r| r.hits).unwrap_or(0) as f64).collect();
    let passes = exec
        .plan()
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut ms: Vec<f64> = frames.iter().filter_map(|f| f.gpu_ms.as_ref().and_then(|g| g.get(i).copied())).collect();
            (p.name.clone(), if ms.is_empty() { f64::NAN } else { median(&mut ms) })
        })
        .collect();
    Ok(Measured { gpu_ms: median(&mut gpu_ms), wall_ms: median(&mut wall_ms), rays: median(&mut rays) as u64, hits: median(&mut hits) as u64, passes })
}

fn row(test: &str, backend: Backend, cfg: &RaysConfig, m: Measured, rfps: Option<f64>) -> RaysRow {
    let Measured { gpu_ms: ms, wall_ms, rays, hits, passes } = m;
    let pixels = cfg.size.0 as f64 * cfg.size.1 as f64;
    RaysRow {
        test: test.into(),
        backend,
        fps: 1000.0 / ms,
        gpu_ms: ms,
        wall_ms,
        rays_per_frame: rays,
        rays_per_pixel: rays as f64 / pixels,
        grays_per_s: rays as f64 / (ms * 1e-3) / 1e9,
        hit_fraction: if rays > 0 { hits as f64 / rays as f64 } else { 0.0 },
        rfps,
        passes,
    }
}

/// Cameras of the Miss test (straight up into the sky above the scene) and the Stress test
/// (close above the scene's lowest large surface, looking down at it, narrow field of view).
pub fn miss_and_stress_cameras(scene: &Scene) -> (Camera, Camera) {
    let b = scene.bounds();
    let (c, r) = (b.center(), 0.5 * b.diagonal().max(1e-3));
    let miss = Camera {
        up: glam::Vec3::Z,
        ..Camera::look(glam::Vec3::new(c.x, b.max.y + r, c.z), glam::Vec3::new(c.x, b.max.y + 3.0 * r, c.z), 60.0, r * 1e-3, r * 10.0)
    };
    let floor = glam::Vec3::new(c.x, b.min.y, c.z);
    let stress = Camera { up: glam::Vec3::Z, ..Camera::look(floor + glam::Vec3::Y * (0.05 * r), floor, 20.0, r * 1e-4, r * 10.0) };
    (miss, stress)
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
    let total = cfg.scenes.len() * (cfg.backends.len() + 1) + 2 * cfg.backends.len();
    let mut done = 0;
    let mut rows = Vec::new();
    let mut last_scene = None;
    for name in &cfg.scenes {
        let (scene, _) = crate::scene::open(name, &LoadOptions { textures: true, ..Default::default() })?;
        let raster_ms = measure(gpu, &raster, &project, &gpu.compile_options(), &scene, &scene.camera, cfg)?.gpu_ms;
        done += 1;
        progress(done, total, &format!("{name}: raster"));
        for &backend in &cfg.backends {
            let mut options = gpu.compile_options_for(backend);
            options.params.insert(("ao".into(), "rays".into()), ParamValue::Int(cfg.ao_rays));
            options.params.insert(("ao".into(), "range_scale".into()), ParamValue::Float(cfg.ao_length));
            let m = measure(gpu, &workload, &project, &options, &scene, &scene.camera, cfg)?;
            rows.push(row(name, backend, cfg, m, Some(1000.0 / raster_ms)));
            on_rows(&rows);
            done += 1;
            progress(done, total, &format!("{name}: {backend}"));
        }
        last_scene = Some(scene);
    }
    if let Some(scene) = last_scene {
        let (miss, stress) = miss_and_stress_cameras(&scene);
        for &backend in &cfg.backends {
            let mut options = gpu.compile_options_for(backend);
            options.params.insert(("primary".into(), "rays".into()), ParamValue::Int(cfg.primary_rays));
            for (test, camera) in [("Miss", &miss), ("Stress", &stress)] {
                let m = measure(gpu, &primary, &project, &options, &scene, camera, cfg)?;
                rows.push(row(test, backend, cfg, m, None));
                on_rows(&rows);
                done += 1;
                progress(done, total, &format!("{test}: {backend}"));
            }
        }
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

/// What the workload and the columns are, for the results' headers.
pub fn definitions(cfg: &RaysConfig) -> String {
    format!(
        "Scene workload (`graph/bench_rays.ron`): per pixel 1 primary ray, and where it hits 1 shadow ray and {} AO rays of length {} x the scene's bounding radius. Miss and Stress (`graph/bench_primary.ron`): {} primary rays per pixel. FPS = 1000 / GPU ms (the sum of the passes' timestamps); wall ms = the frame's wall-clock time (recording, submission, the wait); RFPS = the Rasterization graph's 1000 / GPU ms on the scene's view. Timed frames follow a warm-up that lasts until the frame time has settled.",
        cfg.ao_rays, cfg.ao_length, cfg.primary_rays
    )
}

/// The table as CSV (with the run header and [`definitions`] as `#` comments).
pub fn csv(info: &RunInfo, cfg: &RaysConfig, rows: &[RaysRow]) -> String {
    let mut s = info.csv_comment();
    let _ = writeln!(s, "# {}", definitions(cfg));
    s.push_str("test,backend,fps,gpu_ms,wall_ms,rays_per_frame,rays_per_pixel,grays_per_s,hit_fraction,rfps\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{:.4},{:.4},{:.4},{},{:.3},{:.5},{:.4},{}",
            r.test,
            r.backend,
            r.fps,
            r.gpu_ms,
            r.wall_ms,
            r.rays_per_frame,
            r.rays_per_pixel,
            r.grays_per_s,
            r.hit_fraction,
            r.rfps.map(|f| format!("{f:.3}")).unwrap_or_default()
        );
    }
    s
}

/// The table as markdown, with the paper's RTX 2080 Ti figures beside it.
pub fn markdown(info: &RunInfo, cfg: &RaysConfig, rows: &[RaysRow]) -> String {
    let paper = |test: &str| match test {
        "box" => "12.82",
        "organic" => "5.50",
        "atrium" => "7.09",
        "Miss" => "12.52",
        "Stress" => "6.25",
        _ => "",
    };
    let mut s = format!("# bench rays\n\n{}\n{}\n\n", info.markdown(), definitions(cfg));
    s.push_str("| test | back-end | FPS | GPU ms | wall ms | rays/pixel | GigaRays/s | hit fraction | RFPS | paper GR/s (RTX 2080 Ti) |\n");
    s.push_str("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.3} | {:.3} | {:.2} | {:.3} | {:.3} | {} | {} |",
            r.test,
            r.backend,
            r.fps,
            r.gpu_ms,
            r.wall_ms,
            r.rays_per_pixel,
            r.grays_per_s,
            r.hit_fraction,
            r.rfps.map(|f| format!("{f:.1}")).unwrap_or_else(|| "—".into()),
            paper(&r.test)
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
    let paper = [("box", 12.82), ("organic", 5.50), ("atrium", 7.09), ("Miss", 12.52), ("Stress", 6.25)];
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
