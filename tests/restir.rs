//! ReSTIR DI (layers/restir_di.ron, graph/hybrid_restir.ron) against the sum over every light
//! with its own shadow ray (graph/hybrid.ron's `rt_shadow`), and against one light picked by
//! resampling from as many candidates without reuse (`rt_shadow`'s `light_candidates`).

mod common;

use common::gpu;
use common::lights::sixteen_lights;
use raygraph::graph::compile::compile_with;
use raygraph::graph::desc::ParamValue;
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::Scene;

const SIZE: (u32, u32) = (48, 32);

/// `graph` compiled with `params` set, ready for `scene`.
fn executor(gpu: &Gpu, scene: &Scene, graph: &str, params: &[(&str, &str, ParamValue)]) -> Executor {
    let mut options = raygraph::graph::compile::CompileOptions { reuse: false, ..gpu.compile_options_for(gpu.backends()[0]) };
    for (node, name, value) in params {
        options.params.insert((node.to_string(), name.to_string()), value.clone());
    }
    let path = common::repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), SIZE, &options).unwrap();
    Executor::new(gpu, plan, scene).unwrap()
}

/// The `channel` of `graph` over `frames` frames of a still camera, with `params` set.
fn frames_of(gpu: &Gpu, scene: &Scene, graph: &str, params: &[(&str, &str, ParamValue)], channel: &str, frames: usize) -> Vec<Vec<[f32; 4]>> {
    let mut exec = executor(gpu, scene, graph, params);
    (0..frames)
        .map(|_| {
            exec.render(gpu, scene.camera(), scene).unwrap();
            common::channel(gpu, &exec, channel)
        })
        .collect()
}

fn luma(t: &[f32; 4]) -> f64 {
    (0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2]) as f64
}

/// Of `image` against `reference` over the pixels on geometry: the mean luminance's relative
/// difference and the per-pixel RMS difference over the mean.
fn error(image: &[[f32; 4]], reference: &[[f32; 4]]) -> (f64, f64, usize) {
    let (mut sum_ref, mut sum, mut sq, mut n) = (0.0, 0.0, 0.0, 0usize);
    for (a, b) in reference.iter().zip(image) {
        if a[3] == 0.0 {
            continue;
        }
        sum_ref += luma(a);
        sum += luma(b);
        sq += (luma(b) - luma(a)).powi(2);
        n += 1;
    }
    (sum / sum_ref - 1.0, (sq / n as f64).sqrt() / (sum_ref / n as f64), n)
}

fn mean_of(frames: &[Vec<[f32; 4]>]) -> Vec<[f32; 4]> {
    let mut out = vec![[0.0f32; 4]; frames[0].len()];
    for f in frames {
        for (o, t) in out.iter_mut().zip(f) {
            for c in 0..4 {
                o[c] += t[c] / frames.len() as f32;
            }
        }
    }
    out
}

fn mean_per_frame_rms(images: &[Vec<[f32; 4]>], reference: &[[f32; 4]]) -> f64 {
    images.iter().map(|f| error(f, reference).1).sum::<f64>() / images.len() as f64
}

/// Sixteen coloured lights and a dim sun over a floor and a block, a still camera: the direct
/// light of ReSTIR DI (8 candidates a pixel, temporal and spatial reuse), of its spatial reuse
/// alone, and of one light picked by resampling from 8 candidates with no reuse, against every
/// light with its own shadow ray. The test frame is 48 pixels wide, so the neighbours lie
/// within 4 pixels (the default 30 would span most of it).
#[test]
fn restir_is_less_noisy_than_resampling_alone_and_close_to_every_light() {
    let gpu = gpu();
    let scene = sixteen_lights();
    let every = frames_of(&gpu, &scene, "graph/hybrid.ron", &[], "shadow.direct", 1).remove(0);
    let frames = 24;
    let radius = ("direct", "spatial_radius", ParamValue::Float(4.0));
    let restir = frames_of(&gpu, &scene, "graph/hybrid_restir.ron", &[radius.clone()], "direct.direct", frames);
    let spatial_only = [("direct", "temporal", ParamValue::Bool(false)), radius.clone()];
    let spatial_only = frames_of(&gpu, &scene, "graph/hybrid_restir.ron", &spatial_only, "direct.direct", frames);
    let unseen = [("direct", "visibility_reuse", ParamValue::Bool(false)), radius];
    let unseen = frames_of(&gpu, &scene, "graph/hybrid_restir.ron", &unseen, "direct.direct", frames);
    let plain = [("shadow", "light_candidates", ParamValue::Int(8)), ("shadow", "per_frame", ParamValue::Bool(true))];
    let plain = frames_of(&gpu, &scene, "graph/hybrid.ron", &plain, "shadow.direct", frames);
    // Frames 9-24: the reservoirs' history has settled (its M cap is 20 frames' candidates).
    let settled = 8..frames;
    let mut noise = Vec::new();
    let mut bias = Vec::new();
    for (name, images) in
        [("ReSTIR DI", &restir), ("spatial reuse alone", &spatial_only), ("ReSTIR DI without visibility reuse", &unseen), ("resampling alone", &plain)]
    {
        let rms = mean_per_frame_rms(&images[settled.clone()], &every);
        let (mean_bias, rms_of_mean, n) = error(&mean_of(&images[settled.clone()]), &every);
        println!("{name}: one frame's per-pixel RMS {rms:.3} of the mean (first frame {:.3}); the mean of frames 9-24 {:+.3}% in luminance, its RMS {rms_of_mean:.3}; {n} pixels", error(&images[0], &every).1, 100.0 * mean_bias);
        assert!(n > (SIZE.0 * SIZE.1) as usize / 2, "{n} pixels");
        noise.push(rms);
        bias.push(mean_bias);
    }
    // Measured on lavapipe (Mesa 25.0.7), 2026-11-30: one frame's RMS 0.281 (ReSTIR DI), 0.488
    // (spatial reuse alone), 0.290 (without visibility reuse), 0.903 (resampling alone); the
    // means +0.27%, -0.82%, +0.58% and +0.61%. Bounds: ReSTIR DI at most half as noisy as
    // resampling alone (3.2x less measured), its spatial reuse alone at most 0.7 of it (0.54
    // measured). The means of one run wander with its seed: the reservoirs carry samples over
    // frames and neighbours, so their errors do not average out over a still camera's frames
    // (frames 9-64 with seeds 1, 2, 3: -2.04%, -5.21%, -2.27%, and without visibility reuse
    // -0.62%, -3.78%, -1.50%: a lean of a percent or two below, the biased variant's, within a
    // wander of +-2%); the bound, 8%, is 1.5x the largest. The tight check of the mean is
    // tests/emissive_lights.rs's closed form.
    assert!(noise[0] < 0.5 * noise[3], "ReSTIR DI {} against resampling alone {}", noise[0], noise[3]);
    assert!(noise[1] < 0.7 * noise[3], "spatial reuse alone {} against resampling alone {}", noise[1], noise[3]);
    assert!(bias[0].abs() < 0.08, "ReSTIR DI's mean {} off", bias[0]);
    assert!(bias[2].abs() < 0.08, "without visibility reuse, the mean {} off", bias[2]);
}

/// `channel` of `graph` (with `params`) at each camera of `cameras`, one frame each.
fn track_of(
    gpu: &Gpu,
    scene: &Scene,
    graph: &str,
    params: &[(&str, &str, ParamValue)],
    channel: &str,
    cameras: &[raygraph::scene::Camera],
) -> Vec<Vec<[f32; 4]>> {
    let mut exec = executor(gpu, scene, graph, params);
    cameras
        .iter()
        .map(|camera| {
            exec.render(gpu, camera, scene).unwrap();
            common::channel(gpu, &exec, channel)
        })
        .collect()
}

/// On a camera that moves (8 still frames, then 16 frames sliding sideways by 2% of its
/// distance to its target a frame), the reservoirs follow their surfaces through the motion
/// vectors: every moving frame of ReSTIR DI stays at most half as noisy as resampling from as
/// many candidates without reuse, and finite.
#[test]
fn restir_follows_a_moving_camera() {
    let gpu = gpu();
    let scene = sixteen_lights();
    let start = *scene.camera();
    let side = (start.target - start.position).cross(start.up).normalize() * (start.target - start.position).length() * 0.02;
    let cameras: Vec<_> = (0..24u32)
        .map(|i| {
            let mut c = start;
            let shift = side * i.saturating_sub(8) as f32;
            c.position += shift;
            c.target += shift;
            c
        })
        .collect();
    let radius = [("direct", "spatial_radius", ParamValue::Float(4.0))];
    let restir = track_of(&gpu, &scene, "graph/hybrid_restir.ron", &radius, "direct.direct", &cameras);
    let plain = [("shadow", "light_candidates", ParamValue::Int(8)), ("shadow", "per_frame", ParamValue::Bool(true))];
    let plain = track_of(&gpu, &scene, "graph/hybrid.ron", &plain, "shadow.direct", &cameras);
    let every = track_of(&gpu, &scene, "graph/hybrid.ron", &[], "shadow.direct", &cameras);
    let mut worst: f64 = 0.0;
    for k in 9..24 {
        let (r, p) = (error(&restir[k], &every[k]).1, error(&plain[k], &every[k]).1);
        println!("frame {k}: per-pixel RMS {r:.3} (ReSTIR DI) against {p:.3} (resampling alone)");
        assert!(restir[k].iter().all(|t| t.iter().all(|v| v.is_finite())), "frame {k}: a texel not finite");
        worst = worst.max(r / p);
    }
    // Measured on lavapipe (Mesa 25.0.7), 2026-11-30: ReSTIR DI 0.241-0.321 of the mean on the
    // moving frames, resampling alone 0.859-1.142; the largest ratio 0.366. Bound: 0.5, under
    // what spatial reuse alone gives on a still camera (0.488 / 0.903 = 0.54 in the test above):
    // a temporal reuse lost or misled by the motion shows.
    println!("largest ratio {worst:.3}");
    assert!(worst < 0.5, "a moving frame of ReSTIR DI is {worst} times as noisy as resampling alone");
}
