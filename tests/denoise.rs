//! Temporal accumulation (`layers/temporal.ron`) against a closed form: a floor under a
//! parallel ceiling at h = 0.5 with AO rays of length R = 1 is unoccluded in a fraction
//! (h/R)^2 = 0.25 of cosine-weighted directions at every point. With 8 white-noise rays a
//! frame (`per_frame`: new samples every frame) one frame's estimate has a standard deviation
//! sigma = sqrt(0.25 x 0.75 / 8) = 0.153 per pixel; the accumulated mean over F frames must
//! come to sigma / sqrt(F) around 0.25, unbiased.

mod common;

use common::{gpu, TempProject};
use raygraph::runtime::Executor;

const W: u32 = 64;
const H: u32 = 48;
const RAYS: f64 = 8.0;
const EXPECTED: f64 = 0.25;

const SHOW_LAYER: &str = r#"Layer(
    inputs: {"value": Texture(format: Rgba16Float)},
    outputs: {"color": Texture(format: Rgba8Unorm)},
    passes: [Pass(name: "show", kind: Compute, shader: "test/show_value.wgsl", reads: ["value"], writes: ["color"])],
)
"#;

const SHOW_WGSL: &str = r#"@group(0) @binding(0) var value: texture_2d<f32>;
@group(0) @binding(1) var color: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(color, id.xy, vec4<f32>(textureLoad(value, id.xy, 0).rgb, 1.0));
}
"#;

const GRAPH: &str = r#"Graph(output: "show.color", nodes: {
    "accel": Accel(),
    "gbuffer": Layer(layer: "deferred"),
    "motion": Layer(layer: "motion", inputs: {"position": "gbuffer.position"}),
    "ao": Layer(
        layer: "rt_ao",
        inputs: {"position": "gbuffer.position", "geo_normal": "gbuffer.geo_normal", "tlas": "accel.tlas"},
        params: {"rays": 8, "range": 1.0, "range_scale": 0.0, "sampling": 0, "per_frame": true},
    ),
    "ao_temporal": Layer(layer: "temporal", inputs: {"signal": "ao.ao", "motion": "motion.motion"}, params: {"max_history": 2048, "variance_clamp": false}),
    "show": Layer(layer: "show_value", inputs: {"value": "ao_temporal.accumulated"}),
})"#;

/// (mean over pixels, RMS error against the closed form) of resource `name`'s red channel.
fn stats(values: &[[f32; 4]]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().map(|v| v[0] as f64).sum::<f64>() / n;
    let rms = (values.iter().map(|v| (v[0] as f64 - EXPECTED).powi(2)).sum::<f64>() / n).sqrt();
    (mean, rms)
}

/// An executor of `graph` (with the `show_value` layer) over `scene` at W x H.
fn ceiling_executor(gpu: &raygraph::runtime::Gpu, scene: &raygraph::scene::Scene, graph: &str) -> Executor {
    let p = TempProject::with_repo_files();
    p.write("layers/show_value.ron", SHOW_LAYER);
    p.write("shaders/test/show_value.wgsl", SHOW_WGSL);
    let path = p.write("graph/accumulate.ron", graph);
    let plan = raygraph::graph::compile::compile(&path, &p.project(), (W, H)).unwrap_or_else(|e| panic!("{e}"));
    Executor::new(gpu, plan, scene).unwrap()
}

#[test]
fn accumulating_a_still_frame_converges_to_the_closed_form_ambient_occlusion() {
    let (gpu, scene) = (gpu(), raygraph::bench::error::ceiling_scene());
    let mut exec = ceiling_executor(&gpu, &scene, GRAPH);
    let sigma = (EXPECTED * (1.0 - EXPECTED) / RAYS).sqrt();
    let mut rows = Vec::new();
    for frame in 1..=64u32 {
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        if frame.is_power_of_two() {
            let (mean, rms) = stats(&common::channel(&gpu, &exec, "ao_temporal.accumulated"));
            let (_, single) = stats(&common::channel(&gpu, &exec, "ao.ao"));
            println!(
                "frame {frame:>2}: mean {mean:.4}, RMS error {rms:.4} (sigma/sqrt(F) = {:.4}); this frame alone: RMS {single:.4}",
                sigma / (frame as f64).sqrt()
            );
            rows.push((frame, mean, rms, single));
        }
    }
    for &(frame, mean, rms, single) in &rows {
        let expected_rms = sigma / (frame as f64).sqrt();
        // One frame alone stays at sigma: the samples are new every frame, not accumulated.
        assert!((single / sigma - 1.0).abs() < 0.1, "frame {frame}: one frame's RMS {single} against sigma {sigma}");
        // The accumulated mean: within 15% of sigma / sqrt(F) (3,072 pixels: the RMS itself
        // varies by about 2.5%; the running mean is kept in 32-bit floats and only its output
        // rounded to half floats, 2^-13 at 0.25).
        assert!((rms / expected_rms - 1.0).abs() < 0.15, "frame {frame}: RMS {rms} against sigma/sqrt(F) {expected_rms}");
        // Unbiased: the mean over pixels within 4 standard errors, plus the rounding.
        assert!((mean - EXPECTED).abs() < 4.0 * expected_rms / ((W * H) as f64).sqrt() + 1e-3, "frame {frame}: mean {mean}");
    }
}

/// The accumulation under a moving camera, with the layer's default settings (history of 32
/// frames, variance clamp on): the camera slides over the same closed-form scene at MOTION per
/// frame (about 3.5 pixels), so every pixel's history is reprojected every frame and a strip
/// enters at one edge. Every pixel's expected value is still 0.25. This is GRAPH with the
/// temporal layer's own defaults.
fn moving_graph() -> String {
    let defaults = GRAPH.replace(r#", params: {"max_history": 2048, "variance_clamp": false}"#, "");
    assert_ne!(defaults, GRAPH, "GRAPH sets the temporal layer's parameters");
    defaults
}

/// World units the camera slides along x each frame.
const MOTION: f32 = 0.01;

#[test]
fn under_a_moving_camera_the_accumulated_error_stays_bounded_and_unbiased() {
    let (gpu, scene) = (gpu(), raygraph::bench::error::ceiling_scene());
    let mut exec = ceiling_executor(&gpu, &scene, &moving_graph());
    let sigma = (EXPECTED * (1.0 - EXPECTED) / RAYS).sqrt();
    let mut camera = *scene.camera();
    for frame in 1..=48u32 {
        exec.render(&gpu, &camera, &scene).unwrap();
        camera.position.x += MOTION;
        camera.target.x += MOTION;
        if frame % 16 == 0 {
            let values = common::channel(&gpu, &exec, "ao_temporal.accumulated");
            let moments = common::channel(&gpu, &exec, "ao_temporal.moments");
            // Pixels with at least 8 frames of history (those of the entering strip have fewer).
            let settled: Vec<[f32; 4]> = values.iter().zip(&moments).filter(|(_, m)| m[2] >= 8.0).map(|(v, _)| *v).collect();
            let (mean, rms) = stats(&settled);
            let (_, all_rms) = stats(&values);
            println!(
                "moving, frame {frame}: {} of {} pixels with 8+ frames of history: mean {mean:.4}, RMS {rms:.4} ({:.3} sigma); all pixels RMS {all_rms:.4} ({:.3} sigma)",
                settled.len(),
                values.len(),
                rms / sigma,
                all_rms / sigma
            );
            assert!(settled.len() * 2 > values.len(), "most pixels keep their history under motion: {}", settled.len());
            assert!((mean - EXPECTED).abs() < MOVING_MAX_BIAS, "frame {frame}: mean {mean}, bias {}", mean - EXPECTED);
            assert!(rms < MOVING_MAX_RMS * sigma, "frame {frame}: RMS {rms} against one frame's {sigma}");
            assert!(all_rms < MOVING_MAX_RMS_ALL * sigma, "frame {frame}: all pixels' RMS {all_rms}");
        }
    }
}

/// Bounds of the moving-camera test. Measured on lavapipe (Mesa 25.0.7), 2026-11-29, frames
/// 16, 32 and 48, with the temporal layer's consistent history taps: mean 0.2508-0.2522 (a bias
/// of at most +0.0022: the taps nearer this frame's sample are kept, so the history leans a
/// little towards it); RMS of the pixels with 8+ frames 0.179-0.197 sigma (32 independent
/// frames would give 0.177); all pixels 0.373-0.390 sigma (the entering strip starts at sigma).
/// Bounds: 2x the bias, 1.5-1.7x the RMS values.
const MOVING_MAX_BIAS: f64 = 0.0045;
const MOVING_MAX_RMS: f64 = 0.3;
const MOVING_MAX_RMS_ALL: f64 = 0.68;

/// A layer that writes a constant signal (0.3, 0.6, 0.9) and moments of a settled, noiseless
/// history (10 frames, no variance).
const CONSTANT_LAYER: &str = r#"Layer(
    outputs: {"signal": Texture(format: Rgba16Float), "moments": Texture(format: Rgba32Float)},
    passes: [Pass(name: "fill", kind: Compute, shader: "test/constant.wgsl", writes: ["signal", "moments"])],
)
"#;

/// CONSTANT_LAYER's shader, writing `signal` and `moments` per pixel with `body` (WGSL that sees
/// `id` and `size`).
fn fill_wgsl(body: &str) -> String {
    format!(
        r#"@group(0) @binding(0) var signal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(1) var moments: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let size = textureDimensions(signal);
    if (id.x >= size.x || id.y >= size.y) {{
        return;
    }}
{body}
}}
"#
    )
}

/// The constant signal (0.3, 0.6, 0.9) and a settled, noiseless history (10 frames).
const CONSTANT_FILL: &str = "    textureStore(signal, id.xy, vec4<f32>(0.3, 0.6, 0.9, 1.0));
    textureStore(moments, id.xy, vec4<f32>(0.5, 0.25, 10.0, 0.0));";

/// One frame of `atrous` over the default scene's G-buffer, filtering the signal and moments
/// that `fill_wgsl` writes (`CONSTANT_LAYER`'s interface): the filtered texels and the
/// G-buffer positions.
fn filter_once(fill_wgsl: &str) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
    filter_once_with(fill_wgsl, "{}")
}

/// [`filter_once`] with the `atrous` node's `params` (RON, as a graph file writes them).
fn filter_once_with(fill_wgsl: &str, params: &str) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
    let gpu = gpu();
    let p = TempProject::with_repo_files();
    p.write("layers/show_value.ron", SHOW_LAYER);
    p.write("shaders/test/show_value.wgsl", SHOW_WGSL);
    p.write("layers/constant.ron", CONSTANT_LAYER);
    p.write("shaders/test/constant.wgsl", fill_wgsl);
    let graph = r#"Graph(output: "show.color", nodes: {
    "gbuffer": Layer(layer: "deferred"),
    "constant": Layer(layer: "constant"),
    "filter": Layer(layer: "atrous", inputs: {"signal": "constant.signal", "moments": "constant.moments", "position": "gbuffer.position", "normal": "gbuffer.normal"}, params: PARAMS),
    "show": Layer(layer: "show_value", inputs: {"value": "filter.filtered"}),
})"#;
    let path = p.write("graph/constant.ron", &graph.replace("PARAMS", params));
    let plan = raygraph::graph::compile::compile(&path, &p.project(), (W, H)).unwrap_or_else(|e| panic!("{e}"));
    let scene = raygraph::scene::builtin::default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    (common::channel(&gpu, &exec, "filter.filtered"), common::channel(&gpu, &exec, "gbuffer.position"))
}

/// The à-trous filter (`layers/atrous.ron`: one shader for its four steps, bound through
/// `binding=resource` aliases) keeps a constant image constant over the default scene's
/// edges: its weights are normalised whatever the edge-stopping functions make of them.
#[test]
fn the_atrous_filter_keeps_a_constant_image_constant() {
    let (filtered, _) = filter_once(&fill_wgsl(CONSTANT_FILL));
    // In half-float units in the last place: the signal is stored in half floats six times
    // (the constant itself, packed, and after each step), and a Vulkan implementation may round
    // each store towards zero (lavapipe does: 0.9 comes out as 0.89941, two units low), so up
    // to 6 units.
    let ulp = |c: f32| 2f32.powi(c.log2().floor() as i32 - 10);
    let worst =
        filtered.iter().flat_map(|v| [(v[0] - 0.3).abs() / ulp(0.3), (v[1] - 0.6).abs() / ulp(0.6), (v[2] - 0.9).abs() / ulp(0.9)]).fold(0.0f32, f32::max);
    println!("largest deviation from the constant: {worst} half-float units in the last place");
    assert!(worst <= 6.0, "the filter changed a constant image by {worst} units");
}

/// A hard edge, 0 left of the frame's middle and 1 right of it, with the moments of a single
/// frame (the history a camera motion has just uncovered).
const EDGE_FILL: &str = "    let v = select(0.0, 1.0, 2u * id.x >= size.x);
    textureStore(signal, id.xy, vec4<f32>(v, v, v, 1.0));
    textureStore(moments, id.xy, vec4<f32>(v, v * v, 1.0, 0.0));";

/// Before 4 frames of history the filter takes the variance from the 3x3 neighbourhood
/// ("spatial", the default), which is large across a real edge, so the edge is blurred;
/// "unfiltered" takes it as 0 and leaves every pixel of a two-valued image as it was.
#[test]
fn a_short_history_unfiltered_keeps_a_hard_edge_that_the_spatial_estimate_blurs() {
    let changed = |filtered: &[[f32; 4]], position: &[[f32; 4]]| {
        filtered
            .iter()
            .zip(position)
            .enumerate()
            .filter(|(i, (v, p))| p[3] != 0.0 && (v[0] - if (i % W as usize) * 2 >= W as usize { 1.0 } else { 0.0 }).abs() > 1e-3)
            .count()
    };
    let (spatial, position) = filter_once_with(&fill_wgsl(EDGE_FILL), "{}");
    let (unfiltered, _) = filter_once_with(&fill_wgsl(EDGE_FILL), r#"{"short_history": 1}"#);
    let (blurred, kept) = (changed(&spatial, &position), changed(&unfiltered, &position));
    println!("pixels moved off the edge's two values: spatial {blurred}, unfiltered {kept}");
    assert!(blurred > H as usize, "the spatial estimate blurs the edge ({blurred} pixels changed)");
    assert_eq!(kept, 0, "unfiltered keeps every pixel");
}

/// The filter nodes of `graph/hybrid_denoised.ron` (and `shadow_light`, which puts the filtered
/// shadows back on the light).
const FILTERS: [&str; 9] = [
    "shadow_temporal",
    "shadow_denoise",
    "shadow_light",
    "ao_temporal",
    "ao_denoise",
    "gi_temporal",
    "gi_denoise",
    "reflection_temporal",
    "reflection_denoise",
];

/// Frames of `graph` (a file of the repository) with `off` switched off: the plan's pass
/// names and the output image after `frames` frames.
fn render_switched(graph: &str, off: &[&str], frames: usize) -> (Vec<String>, Vec<u8>) {
    let gpu = gpu();
    let mut options = gpu.compile_options();
    for node in off {
        options.enabled.insert(node.to_string(), false);
    }
    let path = common::repo().join(graph);
    let project = raygraph::graph::compile::Project::beside_graph(&path);
    let plan = raygraph::graph::compile::compile_with(&path, &project, (W, H), &options).unwrap_or_else(|e| panic!("{e}"));
    let passes = plan.passes().iter().map(|p| p.name.clone()).collect();
    let scene = raygraph::scene::builtin::default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    for _ in 0..frames {
        exec.render(&gpu, scene.camera(), &scene).unwrap();
    }
    (passes, exec.read_output(&gpu).unwrap().into_raw())
}

/// Switching a filter off bypasses it (`bypass` in `layers/temporal.ron` and
/// `layers/atrous.ron`): its readers get its input, its passes are culled, and with every
/// filter off the motion pass goes too (nothing reads it) and the image is that of
/// `graph/hybrid_soft_gi.ron` (the same graph without the filters), byte for byte.
#[test]
fn switching_the_filters_off_hands_their_readers_the_noisy_signal() {
    let (noisy_passes, noisy) = render_switched("graph/hybrid_soft_gi.ron", &[], 3);
    let (passes, image) = render_switched("graph/hybrid_denoised.ron", &FILTERS, 3);
    assert_eq!(passes, noisy_passes, "every filter and the motion pass culled");
    assert!(image == noisy, "with the filters off the image is the unfiltered graph's");

    // The spatial filter alone: it reads the raw signal and estimates the variance spatially
    // (its `moments` input falls back to no temporal moments).
    let (passes, spatial) = render_switched("graph/hybrid_denoised.ron", &["shadow_temporal", "ao_temporal", "gi_temporal", "reflection_temporal"], 3);
    assert!(passes.iter().all(|p| !p.contains("temporal") && !p.starts_with("motion/")), "{passes:?}");
    assert!(passes.iter().any(|p| p == "ao_denoise/step8"), "{passes:?}");
    assert!(spatial != noisy, "the spatial filter changed the image");

    // The temporal filter alone.
    let (passes, temporal) = render_switched("graph/hybrid_denoised.ron", &["shadow_denoise", "ao_denoise", "gi_denoise", "reflection_denoise"], 3);
    assert!(passes.iter().all(|p| !p.contains("denoise")), "{passes:?}");
    assert!(passes.iter().any(|p| p == "ao_temporal/accumulate") && passes.iter().any(|p| p.starts_with("motion/")), "{passes:?}");
    assert!(temporal != noisy && temporal != spatial);
}

/// A bypass must join an output to an input of the same format; a bad one is refused with the
/// layer file's name, also while its node is switched off.
#[test]
fn a_bypass_between_different_formats_is_refused() {
    let p = TempProject::with_repo_files();
    p.write(
        "layers/bad_filter.ron",
        r#"Layer(
    inputs: {"signal": Texture(format: Rgba16Float)},
    outputs: {"filtered": Texture(format: Rgba8Unorm)},
    bypass: {"filtered": "signal"},
    passes: [Pass(name: "copy", kind: Compute, shader: "test/copy.wgsl", reads: ["signal"], writes: ["filtered"])],
)
"#,
    );
    for enabled in ["true", "false"] {
        let graph = format!(
            r#"Graph(output: "filter.filtered", nodes: {{
    "gbuffer": Layer(layer: "deferred"),
    "filter": Layer(layer: "bad_filter", enabled: {enabled}, inputs: {{"signal": "gbuffer.emissive"}}),
}})"#
        );
        let e = p.compile("bad_bypass.ron", &graph).expect_err("a bypass across formats");
        let text = e.to_string();
        assert!(text.contains("bad_filter.ron") && text.contains("bypass `filtered` -> `signal`"), "{text}");
    }
}

/// A signal present only on the right half of the frame (alpha 1), the left half without one
/// (alpha 0, as reflections where no ray was traced, and 5.0). Pixels without a signal stay
/// without one through `atrous` (alpha 0, so that the resolve shows the sky there), and the
/// filter leaves their values out of the pixels that have one: the right half stays its
/// constant within the half-float rounding of the test above.
#[test]
fn pixels_without_a_signal_keep_none_and_lend_nothing_to_their_neighbours() {
    let half = CONSTANT_FILL.replace(
        "textureStore(signal, id.xy, vec4<f32>(0.3, 0.6, 0.9, 1.0));",
        "textureStore(signal, id.xy, select(vec4<f32>(5.0, 5.0, 5.0, 0.0), vec4<f32>(0.3, 0.6, 0.9, 1.0), id.x >= size.x / 2u));",
    );
    assert!(half != CONSTANT_FILL);
    let (filtered, position) = filter_once(&fill_wgsl(&half));
    let ulp = |c: f32| 2f32.powi(c.log2().floor() as i32 - 10);
    let (mut left, mut right, mut worst) = (0, 0, 0.0f32);
    for (i, (v, x)) in filtered.iter().zip(&position).enumerate() {
        if x[3] == 0.0 {
            continue; // the sky: passed through as before
        }
        if (i as u32 % W) < W / 2 {
            left += 1;
            assert_eq!(v[3], 0.0, "pixel {i}: no signal stays without one: {v:?}");
        } else {
            right += 1;
            assert_eq!(v[3], 1.0, "pixel {i}: {v:?}");
            worst = worst.max((v[0] - 0.3).abs() / ulp(0.3)).max((v[1] - 0.6).abs() / ulp(0.6)).max((v[2] - 0.9).abs() / ulp(0.9));
        }
    }
    println!("{left} pixels without a signal, {right} with; largest deviation on the right {worst} units");
    assert!(left > 100 && right > 100);
    assert!(worst <= 6.0, "the left half's 5.0 leaked into the right half: {worst} units");
}

/// The shadows of `graph/hybrid_denoised.ron` through a fast turn, made hard (a point sun and
/// point lights: every frame's signal is exact, so the noisy signal is the reference and any
/// difference is the filters' own): the default scene at 64x36, 8 still frames, a turn in place
/// of 40% of the horizontal field of view over 2 frames, then 8 frames at the new view. The
/// filtered direct light (`shadow_light.product`) is compared with this frame's noisy one
/// (`shadow.direct`) over the pixels showing geometry, 1, 2, 4 and 8 frames after the turn.
#[test]
fn after_a_fast_turn_the_filtered_shadows_are_no_worse_than_the_unfiltered_ones() {
    use raygraph::graph::desc::ParamValue;
    let gpu = gpu();
    let scene = raygraph::scene::open("default", &Default::default()).unwrap().0;
    let mut options = gpu.compile_options_for(gpu.backends()[0]);
    options.reuse = false;
    // The other effects of bench error's filter part, and their filters.
    for effect in raygraph::bench::filters::EFFECTS.iter().filter(|e| e.node != "shadow") {
        for node in std::iter::once(effect.node).chain(effect.filters.iter().copied()) {
            options.enabled.insert(node.to_string(), false);
        }
    }
    for name in ["light_radius", "sun_angle"] {
        options.params.insert(("shadow".to_string(), name.to_string()), ParamValue::Float(0.0));
    }
    let path = common::repo().join("graph/hybrid_denoised.ron");
    let project = raygraph::graph::compile::Project::beside_graph(&path);
    let plan = raygraph::graph::compile::compile_with(&path, &project, (64, 36), &options).unwrap_or_else(|e| panic!("{e}"));
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    let camera = *scene.camera();
    let horizontal = 2.0 * ((camera.fov_y * 0.5).tan() * 64.0 / 36.0).atan();
    let turned = |fraction: f32| {
        let rotation = glam::Mat3::from_axis_angle(camera.up.normalize(), 0.4 * horizontal * fraction);
        raygraph::scene::Camera { target: camera.position + rotation * (camera.target - camera.position), ..camera }
    };
    for _ in 0..8 {
        exec.render(&gpu, &camera, &scene).unwrap();
    }
    exec.render(&gpu, &turned(0.5), &scene).unwrap();
    exec.render(&gpu, &turned(1.0), &scene).unwrap();
    for frame in 1..=8 {
        exec.render(&gpu, &turned(1.0), &scene).unwrap();
        if ![1, 2, 4, 8].contains(&frame) {
            continue;
        }
        let filtered = common::channel(&gpu, &exec, "shadow_light.product");
        let noisy = common::channel(&gpu, &exec, "shadow.direct");
        let luminance = |v: &[f32; 4]| 0.2126 * v[0] as f64 + 0.7152 * v[1] as f64 + 0.0722 * v[2] as f64;
        let pairs: Vec<(f64, f64)> = filtered.iter().zip(&noisy).filter(|(_, n)| n[3] > 0.0).map(|(f, n)| (luminance(f), luminance(n))).collect();
        let total: f64 = pairs.iter().map(|(_, n)| n).sum();
        let off: f64 = pairs.iter().map(|(f, n)| (f - n).abs()).sum();
        let wrong = pairs.iter().filter(|(f, n)| (f - n).abs() > 0.05 * n.max(0.05)).count();
        println!(
            "{frame} frame(s) after the turn: {} pixels, mean absolute difference {:.5} of the mean, {wrong} pixels off by more than 5%",
            pairs.len(),
            off / total
        );
        assert!(
            off / total < TURN_MAX_DIFFERENCE,
            "{frame} frame(s) after the turn: the filtered shadows differ from the exact ones by {:.4} of the light",
            off / total
        );
        assert!(wrong <= TURN_MAX_WRONG_PIXELS, "{frame} frame(s) after the turn: {wrong} pixels off by more than 5%");
    }
}

/// Bounds of the turn test. Measured on lavapipe (Mesa 25.0.7), 2026-11-29, 1/2/4/8 frames
/// after the turn: the graph as it is, 0.00043-0.00044 of the light (half-float rounding of
/// the ratio and the light) and no pixel off by 5%. Failing versions, same day: the shadowed
/// light itself filtered (before `rt_shadow`'s `split` and `modulate`) with bilinear history
/// taps, 0.140/0.152/0.138/0.114 and 421-455 pixels; the visibility ratio filtered with
/// bilinear taps (`history_taps: "bilinear"` on `shadow_temporal`), 0.0114/0.0100/0.0080/0.0054
/// and 33-49 pixels. Bounds: 3x the measured difference, and no pixel.
const TURN_MAX_DIFFERENCE: f64 = 0.0015;
const TURN_MAX_WRONG_PIXELS: usize = 0;
