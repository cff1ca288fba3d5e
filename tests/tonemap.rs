//! The tone map (layers/tonemap.ron) against an independent implementation: exposure, the ACES
//! filmic fit (Narkowicz 2015: (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) + 0.14), clamped to
//! [0, 1]), the sRGB transfer function (IEC 61966-2-1) and the sky gradient behind partly
//! covered texels, computed here in f64 from the HDR texels the GPU stored (a ramp over
//! 2^-14..2^7 per channel, alpha 1, 0.5 and 0: tests/fixtures/layers/hdr_pattern.ron).
//!
//! Byte-exact: every channel whose exact value lies more than 0.02 of a step from a rounding
//! boundary (x.5 steps) must be the byte computed here. Nearer a boundary, f32 arithmetic
//! may round either way, so those (counted and printed, a few percent of the texels) must be
//! within one step.

mod common;

use common::{gpu, TempProject};
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::runtime::Executor;
use raygraph::scene::builtin::default_scene;

const SIZE: (u32, u32) = (96, 64);
/// Within this many steps of a rounding boundary, f32 may round either way.
const BOUNDARY: f64 = 0.02;

fn aces(x: f64) -> f64 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

fn srgb_encode(c: f64) -> f64 {
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The sky behind texel row `y`: the gradient from (0.9, 0.85, 0.8) at the bottom to (0.35,
/// 0.55, 0.9) at the top (v = 0 at the top, pixel centres).
fn sky(y: u32, channel: usize) -> f64 {
    let v = (y as f64 + 0.5) / SIZE.1 as f64;
    let (bottom, top) = ([0.9, 0.85, 0.8][channel], [0.35, 0.55, 0.9][channel]);
    bottom + (top - bottom) * (1.0 - v)
}

/// The exact output of one channel in steps of 1/255 (before rounding).
fn expected_steps(hdr: [f32; 4], y: u32, channel: usize, exposure: f64, with_sky: bool) -> f64 {
    let mut linear = hdr[channel] as f64;
    if with_sky && hdr[3] < 1.0 {
        linear += (1.0 - (hdr[3] as f64).max(0.0)) * sky(y, channel);
    }
    srgb_encode(aces(linear * exposure)) * 255.0
}

fn tone_map(exposure: f64, with_sky: bool) -> (Vec<[f32; 4]>, image::RgbaImage) {
    let p = TempProject::with_repo_files();
    let graph = format!(
        r#"Graph(output: "tonemap.color", nodes: {{
            "pattern": Layer(layer: "hdr_pattern"),
            "tonemap": Layer(layer: "tonemap", inputs: {{"hdr": "pattern.hdr"}}, params: {{"exposure": {exposure}, "sky": {with_sky}}}),
        }})"#
    );
    let path = p.write("graph/tonemap_pattern.ron", &graph);
    for f in ["layers/hdr_pattern.ron", "shaders/test/hdr_pattern.wgsl"] {
        p.write(f, &std::fs::read_to_string(common::fixtures().join(f)).unwrap());
    }
    let plan = compile_with(&path, &p.project(), SIZE, &CompileOptions { reuse: false, ..Default::default() }).unwrap();
    let (hdr, color) = (plan.resource_by_name("pattern.hdr").unwrap(), plan.resource_by_name("tonemap.color").unwrap());
    let gpu = gpu();
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    let (_, _, texels) = exec.read_texture_f32(&gpu, hdr).unwrap();
    (texels, exec.read_texture_rgba8(&gpu, color).unwrap())
}

#[test]
fn the_tone_map_matches_aces_and_srgb_computed_independently_byte_for_byte() {
    for (exposure, with_sky) in [(1.0, true), (2.5, true), (0.25, false)] {
        let (hdr, image) = tone_map(exposure, with_sky);
        let (mut exact, mut near_boundary, mut levels) = (0usize, 0usize, std::collections::BTreeSet::new());
        for (i, texel) in hdr.iter().enumerate() {
            let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
            let got = image.get_pixel(x, y).0;
            assert_eq!(got[3], 255, "alpha at ({x}, {y})");
            for c in 0..3 {
                let steps = expected_steps(*texel, y, c, exposure, with_sky);
                let want = steps.round();
                levels.insert(want as u8);
                if (steps.fract() - 0.5).abs() < BOUNDARY {
                    near_boundary += 1;
                    assert!((got[c] as f64 - want).abs() <= 1.0, "({x}, {y}) channel {c}: {} against {steps:.4} steps", got[c]);
                } else {
                    exact += 1;
                    assert_eq!(got[c] as f64, want, "({x}, {y}) channel {c}: hdr {texel:?}, exposure {exposure}, sky {with_sky}: {steps:.4} steps");
                }
            }
        }
        println!("exposure {exposure}, sky {with_sky}: {exact} channels byte-exact, {near_boundary} within {BOUNDARY} of a rounding boundary (within one step), {} output levels", levels.len());
        assert!(levels.len() > 200, "the inputs reach most output levels: {}", levels.len());
        assert!(near_boundary * 20 < exact, "few channels near a boundary: {near_boundary} of {}", exact + near_boundary);
    }
}
