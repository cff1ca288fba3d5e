//! `raygraph bench error`, its part on the time-filtered effects of `graph/hybrid_denoised.ron`:
//! ambient occlusion, soft shadows and one-bounce GI, each with 1, 2, 4, ... rays per pixel,
//! and glossy reflections (one ray a pixel and bounce, the graph's own),
//! with and without its filters (`temporal` and `atrous`), measured against a converged
//! reference: the same graph with the effect's spatial filter off and its temporal
//! accumulation made a plain running mean (no variance clamp, no history limit) over
//! `reference_frames` frames at the most rays, read in 32-bit floats (the shadows' through
//! `modulate`, see [`Effect::reference`]). Only the effect's own
//! signal is compared (the texture the resolve reads for it), on the pixels that show geometry:
//!
//! - relMSE: the mean over pixels and colour channels of (x - r)^2 / (r^2 + 0.01);
//! - ꟻLIP mean: both signals shown as LDR sRGB images (AO as grey, clamped to [0, 1]; the HDR
//!   signals, direct light, GI and reflections, through x / (1 + x) per channel).
//!
//! Noisy rows: the effect's filters switched off (bypassed), one frame (new samples every
//! frame: the error does not depend on the frame). Filtered rows: after 1 frame (the spatial
//! filter alone has anything to work with) and after `settle_frames` frames of a still camera.
//! Milliseconds: medians over the filtered run's `settle_frames` frames (after the warm-up) of
//! the effect's trace pass alone for the noisy rows (the same pass doing the same work), and of
//! the trace pass with its two filters and the shared `motion` pass for the filtered rows. The track: the graph's own ray counts, a still
//! stretch (frame-to-frame ꟻLIP: flicker), then a fast turn in place (in `turn_frames` equal
//! steps, 40% of the horizontal field of view in all, so that what was in the middle of the
//! view stays in it; each step under the executor's 30-degree camera cut) and a stop, with the error against a reference at the new
//! view in the frames after the stop (ghosting).

use super::RunInfo;
use crate::backend::Backend;
use crate::error::RuntimeError;
use crate::graph::compile::{compile_with, CompileOptions, Project};
use crate::graph::desc::ParamValue;
use crate::runtime::{Executor, Gpu};
use crate::scene::{Camera, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One time-filtered effect of `graph/hybrid_denoised.ron`.
#[derive(Debug, Clone, Copy)]
pub struct Effect {
    /// As the tables name it.
    pub label: &'static str,
    /// The node that traces it.
    pub node: &'static str,
    /// Whether the node has a `rays` parameter, set to each of the ray counts (else the rows
    /// are the graph's own sampling, shown as 1 ray).
    pub has_rays: bool,
    /// Its noisy signal.
    pub signal: &'static str,
    /// Its temporal filter node, its spatial one, then any node that puts the filtered signal
    /// back together (the shadows' `modulate`).
    pub filters: &'static [&'static str],
    /// The filtered signal.
    pub filtered: &'static str,
    /// What the reference reads after its frames with the spatial filter switched off: the
    /// temporal filter's 32-bit running mean, or for shadows (filtered as a visibility ratio)
    /// its half-float output put back on the unshadowed light (`modulate`; half floats round
    /// by at most 2^-11 of the value).
    pub reference: &'static str,
    /// Whether the signal is HDR (shown through x / (1 + x) for ꟻLIP) rather than in [0, 1].
    pub hdr: bool,
}

/// AO, soft shadows, GI and glossy reflections.
pub const EFFECTS: [Effect; 4] = [
    Effect {
        label: "AO",
        node: "ao",
        has_rays: true,
        signal: "ao.ao",
        filters: &["ao_temporal", "ao_denoise"],
        filtered: "ao_denoise.filtered",
        reference: "ao_temporal/mean",
        hdr: false,
    },
    Effect {
        label: "soft shadows",
        node: "shadow",
        has_rays: true,
        signal: "shadow.direct",
        filters: &["shadow_temporal", "shadow_denoise", "shadow_light"],
        filtered: "shadow_light.product",
        reference: "shadow_light.product",
        hdr: true,
    },
    Effect {
        label: "GI",
        node: "gi",
        has_rays: true,
        signal: "gi.gi",
        filters: &["gi_temporal", "gi_denoise"],
        filtered: "gi_denoise.filtered",
        reference: "gi_temporal/mean",
        hdr: true,
    },
    Effect {
        label: "reflections",
        node: "reflection",
        has_rays: false,
        signal: "reflection.reflection",
        filters: &["reflection_temporal", "reflection_denoise"],
        filtered: "reflection_denoise.filtered",
        reference: "reflection_temporal/mean",
        hdr: true,
    },
];

impl Effect {
    /// The ray counts of its rows.
    fn ray_counts(&self, cfg: &FiltersConfig) -> Vec<i64> {
        if self.has_rays {
            cfg.rays.clone()
        } else {
            vec![1]
        }
    }

    /// The parameters that set `rays` rays a pixel (none without a `rays` parameter).
    fn rays_params(&self, rays: i64) -> Vec<(&'static str, &'static str, ParamValue)> {
        if self.has_rays {
            vec![(self.node, "rays", ParamValue::Int(rays))]
        } else {
            Vec::new()
        }
    }
}

/// What the part runs.
#[derive(Debug, Clone)]
pub struct FiltersConfig {
    /// Built-in scene names or glTF files.
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Rays per pixel of the rows.
    pub rays: Vec<i64>,
    /// Frames accumulated into the reference (at the most rays).
    pub reference_frames: u32,
    /// Frames of a still camera before a filtered row is measured.
    pub settle_frames: u32,
    /// Frames of the track's still stretch compared pairwise (flicker).
    pub still_frames: u32,
    /// Frames of the turn (see the module doc).
    pub turn_frames: u32,
    /// The back-end.
    pub backend: Backend,
    /// Where `graph/`, `layers/` and `shaders/` are.
    pub root: PathBuf,
}

impl FiltersConfig {
    /// The published run: the atrium and a shared real asset at 1280x720.
    pub fn full(root: &Path, backend: Backend) -> Self {
        Self {
            scenes: vec!["atrium".into(), "assets/gltf/DamagedHelmet/DamagedHelmet.glb".into()],
            size: (1280, 720),
            rays: vec![1, 2, 4, 8],
            reference_frames: 2048,
            settle_frames: 32,
            still_frames: 8,
            turn_frames: 6,
            backend,
            root: root.to_path_buf(),
        }
    }

    /// Seconds on a CPU (CI).
    pub fn quick(root: &Path, backend: Backend) -> Self {
        Self {
            scenes: vec!["default".into()],
            size: (64, 36),
            rays: vec![1, 2],
            reference_frames: 64,
            settle_frames: 8,
            still_frames: 3,
            turn_frames: 2,
            backend,
            root: root.to_path_buf(),
        }
    }
}

/// One row: an effect at a ray count, noisy or filtered after some frames.
#[derive(Debug, Clone)]
pub struct FilterRow {
    /// The scene.
    pub scene: String,
    /// The effect's label.
    pub effect: &'static str,
    /// Rays per pixel.
    pub rays: i64,
    /// 0 for the noisy signal; else the frames the filters had.
    pub filtered_frames: u32,
    /// Median GPU ms per frame of the effect's passes.
    pub ms: f64,
    /// relMSE against the reference.
    pub relmse: f64,
    /// ꟻLIP mean against the reference.
    pub flip: f64,
}

/// The track's figures for an effect, noisy or filtered.
#[derive(Debug, Clone)]
pub struct TrackRow {
    /// The scene.
    pub scene: String,
    /// The effect's label.
    pub effect: &'static str,
    /// Whether the filters ran.
    pub filtered: bool,
    /// Mean ꟻLIP between consecutive frames of the still stretch.
    pub flicker: f64,
    /// ꟻLIP against the reference at the still view, at the end of the still stretch.
    pub still_error: f64,
    /// ꟻLIP against the reference at the view after the turn, 1, 2, 4 and 8 frames after it.
    pub after_turn: [f64; 4],
}

/// An effect's signal and the pixels showing geometry, read after a frame.
struct Signal {
    values: Vec<[f32; 4]>,
    geometry: Vec<bool>,
}

/// The compiled graph's executor for `effect` with `off` switched off and `params` set on
/// `(node, name)`. The other effects and the reflections are switched off too: the effects are
/// independent of each other (GI traces its own shadow rays), so this changes nothing in the
/// effect's signal and keeps the timings to its own passes.
fn executor(
    gpu: &Gpu,
    cfg: &FiltersConfig,
    scene: &Scene,
    effect: &Effect,
    off: &[&str],
    params: &[(&str, &str, ParamValue)],
) -> Result<Executor, RuntimeError> {
    let project = Project { layers_dir: cfg.root.join("layers"), shaders_dir: cfg.root.join("shaders") };
    let mut options: CompileOptions = gpu.compile_options_for(cfg.backend);
    options.reuse = false; // every resource readable after the frame
    let others = EFFECTS.iter().filter(|e| e.node != effect.node).flat_map(|e| std::iter::once(e.node).chain(e.filters.iter().copied()));
    for node in off.iter().copied().chain(others) {
        options.enabled.insert(node.to_string(), false);
    }
    for (node, name, value) in params {
        options.params.insert((node.to_string(), name.to_string()), *value);
    }
    let plan = compile_with(&cfg.root.join("graph/hybrid_denoised.ron"), &project, cfg.size, &options)?;
    Executor::new(gpu, plan, scene)
}

/// Resource `name` of the executor's plan after its last frame, with the geometry mask.
fn read(gpu: &Gpu, exec: &Executor, name: &str) -> Result<Signal, RuntimeError> {
    let find = |n: &str| exec.plan().resource_by_name(n).ok_or_else(|| RuntimeError::Gpu(format!("graph/hybrid_denoised.ron has no resource {n}")));
    let (_, _, values) = exec.read_texture_f32(gpu, find(name)?)?;
    let (_, _, positions) = exec.read_texture_f32(gpu, find("gbuffer.position")?)?;
    Ok(Signal { values, geometry: positions.iter().map(|p| p[3] != 0.0).collect() })
}

/// The converged reference of `effect` at `camera`: the running mean of its noisy signal over
/// `reference_frames` frames at the most rays, in 32-bit floats (`Effect::reference`).
fn reference(gpu: &Gpu, cfg: &FiltersConfig, scene: &Scene, effect: &Effect, camera: &Camera) -> Result<Signal, RuntimeError> {
    let rays = *effect.ray_counts(cfg).iter().max().unwrap_or(&1);
    let frames = cfg.reference_frames.max(1) as i64;
    let mut params = effect.rays_params(rays);
    params.push((effect.filters[0], "max_history", ParamValue::Int(frames)));
    params.push((effect.filters[0], "variance_clamp", ParamValue::Bool(false)));
    let mut exec = executor(gpu, cfg, scene, effect, &[effect.filters[1]], &params)?;
    for _ in 0..frames {
        exec.render(gpu, camera, scene)?;
    }
    read(gpu, &exec, effect.reference)
}

/// (relMSE, ꟻLIP mean) of `test` against `reference` over the pixels where both show geometry
/// (NaN where there are none).
fn compare(test: &Signal, reference: &Signal, size: (u32, u32), hdr: bool) -> (f64, f64) {
    let mut sum = 0.0;
    let mut n = 0usize;
    for ((t, r), (gt, gr)) in test.values.iter().zip(&reference.values).zip(test.geometry.iter().zip(&reference.geometry)) {
        if *gt && *gr {
            sum += (0..3).map(|c| (t[c] as f64 - r[c] as f64).powi(2) / ((r[c] as f64).powi(2) + 1e-2)).sum::<f64>() / 3.0;
            n += 1;
        }
    }
    if n == 0 {
        return (f64::NAN, f64::NAN); // nothing to compare: shown as "—", never as no error
    }
    (sum / n as f64, flip_between(test, reference, size, hdr))
}

/// ꟻLIP mean between two signals shown as LDR images (background pixels black in both).
fn flip_between(a: &Signal, b: &Signal, (w, h): (u32, u32), hdr: bool) -> f64 {
    let mask: Vec<bool> = a.geometry.iter().zip(&b.geometry).map(|(x, y)| *x && *y).collect();
    let show = |s: &Signal| -> image::RgbaImage {
        let c = |x: f32, on: bool| {
            let x = if hdr { x.max(0.0) / (1.0 + x.max(0.0)) } else { x.clamp(0.0, 1.0) };
            if on {
                (crate::util::linear_to_srgb(x as f64) * 255.0).round() as u8
            } else {
                0
            }
        };
        let rgba = s.values.iter().zip(&mask).flat_map(|(v, on)| [c(v[0], *on), c(v[1], *on), c(v[2], *on), 255]).collect();
        image::RgbaImage::from_raw(w, h, rgba).expect("a texel per pixel")
    };
    super::modes::flip_mean(&show(b), &show(a)) as f64
}

/// The rows of one scene and effect: noisy and filtered at every ray count.
fn effect_rows(gpu: &Gpu, cfg: &FiltersConfig, scene: &Scene, scene_name: &str, effect: &Effect, reference: &Signal) -> Result<Vec<FilterRow>, RuntimeError> {
    let mut rows = Vec::new();
    let camera = *scene.camera();
    let median = crate::runtime::profiler::median;
    let with_filters: Vec<&str> = [effect.node, "motion"].into_iter().chain(effect.filters.iter().copied()).collect();
    for n in effect.ray_counts(cfg) {
        let rays = effect.rays_params(n);
        let row =
            |filtered_frames, ms, (relmse, flip)| FilterRow { scene: scene_name.to_string(), effect: effect.label, rays: n, filtered_frames, ms, relmse, flip };
        // The filtered run times both: the trace pass alone (the noisy signal's cost) and with
        // the filters and the motion pass, over the same frames.
        let mut filtered = executor(gpu, cfg, scene, effect, &[], &rays)?;
        crate::runtime::warm_up::WarmUp::for_gpu(gpu, 1).run(gpu, &mut filtered, scene, &camera)?;
        filtered.camera_cut(); // the history starts again at the first measured frame
        let (mut trace_ms, mut all_ms, mut errors) = (Vec::new(), Vec::new(), Vec::new());
        for frame_no in 1..=cfg.settle_frames.max(1) {
            let frame = filtered.render(gpu, &camera, scene)?;
            trace_ms.push(super::nodes_ms(&filtered, &frame, &[effect.node]));
            all_ms.push(super::nodes_ms(&filtered, &frame, &with_filters));
            if frame_no == 1 || frame_no == cfg.settle_frames {
                errors.push((frame_no, compare(&read(gpu, &filtered, effect.filtered)?, reference, cfg.size, effect.hdr)));
            }
        }
        drop(filtered);
        // The noisy signal: one frame with the filters switched off (new samples every frame,
        // so any frame is as good as another).
        let mut noisy = executor(gpu, cfg, scene, effect, effect.filters, &rays)?;
        noisy.render(gpu, &camera, scene)?;
        rows.push(row(0, median(&mut trace_ms), compare(&read(gpu, &noisy, effect.signal)?, reference, cfg.size, effect.hdr)));
        let filtered_ms = median(&mut all_ms);
        rows.extend(errors.into_iter().map(|(frames, e)| row(frames, filtered_ms, e)));
    }
    Ok(rows)
}

/// `camera` turned about its position by `degrees` around the up axis.
fn turned(camera: &Camera, degrees: f32) -> Camera {
    let rotation = glam::Mat3::from_axis_angle(camera.up.normalize(), degrees.to_radians());
    Camera { target: camera.position + rotation * (camera.target - camera.position), ..*camera }
}

/// Degrees per frame of the track's turn: 40% of the horizontal field of view over
/// `turn_frames` frames.
fn turn_step(cfg: &FiltersConfig, camera: &Camera) -> f32 {
    let aspect = cfg.size.0 as f32 / cfg.size.1 as f32;
    let horizontal = 2.0 * ((camera.fov_y * 0.5).tan() * aspect).atan();
    0.4 * horizontal.to_degrees() / cfg.turn_frames.max(1) as f32
}

/// The track for one effect, noisy or filtered: a still stretch, a fast turn, a stop.
fn track_row(
    gpu: &Gpu,
    cfg: &FiltersConfig,
    scene: &Scene,
    scene_name: &str,
    effect: &Effect,
    references: (&Signal, &Signal),
    filtered: bool,
) -> Result<TrackRow, RuntimeError> {
    let off: &[&str] = if filtered { &[] } else { effect.filters };
    let mut exec = executor(gpu, cfg, scene, effect, off, &[])?;
    let signal = if filtered { effect.filtered } else { effect.signal };
    let camera = *scene.camera();
    for _ in 0..cfg.settle_frames {
        exec.render(gpu, &camera, scene)?;
    }
    let mut previous: Option<Signal> = None;
    let mut flicker = Vec::new();
    for _ in 0..cfg.still_frames.max(2) {
        exec.render(gpu, &camera, scene)?;
        let now = read(gpu, &exec, signal)?;
        if let Some(p) = &previous {
            flicker.push(flip_between(&now, p, cfg.size, effect.hdr));
        }
        previous = Some(now);
    }
    let still_error = compare(previous.as_ref().expect("two or more still frames"), references.0, cfg.size, effect.hdr).1;
    let degrees = turn_step(cfg, &camera);
    for i in 1..=cfg.turn_frames {
        exec.render(gpu, &turned(&camera, degrees * i as f32), scene)?;
    }
    let end = turned(&camera, degrees * cfg.turn_frames as f32);
    let mut after_turn = [0.0; 4];
    for frame_no in 1..=8u32 {
        exec.render(gpu, &end, scene)?;
        if let Some(slot) = [1, 2, 4, 8].iter().position(|f| *f == frame_no) {
            after_turn[slot] = compare(&read(gpu, &exec, signal)?, references.1, cfg.size, effect.hdr).1;
        }
    }
    let flicker = flicker.iter().sum::<f64>() / flicker.len().max(1) as f64;
    Ok(TrackRow { scene: scene_name.to_string(), effect: effect.label, filtered, flicker, still_error, after_turn })
}

/// Runs the part; `on_rows` sees the rows finished so far.
pub fn run(
    gpu: &Gpu,
    cfg: &FiltersConfig,
    mut progress: impl FnMut(usize, usize, &str),
    mut on_rows: impl FnMut(&[FilterRow], &[TrackRow]),
) -> Result<(Vec<FilterRow>, Vec<TrackRow>), RuntimeError> {
    let (mut rows, mut track) = (Vec::new(), Vec::new());
    let total = cfg.scenes.len() * EFFECTS.len();
    for scene_name in &cfg.scenes {
        let (scene, _) = crate::scene::open(scene_name, &crate::scene::LoadOptions::default())?;
        for effect in &EFFECTS {
            let reference_still = reference(gpu, cfg, &scene, effect, scene.camera())?;
            rows.extend(effect_rows(gpu, cfg, &scene, scene_name, effect, &reference_still)?);
            let end = turned(scene.camera(), turn_step(cfg, scene.camera()) * cfg.turn_frames as f32);
            let reference_end = reference(gpu, cfg, &scene, effect, &end)?;
            for filtered in [false, true] {
                track.push(track_row(gpu, cfg, &scene, scene_name, effect, (&reference_still, &reference_end), filtered)?);
            }
            on_rows(&rows, &track);
            progress(track.len() / 2, total, &format!("{scene_name}: {}", effect.label));
        }
    }
    Ok((rows, track))
}

/// The rows as CSV, with the run's header.
pub fn csv(info: &RunInfo, rows: &[FilterRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,effect,rays,filtered_frames,ms,relmse,flip_mean\n");
    for r in rows {
        let _ = writeln!(s, "{},{},{},{},{:.5},{:.6},{:.5}", r.scene, r.effect, r.rays, r.filtered_frames, r.ms, r.relmse, r.flip);
    }
    s
}

/// The track's rows as CSV, with the run's header.
pub fn track_csv(info: &RunInfo, rows: &[TrackRow]) -> String {
    let mut s = info.csv_comment();
    s.push_str("scene,effect,filtered,flicker_flip,still_flip,after_turn_1,after_turn_2,after_turn_4,after_turn_8\n");
    for r in rows {
        let a = r.after_turn;
        let _ = writeln!(s, "{},{},{},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5}", r.scene, r.effect, r.filtered, r.flicker, r.still_error, a[0], a[1], a[2], a[3]);
    }
    s
}

/// A ꟻLIP figure for a table; "—" where nothing was compared.
fn cell(x: f64) -> String {
    if x.is_nan() {
        "—".into()
    } else {
        format!("{x:.4}")
    }
}

fn describe(filtered_frames: u32) -> String {
    match filtered_frames {
        0 => "noisy".into(),
        1 => "filtered, 1st frame".into(),
        n => format!("filtered, {n} frames"),
    }
}

/// The rows as markdown: error against time, the equal-time table and the track.
pub fn markdown(info: &RunInfo, cfg: &FiltersConfig, rows: &[FilterRow], track: &[TrackRow]) -> String {
    let mut s = format!("# bench error: AO, soft shadows, GI and reflections, noisy and filtered, against converged references\n\n{}\n", info.markdown());
    let _ = writeln!(
        s,
        "`graph/hybrid_denoised.ron`; reference: {} frames accumulated at {} rays/pixel without the spatial filter; back-end {}.\n",
        cfg.reference_frames,
        cfg.rays.iter().max().unwrap_or(&1),
        cfg.backend
    );
    s.push_str("| scene | effect | rays/pixel | signal | GPU ms | relMSE | ꟻLIP mean |\n| --- | --- | ---: | --- | ---: | ---: | ---: |\n");
    for r in rows {
        let _ = writeln!(s, "| {} | {} | {} | {} | {:.3} | {:.5} | {:.4} |", r.scene, r.effect, r.rays, describe(r.filtered_frames), r.ms, r.relmse, r.flip);
    }
    s.push_str("\nEqual time: for each noisy row's GPU time, the lowest ꟻLIP mean of a filtered row (after the still frames) that costs no more:\n\n| scene | effect | budget ms (noisy rays) | noisy ꟻLIP | filtered within budget |\n| --- | --- | ---: | ---: | --- |\n");
    for noisy in rows.iter().filter(|r| r.filtered_frames == 0) {
        let best = rows
            .iter()
            .filter(|r| r.scene == noisy.scene && r.effect == noisy.effect && r.filtered_frames > 1 && r.ms <= noisy.ms)
            .min_by(|a, b| a.flip.total_cmp(&b.flip))
            .map(|r| format!("{:.4} ({} rays, {:.3} ms)", r.flip, r.rays, r.ms))
            .unwrap_or_else(|| "none fits".into());
        let _ = writeln!(s, "| {} | {} | {:.3} ({}) | {:.4} | {best} |", noisy.scene, noisy.effect, noisy.ms, noisy.rays, noisy.flip);
    }
    let _ = writeln!(
        s,
        "\nCamera track (the graph's own ray counts): ꟻLIP between consecutive frames of a still stretch of {} frames (flicker), against the reference at its end, and against the reference at the new view 1, 2, 4 and 8 frames after a turn in place of 40% of the horizontal field of view in {} frames (ghosting):\n",
        cfg.still_frames, cfg.turn_frames
    );
    s.push_str("| scene | effect | signal | flicker | still error | +1 | +2 | +4 | +8 |\n| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in track {
        let a = r.after_turn;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.scene,
            r.effect,
            if r.filtered { "filtered" } else { "noisy" },
            cell(r.flicker),
            cell(r.still_error),
            cell(a[0]),
            cell(a[1]),
            cell(a[2]),
            cell(a[3])
        );
    }
    s
}
