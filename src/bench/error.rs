//! `raygraph bench error`: speed against error for ray-traced ambient occlusion. The scene is a
//! floor under a parallel ceiling at height `h`, with AO rays of length `R`: for cosine-weighted
//! directions the unoccluded fraction is `(h/R)^2` at every floor point, so the reference is
//! exact. For every back-end, sampling scheme (`white`: independent numbers per ray; `r2`: the
//! R2 low-discrepancy sequence, rotated per pixel; `net`: a scrambled (0,k,2)-net per pixel, its
//! rays in cell order) and rays per pixel 1, 2, 4, ..., the AO pass
//! of `graph/ao.ron` runs with several seeds. A row holds the AO pass's GPU time (median) and,
//! over all pixels and seeds, the RMSE and relMSE against the reference, the bias (mean error)
//! and the variance (mean over pixels of the variance across seeds), and FLIP (mean and 99th
//! percentile) of the images shown as grey against the reference grey. The slope of log RMSE
//! against log rays per pixel is fitted per back-end and scheme (-0.5 for white noise).
//! Also hybrid against full RT ([`run_hybrid`]): both final images of a scene, compared with
//! full RT as the reference, and both frame times; and shadow maps against ray-traced shadows
//! ([`run_shadow_maps`]): false-shadow and false-lit rates over the shadow-map bias, normal
//! offset and resolution.

use super::RunInfo;
use crate::backend::Backend;
use crate::error::RuntimeError;
use crate::graph::compile::{compile_with, CompileOptions};
use crate::graph::desc::ParamValue;
use crate::graph::Project;
use crate::runtime::profiler::median;
use crate::runtime::{Executor, Gpu};
use crate::scene::{builtin, Camera, Instance, Scene};
use crate::util::linear_to_srgb;
use glam::{Mat4, Vec3};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Ceiling height and AO ray length: the reference unoccluded fraction is `(H / R)^2`.
pub(crate) const CEILING: f32 = 0.5;
/// AO ray length of the closed-form scene.
pub(crate) const RANGE: f32 = 1.0;

/// The sampling schemes of `layers/rt_ao.ron` (its `sampling` parameter).
pub(crate) const SCHEMES: [(&str, i64); 3] = [("white", 0), ("r2", 1), ("net", 2)];

/// Settings of `raygraph bench error`.
#[derive(Debug, Clone)]
pub struct ErrorConfig {
    /// Frame size.
    pub size: (u32, u32),
    /// Rays per pixel run: 1, 2, 4, ... up to this.
    pub max_rays: i64,
    /// Seeds per ray count.
    pub seeds: u32,
    /// Untimed frames before the timed ones of every seed (the GPU's clocks rise under load).
    pub warmup: u32,
    /// Timed frames per seed.
    pub frames: u32,
    /// The back-ends measured.
    pub backends: Vec<Backend>,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

impl ErrorConfig {
    /// The settings of the published tables.
    pub fn full(root: &Path, backends: Vec<Backend>) -> Self {
        Self { size: (256, 256), max_rays: 256, seeds: 8, warmup: 20, frames: 10, backends, root: root.to_path_buf() }
    }

    /// A small run for tests.
    pub fn quick(root: &Path, backends: Vec<Backend>) -> Self {
        Self { size: (32, 32), max_rays: 64, seeds: 4, warmup: 1, frames: 1, backends, root: root.to_path_buf() }
    }
}

/// One ray count of one sampling scheme on one back-end, over all seeds.
#[derive(Debug, Clone)]
pub struct ErrorRow {
    /// The back-end.
    pub backend: Backend,
    /// The sampling scheme: `white`, `r2` or `net` (the `sampling` parameter of `layers/rt_ao.ron`).
    pub sampling: &'static str,
    /// AO rays per pixel.
    pub rays: i64,
    /// GPU milliseconds of the AO pass.
    pub ao_ms: f64,
    /// Root mean square error against the closed form.
    pub rmse: f64,
    /// Relative mean square error.
    pub relmse: f64,
    /// Mean error (bias).
    pub bias: f64,
    /// Variance over seeds.
    pub variance: f64,
    /// FLIP (NVIDIA's perceptual difference, `nv-flip`) of the AO images shown as grey against
    /// the reference grey: mean and 99th percentile over all pixels of all seeds.
    pub flip_mean: f64,
    /// 99th percentile of FLIP.
    pub flip_p99: f64,
}

/// The floor, the ceiling (a floor turned over, facing down) and a camera between them looking
/// down: every pixel sees the floor.
pub fn ceiling_scene() -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("parallel ceiling");
    s.set_meshes(vec![builtin::plane("floor", 400.0, 1.0)]);
    s.strip_textures();
    let ceiling = Mat4::from_translation(Vec3::new(0.0, CEILING, 0.0)) * Mat4::from_rotation_x(std::f32::consts::PI);
    s.set_instances(vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 0, material: 0, transform: ceiling }]);
    *s.camera_mut() = Camera::look(Vec3::new(0.0, 0.25, 0.0), Vec3::new(0.0, 0.0, 0.001), 40.0, 0.01, 100.0);
    *s.presets_mut() = vec![("default".into(), *s.camera())];
    s.set_point_light(None);
    s
}

/// `on_rows` sees the rows finished so far after each one.
pub fn run(
    gpu: &Gpu,
    cfg: &ErrorConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[ErrorRow]),
) -> Result<Vec<ErrorRow>, RuntimeError> {
    let bench = AoBench {
        gpu,
        cfg,
        scene: ceiling_scene(),
        reference: (CEILING as f64 / RANGE as f64).powi(2),
        project: Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") },
        graph: cfg.root.join("graph/ao.ron"),
    };
    let rays: Vec<i64> = std::iter::successors(Some(1i64), |r| Some(r * 2)).take_while(|r| *r <= cfg.max_rays).collect();
    let total = cfg.backends.len() * SCHEMES.len() * rays.len();
    let mut rows = Vec::new();
    for &backend in &cfg.backends {
        for &(sampling, scheme) in &SCHEMES {
            for &n in &rays {
                rows.push(bench.row(backend, (sampling, scheme), n)?);
                on_rows(&rows);
                progress(rows.len(), total, &format!("{backend}: {sampling}, {n} rays/pixel"));
            }
        }
    }
    Ok(rows)
}

/// The AO pass of `graph/ao.ron` on the closed-form scene, against its reference.
struct AoBench<'a> {
    gpu: &'a Gpu,
    cfg: &'a ErrorConfig,
    /// [`ceiling_scene`].
    scene: Scene,
    /// The exact unoccluded fraction.
    reference: f64,
    project: Project,
    /// `graph/ao.ron`.
    graph: PathBuf,
}

/// One seed's run of the AO pass: its GPU times and the AO of the floor's pixels.
struct AoSeed {
    /// GPU milliseconds of the AO node, one per timed frame.
    ms: Vec<f64>,
    /// The AO of every floor pixel.
    floor: Vec<f64>,
}

impl AoBench<'_> {
    /// The row of `n` rays per pixel with the `(name, value)` sampling scheme on `backend`,
    /// over every seed.
    fn row(&self, backend: Backend, (sampling, scheme): (&'static str, i64), n: i64) -> Result<ErrorRow, RuntimeError> {
        let mut images: Vec<Vec<f64>> = Vec::new();
        let mut ms = Vec::new();
        let mut flip = nv_flip::FlipPool::new();
        for seed in 0..self.cfg.seeds {
            let run = self.seed(backend, scheme, n, seed, &mut flip)?;
            ms.extend(run.ms);
            images.push(run.floor);
        }
        let (rmse, relmse, bias, variance) = error_statistics(&images, self.reference)?;
        let (flip_mean, flip_p99) = (flip.mean() as f64, flip.get_percentile(0.99, false) as f64);
        Ok(ErrorRow { backend, sampling, rays: n, ao_ms: median(&mut ms), rmse, relmse, bias, variance, flip_mean, flip_p99 })
    }

    /// Runs the AO pass with one seed; adds its image's FLIP against the reference to `flip`.
    fn seed(&self, backend: Backend, scheme: i64, n: i64, seed: u32, flip: &mut nv_flip::FlipPool) -> Result<AoSeed, RuntimeError> {
        let (gpu, cfg, scene) = (self.gpu, self.cfg, &self.scene);
        let mut options = gpu.compile_options_for(backend);
        for (name, value) in [
            ("rays", ParamValue::Int(n)),
            ("range", ParamValue::Float(RANGE as f64)),
            ("range_scale", ParamValue::Float(0.0)),
            ("sampling", ParamValue::Int(scheme)),
            ("seed", ParamValue::Int(seed as i64)),
        ] {
            options.params.insert(("ao".into(), name.into()), value);
        }
        let plan = compile_with(&self.graph, &self.project, cfg.size, &options)?;
        // The AO node's passes: its rays (ao/ao) and the sum of each pixel's lanes.
        if !plan.passes.iter().any(|p| p.node == "ao") {
            return Err(RuntimeError::Gpu("graph/ao.ron has no pass of node ao".into()));
        }
        let ao = plan.resource_by_name("ao.ao").ok_or_else(|| RuntimeError::Gpu("graph/ao.ron has no resource ao.ao".into()))?;
        let position = plan.resource_by_name("gbuffer.position").ok_or_else(|| RuntimeError::Gpu("graph/ao.ron has no gbuffer.position".into()))?;
        let mut exec = Executor::new(gpu, plan, scene)?;
        let frames = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, cfg.frames, |_| *scene.camera())?;
        let ms = frames.iter().map(|f| super::nodes_ms(&exec, f, &["ao"])).collect();
        let (_, _, values) = exec.read_texture_f32(gpu, ao)?;
        let (_, _, positions) = exec.read_texture_f32(gpu, position)?;
        let test: Vec<u8> = values.iter().flat_map(|v| grey(v[0] as f64)).collect();
        let reference_image: Vec<u8> = values.iter().flat_map(|_| grey(self.reference)).collect();
        let (w, h) = cfg.size;
        let error_map = nv_flip::flip(
            nv_flip::FlipImageRgb8::with_data(w, h, &reference_image),
            nv_flip::FlipImageRgb8::with_data(w, h, &test),
            nv_flip::DEFAULT_PIXELS_PER_DEGREE,
        );
        flip.update_with_image(&error_map);
        // Floor pixels only (every pixel, with this camera).
        let floor = values.iter().zip(&positions).filter(|(_, p)| p[3] != 0.0 && p[1].abs() < 1e-3).map(|(v, _)| v[0] as f64).collect();
        Ok(AoSeed { ms, floor })
    }
}

/// An AO value shown as sRGB grey.
fn grey(v: f64) -> [u8; 3] {
    let c = (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0).round() as u8;
    [c, c, c]
}

/// RMSE, relMSE, bias and variance (over seeds, mean over pixels) of the seeds' floor images
/// against `reference`, over the pixels every image has.
fn error_statistics(images: &[Vec<f64>], reference: f64) -> Result<(f64, f64, f64, f64), RuntimeError> {
    let pixels = images.iter().map(Vec::len).min().unwrap_or(0);
    if pixels == 0 {
        return Err(RuntimeError::Gpu("bench error: no floor pixel in the AO image".into()));
    }
    let samples = (pixels * images.len()) as f64;
    let errors = || images.iter().flat_map(|img| img[..pixels].iter().map(|v| v - reference));
    let rmse = (errors().map(|e| e * e).sum::<f64>() / samples).sqrt();
    let relmse = errors().map(|e| e * e / (reference * reference + 1e-2)).sum::<f64>() / samples;
    let bias = errors().sum::<f64>() / samples;
    let seeds = images.len() as f64;
    let variance = if images.len() > 1 {
        (0..pixels)
            .map(|p| {
                let mean = images.iter().map(|img| img[p]).sum::<f64>() / seeds;
                images.iter().map(|img| (img[p] - mean).powi(2)).sum::<f64>() / (seeds - 1.0)
            })
            .sum::<f64>()
            / pixels as f64
    } else {
        0.0
    };
    Ok((rmse, relmse, bias, variance))
}

/// A pass's GPU milliseconds in a frame (the frame's wall time without timestamp queries).
fn pass_ms(frame: &crate::runtime::profiler::FrameTimings, pass: usize) -> f64 {
    frame.gpu_ms.as_ref().map(|v| v[pass]).unwrap_or(frame.frame_ms)
}

/// Least-squares slope of log RMSE against log rays per pixel, per back-end and scheme.
pub fn slopes(rows: &[ErrorRow]) -> Vec<(Backend, &'static str, f64)> {
    let mut out = Vec::new();
    for r in rows {
        if out.iter().any(|(b, s, _)| *b == r.backend && *s == r.sampling) {
            continue;
        }
        let pts: Vec<(f64, f64)> =
            rows.iter().filter(|q| q.backend == r.backend && q.sampling == r.sampling && q.rmse > 0.0).map(|q| ((q.rays as f64).ln(), q.rmse.ln())).collect();
        let n = pts.len() as f64;
        if n < 2.0 {
            continue;
        }
        let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
        let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
        out.push((r.backend, r.sampling, slope));
    }
    out
}

/// The fewest rays per pixel (and their AO time) at which a series' RMSE is at most `target`.
fn equal_error(rows: &[ErrorRow], backend: Backend, sampling: &str, target: f64) -> Option<(i64, f64)> {
    rows.iter().filter(|r| r.backend == backend && r.sampling == sampling && r.rmse <= target).map(|r| (r.rays, r.ao_ms)).min_by_key(|r| r.0)
}

/// A results CSV: the run's comment lines, the header, then one line per row.
fn csv_file(info: &RunInfo, header: &str, lines: impl Iterator<Item = String>) -> String {
    let mut s = info.csv_comment();
    s.push_str(header);
    s.push('\n');
    for line in lines {
        s.push_str(&line);
        s.push('\n');
    }
    s
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[ErrorRow]) -> String {
    csv_file(
        info,
        "backend,sampling,rays,ao_ms,rmse,relmse,bias,variance,flip_mean,flip_p99",
        rows.iter().map(|r| {
            format!(
                "{},{},{},{:.5},{:.6},{:.6},{:.6},{:.7},{:.5},{:.5}",
                r.backend, r.sampling, r.rays, r.ao_ms, r.rmse, r.relmse, r.bias, r.variance, r.flip_mean, r.flip_p99
            )
        }),
    )
}

/// The rows as markdown tables (fitted slopes, equal-error and equal-time tables), with the run's header.
pub fn markdown(info: &RunInfo, rows: &[ErrorRow]) -> String {
    let mut s = format!("# bench error: ambient occlusion against the closed form\n\n{}\n", info.markdown());
    let _ = writeln!(
        s,
        "Floor under a parallel ceiling at h = {CEILING}, AO rays of length R = {RANGE}: reference unoccluded fraction (h/R)^2 = {}.\n",
        (CEILING as f64 / RANGE as f64).powi(2)
    );
    s.push_str("| back-end | sampling | rays/pixel | AO ms | RMSE | relMSE | bias | variance | FLIP mean | FLIP p99 |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.4} | {:.5} | {:.5} | {:+.5} | {:.6} | {:.4} | {:.4} |",
            r.backend, r.sampling, r.rays, r.ao_ms, r.rmse, r.relmse, r.bias, r.variance, r.flip_mean, r.flip_p99
        );
    }
    s.push_str("\nFitted slope of log RMSE against log rays per pixel:\n\n| back-end | sampling | slope |\n| --- | --- | ---: |\n");
    for (b, sampling, slope) in slopes(rows) {
        let _ = writeln!(s, "| {b} | {sampling} | {slope:.3} |");
    }
    s.push_str(
        "\nEqual error: the fewest rays per pixel (AO ms) reaching each RMSE:\n\n| back-end | RMSE | white | r2 | net |\n| --- | ---: | ---: | ---: | ---: |\n",
    );
    let mut backends: Vec<Backend> = Vec::new();
    for r in rows {
        if !backends.contains(&r.backend) {
            backends.push(r.backend);
        }
    }
    for &b in &backends {
        for target in [0.1, 0.05, 0.02, 0.01] {
            let cell = |sampling| equal_error(rows, b, sampling, target).map(|(n, ms)| format!("{n} ({ms:.3} ms)")).unwrap_or_else(|| "—".into());
            let _ = writeln!(s, "| {b} | {target} | {} | {} | {} |", cell("white"), cell("r2"), cell("net"));
        }
    }
    s.push_str("\nEqual time: the lowest RMSE each scheme reaches within a budget of AO pass time (the budgets are the white-noise rows' times):\n\n| back-end | AO ms budget | white RMSE | r2 RMSE | net RMSE |\n| --- | ---: | ---: | ---: | ---: |\n");
    for &b in &backends {
        for budget in rows.iter().filter(|r| r.backend == b && r.sampling == "white").map(|r| r.ao_ms) {
            let best = |sampling: &str| {
                rows.iter()
                    .filter(|r| r.backend == b && r.sampling == sampling && r.ao_ms <= budget)
                    .map(|r| r.rmse)
                    .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.min(x))))
                    .map(|x| format!("{x:.5}"))
                    .unwrap_or_else(|| "—".into())
            };
            let _ = writeln!(s, "| {b} | {budget:.4} | {} | {} | {} |", best("white"), best("r2"), best("net"));
        }
    }
    s
}

/// `error.png`: RMSE against the AO pass's GPU time, log-log, one line per back-end and scheme.
pub fn plots(dir: &Path, rows: &[ErrorRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut series: Vec<Series> = Vec::new();
    for r in rows {
        let name = format!("{}: {}", r.backend, r.sampling);
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push((r.ao_ms.max(1e-6), r.rmse.max(1e-9))),
            None => series.push(Series { name, points: vec![(r.ao_ms.max(1e-6), r.rmse.max(1e-9))] }),
        }
    }
    let path = dir.join("error.png");
    LinePlot { title: "AO error against time", x_label: "AO pass GPU ms", y_label: "RMSE against the closed form", log_x: true, log_y: true, x_labels: None }
        .write(&path, &series)?;
    Ok(vec![path])
}

/// Hybrid against full RT on one scene and back-end: both graphs' final images (the same
/// camera, shadows, AO and reflections; the G-buffer rasterized or from primary rays) and their
/// GPU frame times.
#[derive(Debug, Clone)]
pub struct HybridRow {
    /// The back-end.
    pub backend: Backend,
    /// The scene.
    pub scene: String,
    /// With the scene's textures, or with every material's constant colour only.
    pub textures: bool,
    /// GPU milliseconds of a hybrid frame.
    pub hybrid_ms: f64,
    /// GPU milliseconds of a full-RT frame.
    pub full_rt_ms: f64,
    /// Over the 8-bit RGB output: RMSE (in 8-bit units), the fraction of pixels with a channel
    /// differing by more than 8, and FLIP (mean, 99th percentile).
    pub rmse: f64,
    /// Fraction of pixels with a channel differing by more than 8.
    pub differing: f64,
    /// Mean FLIP.
    pub flip_mean: f64,
    /// 99th percentile of FLIP.
    pub flip_p99: f64,
}

/// Hybrid against full RT on `scenes` at `size`, on every back-end of `cfg`.
pub fn run_hybrid(gpu: &Gpu, cfg: &ErrorConfig, scenes: &[&str], size: (u32, u32)) -> Result<Vec<HybridRow>, RuntimeError> {
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let mut rows = Vec::new();
    for (name, textures) in scenes.iter().flat_map(|n| [(n, true), (n, false)]) {
        let (scene, _) = crate::scene::open(name, &crate::scene::LoadOptions { textures, ..Default::default() })?;
        for &backend in &cfg.backends {
            let mut images = Vec::new();
            let mut times = Vec::new();
            for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
                let plan = compile_with(&cfg.root.join(graph), &project, size, &gpu.compile_options_for(backend))?;
                let mut exec = Executor::new(gpu, plan, &scene)?;
                let frames = super::timed_frames(gpu, &mut exec, &scene, cfg.warmup, cfg.frames, |_| *scene.camera())?;
                let mut ms: Vec<f64> = frames.iter().map(super::frame_gpu_ms).collect();
                times.push(median(&mut ms));
                images.push(exec.read_output(gpu)?);
            }
            let (a, b) = (&images[0], &images[1]);
            let rgb = |img: &image::RgbaImage| img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect::<Vec<u8>>();
            let (ra, rb) = (rgb(a), rgb(b));
            let n = ra.len() as f64;
            let rmse = (ra.iter().zip(&rb).map(|(x, y)| (*x as f64 - *y as f64).powi(2)).sum::<f64>() / n).sqrt();
            let differing =
                a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| (p[c] as i32 - q[c] as i32).abs() > 8)).count() as f64 / (size.0 * size.1) as f64;
            let error_map = nv_flip::flip(
                nv_flip::FlipImageRgb8::with_data(size.0, size.1, &rb),
                nv_flip::FlipImageRgb8::with_data(size.0, size.1, &ra),
                nv_flip::DEFAULT_PIXELS_PER_DEGREE,
            );
            let mut pool = nv_flip::FlipPool::from_image(&error_map);
            rows.push(HybridRow {
                backend,
                scene: name.to_string(),
                textures,
                hybrid_ms: times[0],
                full_rt_ms: times[1],
                rmse,
                differing,
                flip_mean: pool.mean() as f64,
                flip_p99: pool.get_percentile(0.99, false) as f64,
            });
        }
    }
    Ok(rows)
}

/// The rows as CSV, with the run's header.
pub fn hybrid_csv(info: &RunInfo, rows: &[HybridRow]) -> String {
    csv_file(
        info,
        "scene,textures,backend,hybrid_ms,full_rt_ms,rmse,differing,flip_mean,flip_p99",
        rows.iter().map(|r| {
            format!(
                "{},{},{},{:.4},{:.4},{:.4},{:.5},{:.5},{:.5}",
                r.scene, r.textures, r.backend, r.hybrid_ms, r.full_rt_ms, r.rmse, r.differing, r.flip_mean, r.flip_p99
            )
        }),
    )
}

/// The rows as a markdown table, with the run's header.
pub fn hybrid_markdown(info: &RunInfo, rows: &[HybridRow]) -> String {
    let mut s = format!("# bench error: hybrid against full ray tracing\n\n{}\n", info.markdown());
    s.push_str("Full RT's image is the reference; RMSE in 8-bit units over RGB; differing: pixels with a channel more than 8 apart.\n\n");
    s.push_str("| scene | textures | back-end | hybrid ms | full RT ms | RMSE | differing pixels | FLIP mean | FLIP p99 |\n| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.2}% | {:.4} | {:.4} |",
            r.scene,
            if r.textures { "yes" } else { "no" },
            r.backend,
            r.hybrid_ms,
            r.full_rt_ms,
            r.rmse,
            100.0 * r.differing,
            r.flip_mean,
            r.flip_p99
        );
    }
    s
}

/// Shadow maps against ray-traced shadows ([`run_shadow_maps`]): the sweep of the raster
/// graph's shadow-map settings.
#[derive(Debug, Clone)]
pub struct ShadowMapSweep {
    /// The scenes.
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Shadow-map sizes (square texels): copies of `layers/shadow_map.ron` with that size.
    pub resolutions: Vec<u32>,
    /// The `forward` layer's `shadow_bias` (shadow-map depth units).
    pub biases: Vec<f64>,
    /// The `forward` layer's `normal_offset` (shadow-map texels).
    pub normal_offsets: Vec<f64>,
}

impl ShadowMapSweep {
    /// The sweep of the published tables.
    pub fn full() -> Self {
        Self {
            scenes: vec!["default".into(), "atrium".into()],
            size: (1280, 720),
            resolutions: vec![512, 1024, 2048, 4096],
            biases: vec![0.0, 3e-5, 1e-4, 3e-4, 1e-3, 1e-2],
            normal_offsets: vec![0.0, 0.5, 1.0, 2.0, 4.0],
        }
    }

    /// A small sweep for tests.
    pub fn quick() -> Self {
        Self { scenes: vec!["default".into()], size: (128, 72), resolutions: vec![256, 1024], biases: vec![0.0, 1e-4, 1e-2], normal_offsets: vec![0.0, 1.0] }
    }
}

/// One shadow-map setting against the ray-traced shadow mask, over the pixels both modes light
/// or shadow (surfaces facing the light). Rates: `false_shadow` = shadowed by the map among
/// the pixels the rays light; `false_lit` = lit by the map among those the rays shadow.
#[derive(Debug, Clone)]
pub struct ShadowMapRow {
    /// The scene.
    pub scene: String,
    /// Shadow-map size, texels.
    pub resolution: u32,
    /// The `shadow_bias`.
    pub bias: f64,
    /// The `normal_offset`.
    pub normal_offset: f64,
    /// Pixels the rays light.
    pub lit_pixels: usize,
    /// Pixels the rays shadow.
    pub shadowed_pixels: usize,
    /// Shadowed by the map among the pixels the rays light.
    pub false_shadow: f64,
    /// Lit by the map among the pixels the rays shadow.
    pub false_lit: f64,
    /// GPU ms of the shadow-map pass (median), and of the ray-traced shadow pass it replaces.
    pub shadow_map_ms: f64,
    /// GPU milliseconds of the ray-traced shadow pass.
    pub rt_shadow_ms: f64,
}

/// The shadow-map visibility of every pixel of the raster graph (`graph/raster.ron`) with the
/// hard filter (`pcf` 0, so each answer is lit or shadowed, like a shadow ray's), and the ray-
/// traced shadow mask of the hybrid graph (`graph/hybrid.ron`, AO and reflections off) as the
/// truth, at the same camera; both rasterize the same pixels. The map's answer is recovered
/// from the forward pass's colour with the ambient light off: colour with shadows over colour
/// without is the visibility (direct light is its only term). Compared: pixels whose surface
/// faces the light in both (the shadow ray is traced and the unshadowed colour is not black).
pub fn run_shadow_maps(gpu: &Gpu, cfg: &ErrorConfig, sweep: &ShadowMapSweep, backend: Backend) -> Result<Vec<ShadowMapRow>, RuntimeError> {
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let layer_text = read_text(&project.layers_dir.join("shadow_map.ron"))?;
    if !layer_text.contains(SHADOW_MAP_SIZE) {
        return Err(RuntimeError::Gpu(format!("layers/shadow_map.ron no longer declares `{SHADOW_MAP_SIZE}`: the sweep cannot size its copies")));
    }
    let mut rows = Vec::new();
    for name in &sweep.scenes {
        let (mut scene, _) = crate::scene::open(name, &crate::scene::LoadOptions { textures: false, ..Default::default() })?;
        scene.light_mut().ambient = 0.0;
        scene.set_point_light(None);
        let truth = shadow_truth(gpu, cfg, sweep, backend, &project, &scene)?;
        for &resolution in &sweep.resolutions {
            let dir = SweepDir::new(&format!("sm{resolution}"))?;
            dir.copy_files_of(&project.layers_dir)?;
            let sized_layer = dir.0.join("shadow_map.ron");
            std::fs::write(&sized_layer, layer_text.replace(SHADOW_MAP_SIZE, &format!("size: Absolute({resolution}, {resolution})")))
                .map_err(|source| RuntimeError::Output { path: sized_layer, source })?;
            let raster = RasterShadows {
                gpu,
                cfg,
                sweep,
                backend,
                scene: &scene,
                project: Project { layers_dir: dir.0.clone(), shaders_dir: project.shaders_dir.clone() },
                graph: cfg.root.join("graph/raster.ron"),
            };
            let (unshadowed, _) = raster.render(false, 0.0, 0.0)?;
            for &normal_offset in &sweep.normal_offsets {
                for &bias in &sweep.biases {
                    let (shadowed, shadow_map_ms) = raster.render(true, bias, normal_offset)?;
                    let ShadowCounts { lit, dark, false_shadow, false_lit } = ShadowCounts::compare(&truth, &unshadowed, &shadowed);
                    if lit == 0 || dark == 0 {
                        return Err(RuntimeError::Gpu(format!(
                            "bench error: {name} has {lit} lit and {dark} shadowed pixels facing the light; both are needed"
                        )));
                    }
                    rows.push(ShadowMapRow {
                        scene: name.clone(),
                        resolution,
                        bias,
                        normal_offset,
                        lit_pixels: lit,
                        shadowed_pixels: dark,
                        false_shadow: false_shadow as f64 / lit as f64,
                        false_lit: false_lit as f64 / dark as f64,
                        shadow_map_ms,
                        rt_shadow_ms: truth.rt_shadow_ms,
                    });
                }
            }
        }
    }
    Ok(rows)
}

/// The shadow-map size `layers/shadow_map.ron` declares; the sweep's copies replace it.
const SHADOW_MAP_SIZE: &str = "size: Absolute(2048, 2048)";

/// The resource `name` of `plan`.
fn plan_resource(plan: &crate::graph::Plan, name: &str) -> Result<usize, RuntimeError> {
    plan.resource_by_name(name).ok_or_else(|| RuntimeError::Gpu(format!("no resource {name}")))
}

/// The truth of the shadow-map sweep on one scene: the ray-traced shadow mask, and which pixels
/// face the light.
struct ShadowTruth {
    /// The shadow mask of the hybrid graph (1 where the shadow ray reaches the light).
    mask: Vec<[f32; 4]>,
    /// Pixels whose surface (rasterized, not background) faces the light.
    faces_light: Vec<bool>,
    /// GPU milliseconds of the ray-traced shadow pass (median).
    rt_shadow_ms: f64,
}

/// The ray-traced shadow mask over the rasterized G-buffer: `graph/hybrid.ron` with AO and
/// reflections off.
fn shadow_truth(gpu: &Gpu, cfg: &ErrorConfig, sweep: &ShadowMapSweep, backend: Backend, project: &Project, scene: &Scene) -> Result<ShadowTruth, RuntimeError> {
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    let text = read_text(&cfg.root.join("graph/hybrid.ron"))?
        .replace("\"ao\": Layer(", "\"ao\": Layer(enabled: false, ")
        .replace("\"reflection\": Layer(", "\"reflection\": Layer(enabled: false, ");
    let truth_dir = SweepDir::new("truth")?;
    let truth_graph = truth_dir.0.join("hybrid.ron");
    std::fs::write(&truth_graph, text).map_err(|source| RuntimeError::Output { path: truth_graph.clone(), source })?;
    let plan = compile_with(&truth_graph, project, sweep.size, &options)?;
    let rt_pass =
        plan.passes.iter().position(|p| p.name == "shadow/shadow").ok_or_else(|| RuntimeError::Gpu("graph/hybrid.ron has no pass shadow/shadow".into()))?;
    let (shadow_id, geo_id, pos_id) =
        (plan_resource(&plan, "shadow.shadow")?, plan_resource(&plan, "gbuffer.geo_normal")?, plan_resource(&plan, "gbuffer.position")?);
    let mut exec = Executor::new(gpu, plan, scene)?;
    let frames = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, cfg.frames, |_| *scene.camera())?;
    let rt_shadow_ms = median(&mut frames.iter().map(|f| pass_ms(f, rt_pass)).collect::<Vec<_>>());
    let mask = exec.read_texture_f32(gpu, shadow_id)?.2;
    let geo = exec.read_texture_f32(gpu, geo_id)?.2;
    let positions = exec.read_texture_f32(gpu, pos_id)?.2;
    let l = scene.light().direction.normalize();
    let faces_light: Vec<bool> = geo.iter().zip(&positions).map(|(n, p)| p[3] != 0.0 && Vec3::new(n[0], n[1], n[2]).dot(l) > 0.0).collect();
    Ok(ShadowTruth { mask, faces_light, rt_shadow_ms })
}

/// The raster graph (`graph/raster.ron`) with one shadow-map size (the layers of `project`),
/// the ambient light off and the hard filter.
struct RasterShadows<'a> {
    gpu: &'a Gpu,
    cfg: &'a ErrorConfig,
    sweep: &'a ShadowMapSweep,
    backend: Backend,
    scene: &'a Scene,
    /// The layers with the sized `shadow_map.ron`.
    project: Project,
    /// `graph/raster.ron`.
    graph: PathBuf,
}

impl RasterShadows<'_> {
    /// The forward pass's colour with shadows on or off at `bias` and normal `offset`, and the
    /// shadow-map pass's GPU milliseconds (median).
    fn render(&self, shadows: bool, bias: f64, offset: f64) -> Result<(Vec<[f32; 4]>, f64), RuntimeError> {
        let (gpu, cfg, scene) = (self.gpu, self.cfg, self.scene);
        let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(self.backend) };
        for (param, value) in [
            ("shadows", ParamValue::Bool(shadows)),
            ("shadow_bias", ParamValue::Float(bias)),
            ("normal_offset", ParamValue::Float(offset)),
            ("pcf", ParamValue::Int(0)),
        ] {
            options.params.insert(("forward".into(), param.into()), value);
        }
        let plan = compile_with(&self.graph, &self.project, self.sweep.size, &options)?;
        let pass = plan
            .passes
            .iter()
            .position(|p| p.name == "shadow_map/shadow_map")
            .ok_or_else(|| RuntimeError::Gpu("graph/raster.ron has no pass shadow_map/shadow_map".into()))?;
        let color = plan_resource(&plan, "forward.color")?;
        let mut exec = Executor::new(gpu, plan, scene)?;
        let frames = super::timed_frames(gpu, &mut exec, scene, cfg.warmup, cfg.frames, |_| *scene.camera())?;
        let ms = median(&mut frames.iter().map(|f| pass_ms(f, pass)).collect::<Vec<_>>());
        Ok((exec.read_texture_f32(gpu, color)?.2, ms))
    }
}

/// The shadow map's answers against the truth's, over the pixels facing the light and lit
/// without shadows.
struct ShadowCounts {
    /// Pixels the rays light.
    lit: usize,
    /// Pixels the rays shadow.
    dark: usize,
    /// Lit by the rays, shadowed by the map.
    false_shadow: usize,
    /// Shadowed by the rays, lit by the map.
    false_lit: usize,
}

impl ShadowCounts {
    /// Counts over the forward pass's colour without shadows (`unshadowed`) and with them:
    /// their ratio is the map's visibility.
    fn compare(truth: &ShadowTruth, unshadowed: &[[f32; 4]], shadowed: &[[f32; 4]]) -> Self {
        let brightness = |c: &[f32; 4]| c[0] as f64 + c[1] as f64 + c[2] as f64;
        let (mut lit, mut dark, mut false_shadow, mut false_lit) = (0usize, 0usize, 0usize, 0usize);
        for i in 0..truth.mask.len() {
            let full = brightness(&unshadowed[i]);
            if !truth.faces_light[i] || full <= 1e-3 {
                continue;
            }
            let map_lit = brightness(&shadowed[i]) / full > 0.5;
            if truth.mask[i][0] == 1.0 {
                lit += 1;
                false_shadow += !map_lit as usize;
            } else {
                dark += 1;
                false_lit += map_lit as usize;
            }
        }
        Self { lit, dark, false_shadow, false_lit }
    }
}

/// A scratch directory for the sweep's layer copies, removed on drop.
struct SweepDir(PathBuf);

impl SweepDir {
    fn new(name: &str) -> Result<Self, RuntimeError> {
        let dir = std::env::temp_dir().join(format!("raygraph-shadow-maps-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(|source| RuntimeError::Output { path: dir.clone(), source })?;
        Ok(Self(dir))
    }

    /// Copies the files (not the folders) of `from` into this directory.
    fn copy_files_of(&self, from: &Path) -> Result<(), RuntimeError> {
        let entries = std::fs::read_dir(from).map_err(|e| RuntimeError::Gpu(format!("could not read {}: {e}", from.display())))?;
        for e in entries.flatten() {
            if e.path().is_file() {
                let to = self.0.join(e.file_name());
                std::fs::copy(e.path(), &to).map_err(|source| RuntimeError::Output { path: to, source })?;
            }
        }
        Ok(())
    }
}

fn read_text(path: &Path) -> Result<String, RuntimeError> {
    std::fs::read_to_string(path).map_err(|e| RuntimeError::Gpu(format!("could not read {}: {e}", path.display())))
}

impl Drop for SweepDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The rows as CSV, with the run's header.
pub fn shadow_map_csv(info: &RunInfo, rows: &[ShadowMapRow]) -> String {
    csv_file(
        info,
        "scene,resolution,bias,normal_offset,lit_pixels,shadowed_pixels,false_shadow,false_lit,shadow_map_ms,rt_shadow_ms",
        rows.iter().map(|r| {
            format!(
                "{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.4}",
                r.scene, r.resolution, r.bias, r.normal_offset, r.lit_pixels, r.shadowed_pixels, r.false_shadow, r.false_lit, r.shadow_map_ms, r.rt_shadow_ms
            )
        }),
    )
}

/// The rows as a markdown table, with the run's header.
pub fn shadow_map_markdown(info: &RunInfo, rows: &[ShadowMapRow]) -> String {
    let mut s = format!("# bench error: shadow maps against ray-traced shadows\n\n{}\n", info.markdown());
    s.push_str(
        "The raster graph's shadow map (hard filter, `pcf` 0) against one shadow ray per pixel (the truth), over the pixels facing the light. \
         False shadow: shadowed by the map among the pixels the rays light; false lit: lit by the map among those the rays shadow.\n\n",
    );
    s.push_str("| scene | map size | bias | normal offset | false shadow | false lit | shadow map ms | RT shadow ms |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2}% | {:.2}% | {:.3} | {:.3} |",
            r.scene,
            r.resolution,
            r.bias,
            r.normal_offset,
            100.0 * r.false_shadow,
            100.0 * r.false_lit,
            r.shadow_map_ms,
            r.rt_shadow_ms
        );
    }
    s
}

/// `shadow_maps.png`: false-shadow rate against false-lit rate, one line over the biases per
/// scene, map size and normal offset.
pub fn shadow_map_plot(dir: &Path, rows: &[ShadowMapRow]) -> Result<Vec<PathBuf>, String> {
    use super::plot::{LinePlot, Series};
    let mut series: Vec<Series> = Vec::new();
    for r in rows {
        let name = format!("{} {}², offset {}", r.scene, r.resolution, r.normal_offset);
        let point = (r.false_lit, r.false_shadow);
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => series.push(Series { name, points: vec![point] }),
        }
    }
    let path = dir.join("shadow_maps.png");
    LinePlot {
        title: "Shadow maps against shadow rays (bias swept along each line)",
        x_label: "false-lit rate",
        y_label: "false-shadow rate",
        log_x: false,
        log_y: false,
        x_labels: None,
    }
    .write(&path, &series)?;
    Ok(vec![path])
}
