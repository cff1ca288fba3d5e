//! Many lights: the built-in `atrium-lights` scene, and `light_candidates` (one light picked by
//! resampled importance sampling stands for all of them: `rt_shadow` at every pixel,
//! `rt_reflection` at its hits) against the sum over every light with its own shadow ray.

mod common;

use common::gpu;
use common::lights::sixteen_lights;
use raygraph::graph::compile::compile_with;
use raygraph::graph::desc::ParamValue;
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::gltf_import::LoadOptions;
use raygraph::scene::{LightKind, Scene};

const SIZE: (u32, u32) = (48, 32);
const FRAMES: usize = 64;

#[test]
fn the_atrium_at_night_has_a_thousand_lights_and_glowing_lanterns() {
    let (s, _) = raygraph::scene::open("atrium-lights", &LoadOptions { textures: false, ..Default::default() }).unwrap();
    let (day, _) = raygraph::scene::open("atrium", &LoadOptions { textures: false, ..Default::default() }).unwrap();
    assert_eq!(s.lights().len(), raygraph::scene::procedural::ATRIUM_LIGHT_COUNT);
    assert_eq!(s.triangle_count(), day.triangle_count(), "the atrium's geometry");
    let bounds = day.bounds();
    for l in s.lights() {
        assert!(matches!(l.kind, LightKind::Point { range: Some(_) }) && l.intensity > 0.0, "{}", l.name);
        assert!(l.position.cmpge(bounds.min).all() && l.position.cmple(bounds.max).all(), "{} at {} outside the atrium", l.name, l.position);
    }
    assert_eq!(s.effective_lights().len(), s.lights().len(), "the sun is off: only the file's lights");
    let table = raygraph::scene::emitters::emitter_table(&s);
    let glowing = s.instances().iter().filter(|i| s.materials()[i.material].emissive.iter().any(|e| *e > 0.0)).count();
    println!("{} lights, {} emitting triangles on {glowing} lanterns", s.lights().len(), table[0]);
    assert_eq!(glowing, 20, "the twenty lanterns glow");
    assert!(table[0] > 1000, "their triangles are lights: {}", table[0]);
    let info = raygraph::scene::info::describe(&s, None);
    assert!(info.contains("1024 from the file: light 0 (point),") && info.contains(" and 1016 more"), "scene info names a few lights: {info}");
}

/// `resolve.hdr` of graph/hybrid.ron averaged over `frames` frames, with `light_candidates` in
/// the shadow pass and at the reflection rays' hits (new picks every frame; mirror reflections,
/// so that nothing else varies between frames).
fn mean_image(gpu: &Gpu, scene: &Scene, light_candidates: i64, frames: usize) -> (Vec<[f32; 4]>, usize) {
    let mut options = raygraph::graph::compile::CompileOptions { reuse: false, ..gpu.compile_options_for(gpu.backends()[0]) };
    options.params.insert(("shadow".into(), "light_candidates".into()), ParamValue::Int(light_candidates));
    options.params.insert(("shadow".into(), "per_frame".into()), ParamValue::Bool(true));
    options.params.insert(("reflection".into(), "light_candidates".into()), ParamValue::Int(light_candidates));
    options.params.insert(("reflection".into(), "per_frame".into()), ParamValue::Bool(true));
    options.params.insert(("reflection".into(), "glossy".into()), ParamValue::Bool(false));
    let path = common::repo().join("graph/hybrid.ron");
    let plan = compile_with(&path, &Project::beside_graph(&path), SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    let mut sum = vec![[0.0f32; 4]; (SIZE.0 * SIZE.1) as usize];
    for _ in 0..frames {
        exec.render(gpu, scene.camera(), scene).unwrap();
        for (acc, t) in sum.iter_mut().zip(common::channel(gpu, &exec, "resolve.hdr")) {
            for c in 0..4 {
                acc[c] += t[c] / frames as f32;
            }
        }
    }
    let reflecting = common::channel(gpu, &exec, "reflection.reflection").iter().filter(|r| r[3] > 0.0).count();
    (sum, reflecting)
}

#[test]
fn one_light_picked_by_resampling_converges_to_the_sum_over_every_light() {
    let gpu = gpu();
    let scene = sixteen_lights();
    let (every, reflecting) = mean_image(&gpu, &scene, 0, 1);
    assert!(reflecting > (SIZE.0 * SIZE.1) as usize / 2, "reflection rays at {reflecting} pixels");
    let luma = |t: &[f32; 4]| 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
    // Measured on lavapipe (Mesa 25.0.7), 2026-11-30, 64 frames: 1 candidate (a light drawn
    // uniformly) mean +0.86%, per-pixel RMS 0.25 of the mean; 8 candidates +0.03%, 0.099. Bounds:
    // the mean within four standard errors (the RMS over the square root of the pixel count,
    // as if pixels were independent: 0.6% and 0.25%), the RMS 3x the measured, and resampling
    // from 8 at most half as noisy as from 1.
    let mut noise = Vec::new();
    for (candidates, max_rms) in [(1, 0.72), (8, 0.28)] {
        let (sampled, _) = mean_image(&gpu, &scene, candidates, FRAMES);
        let (mut sum_every, mut sum_sampled, mut sq, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
        for (a, b) in every.iter().zip(&sampled) {
            if a[3] == 0.0 {
                continue;
            }
            sum_every += luma(a) as f64;
            sum_sampled += luma(b) as f64;
            sq += ((luma(b) - luma(a)) as f64).powi(2);
            n += 1;
        }
        let (bias, rmse) = (sum_sampled / sum_every - 1.0, (sq / n as f64).sqrt() / (sum_every / n as f64));
        println!("{candidates} candidates, {FRAMES} frames: mean luminance {:+.4}% against every light's, per-pixel RMS {:.4} of the mean", 100.0 * bias, rmse);
        assert!(n > (SIZE.0 * SIZE.1) as usize / 2, "{n} pixels");
        assert!(bias.abs() < 4.0 * rmse / (n as f64).sqrt(), "{candidates} candidates: the mean is {bias} off");
        assert!(rmse < max_rms, "{candidates} candidates: per-pixel RMS {rmse} of the mean");
        noise.push(rmse);
    }
    assert!(noise[1] < 0.5 * noise[0], "resampling from 8 candidates: {} against {}", noise[1], noise[0]);
}
