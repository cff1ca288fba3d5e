//! The AO layer's schedules give the same bits: `rt_ao_four_lanes` (four lanes a pixel over the
//! frame), `rt_ao_compacted` (one invocation per (pixel, lane) item of a list of the pixels with
//! rays) and `rt_ao_persistent` (a fixed dispatch taking items off a counter), substituted for
//! `rt_ao` in `graph/ao.ron` (without its `blend` node, which the AO does not feed), on every
//! back-end the adapter has: the AO output and each lane's
//! partial sum bit for bit, with part of the frame covered, none of it (an empty list) and all
//! of it, and on the pine's alpha-tested and BLEND foliage. Two frames each, with the rays each
//! frame traces, so the list's counters are seen zeroed again before the second. `rt_ao` itself
//! (more lanes a pixel where few pixels had rays the frame before) traces the same rays: its AO
//! and lane sums equal the four-lane schedule's bit for bit where it runs four lanes (the first
//! frame, and after a frame at least an eighth covered), and its AO is within the rounding of
//! a sum in another order where it spreads them; which schedule each frame ran follows the
//! coverage of the frame before.

mod common;

use common::{ao_graph_without_blend, channel, gpu};
use glam::Vec3;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::graph::desc::{ParamValue, PassKind};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{AlphaMode, Camera, Scene};

const SIZE: (u32, u32) = (40, 30);
const VARIANTS: [&str; 2] = ["rt_ao_compacted", "rt_ao_persistent"];
const FOUR_LANES: &str = "rt_ao_four_lanes";
const SPREAD: &str = "rt_ao";
/// rt_ao's AO against the four-lane schedule's where it gives a pixel more than four lanes: the
/// same rays summed in another order differ by a few f32 units in the last place, which the
/// Rgba16Float output rounds to at most one of its own (2^-11 below 1).
const SPREAD_TOLERANCE: f32 = 1.0 / 2048.0;

/// What a schedule leaves after its frames: `ao.ao`'s texels, and the lanes' partial sums of
/// the pixels with rays (`ao/partial` is not written over the sky), all as bits; and the rays
/// each frame traced (a list counter not zeroed between frames would trace the last frame's
/// items again).
#[derive(Debug, PartialEq)]
struct AoBits {
    ao: Vec<[u32; 4]>,
    partial: Vec<u32>,
    covered: usize,
    rays: Vec<String>,
}

fn bits(v: [f32; 4]) -> [u32; 4] {
    v.map(f32::to_bits)
}

/// `ao_graph_without_blend` with `rt_ao` compiled from `variant` (itself: no substitution), a
/// frame from each camera.
fn render(gpu: &Gpu, scene: &Scene, cameras: &[Camera], backend: Backend, variant: &str, sampling: i64) -> AoBits {
    render_with_schedules(gpu, scene, cameras, backend, variant, sampling).0
}

/// [`render`], and for each frame the names of the AO node's trace passes it recorded.
fn render_with_schedules(gpu: &Gpu, scene: &Scene, cameras: &[Camera], backend: Backend, variant: &str, sampling: i64) -> (AoBits, Vec<Vec<String>>) {
    let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    if variant != "rt_ao" {
        options.layers.insert("rt_ao".into(), variant.into());
    }
    options.params.insert(("ao".into(), "sampling".into()), ParamValue::Int(sampling));
    let (path, project) = ao_graph_without_blend();
    let plan = compile_with(&path, &project, SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    let (mut rays, mut schedules) = (Vec::new(), Vec::new());
    for camera in cameras {
        let timings = exec.render(gpu, camera, scene).unwrap();
        rays.push(format!("{:?}", timings.rays));
        let passes = exec.plan().passes().iter().zip(&timings.skipped);
        schedules.push(passes.filter(|(p, skipped)| p.kind == PassKind::Trace && p.node == "ao" && !**skipped).map(|(p, _)| p.name.clone()).collect());
    }
    (AoBits { rays, ..read(gpu, &exec) }, schedules)
}

fn read(gpu: &Gpu, exec: &Executor) -> AoBits {
    let position = channel(gpu, exec, "gbuffer.position");
    let partial = channel(gpu, exec, "ao/partial");
    let width = SIZE.0 as usize;
    let mut lanes = Vec::new();
    for (i, p) in position.iter().enumerate() {
        if p[3] != 0.0 {
            let (x, y) = (i % width, i / width);
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                lanes.push(partial[(2 * y + dy) * 2 * width + 2 * x + dx][0].to_bits());
            }
        }
    }
    let covered = position.iter().filter(|p| p[3] != 0.0).count();
    AoBits { ao: channel(gpu, exec, "ao.ao").into_iter().map(bits).collect(), partial: lanes, covered, rays: Vec::new() }
}

/// Every variant equals `rt_ao_four_lanes` bit for bit on every back-end, and traces as many
/// rays each frame, and so does `rt_ao` (`assert_spread_agrees`); returns the four-lane
/// schedule's result on the last back-end, and the AO trace pass `rt_ao` ran in its last
/// frame (the same on every back-end).
fn assert_schedules_agree(scene: &Scene, cameras: &[Camera], sampling: i64, what: &str) -> (AoBits, String) {
    let gpu = gpu();
    let mut last = None;
    let mut last_schedule: Option<Vec<String>> = None;
    for &backend in gpu.backends() {
        let lanes = render(&gpu, scene, cameras, backend, FOUR_LANES, sampling);
        for variant in VARIANTS {
            let other = render(&gpu, scene, cameras, backend, variant, sampling);
            assert_eq!(other.covered, lanes.covered, "{what}, {backend}: {variant} saw other pixels");
            let differing = lanes.ao.iter().zip(&other.ao).filter(|(a, b)| a != b).count();
            assert_eq!(differing, 0, "{what}, {backend}: {variant}'s AO differs from {FOUR_LANES}'s at {differing} pixels");
            assert!(other.partial == lanes.partial, "{what}, {backend}: {variant}'s lane sums differ from {FOUR_LANES}'s");
            assert_eq!(other.rays, lanes.rays, "{what}, {backend}: {variant} traces other rays than {FOUR_LANES}, frame by frame");
        }
        let (spread, schedules) = render_with_schedules(&gpu, scene, cameras, backend, SPREAD, sampling);
        let schedule = schedules.last().cloned().unwrap_or_default();
        assert_spread_agrees(&lanes, &spread, schedule == ["ao/ao"], &format!("{what}, {backend}"));
        assert!(last_schedule.as_ref().is_none_or(|s| *s == schedule), "{what}, {backend}: another schedule than another back-end's: {schedule:?}");
        last_schedule = Some(schedule);
        last = Some(lanes);
    }
    (last.expect("the adapter has a back-end"), last_schedule.unwrap_or_default().join(", "))
}

/// rt_ao (`spread`) against the four-lane schedule (`lanes`): the same pixels and rays each
/// frame; the same AO and lane-sum bits where its last frame ran four lanes, else the AO within
/// [`SPREAD_TOLERANCE`].
fn assert_spread_agrees(lanes: &AoBits, spread: &AoBits, four_lanes: bool, what: &str) {
    assert_eq!(spread.covered, lanes.covered, "{what}: {SPREAD} saw other pixels");
    assert_eq!(spread.rays, lanes.rays, "{what}: {SPREAD} traces other rays than {FOUR_LANES}, frame by frame");
    let worst = lanes.ao.iter().zip(&spread.ao).map(|(a, b)| (f32::from_bits(a[0]) - f32::from_bits(b[0])).abs()).fold(0.0, f32::max);
    if four_lanes {
        assert!(lanes.ao == spread.ao, "{what}: {SPREAD} keeps four lanes, yet its AO differs from {FOUR_LANES}'s (by up to {worst})");
        assert!(lanes.partial == spread.partial, "{what}: {SPREAD} keeps four lanes, yet its lane sums differ from {FOUR_LANES}'s");
    } else {
        assert!(worst <= SPREAD_TOLERANCE, "{what}: {SPREAD}'s AO differs from {FOUR_LANES}'s by {worst}");
    }
}

/// The share of pixels whose AO is below one (something occludes them).
fn occluded_share(r: &AoBits) -> f64 {
    r.ao.iter().filter(|t| f32::from_bits(t[0]) < 1.0).count() as f64 / r.ao.len() as f64
}

#[test]
fn schedules_agree_with_the_sky_in_view() {
    let scene = raygraph::scene::builtin::default_scene();
    for sampling in [0, 1] {
        let (r, _) = assert_schedules_agree(&scene, &[*scene.camera(); 2], sampling, &format!("default scene, sampling {sampling}"));
        let pixels = (SIZE.0 * SIZE.1) as usize;
        assert!(r.covered > pixels / 4 && r.covered < pixels, "part of the frame is covered: {} of {pixels}", r.covered);
        assert!(occluded_share(&r) > 0.05, "the floor by the cube and spheres is occluded: {:.3}", occluded_share(&r));
    }
}

#[test]
fn schedules_agree_with_a_small_model_in_view() {
    // The default scene from far away: under an eighth of the frame covered, so rt_ao spreads
    // each pixel's rays over more than four lanes, with every sampling (white noise draws each
    // lane's numbers from the pixel's one stream; the net gives ray i the point of cell i
    // whatever lane traces it). Measured: 111 of 1,200 pixels, 16 lanes each.
    let scene = raygraph::scene::builtin::default_scene();
    let far = Camera::look(Vec3::new(0.0, 6.0, 40.0), Vec3::new(0.0, 0.5, 0.0), 20.0, 0.1, 200.0);
    for sampling in [0, 1, 2] {
        let (r, schedule) = assert_schedules_agree(&scene, &[far; 2], sampling, &format!("default scene from far, sampling {sampling}"));
        assert_eq!(schedule, "ao/ao_spread", "the second frame spreads the rays");
        let pixels = (SIZE.0 * SIZE.1) as usize;
        assert!(r.covered > 20 && 8 * r.covered < pixels, "a few pixels covered, under an eighth: {} of {pixels}", r.covered);
        assert!(occluded_share(&r) > 0.005, "something occludes them: {:.4}", occluded_share(&r));
    }
}

#[test]
fn schedules_agree_with_nothing_in_view() {
    let scene = raygraph::scene::builtin::default_scene();
    // Up into the sky from above every object: the list is empty (after a frame whose list
    // was not).
    let up = Camera::look(Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, 10.0, 0.5), 50.0, 0.05, 100.0);
    let (r, _) = assert_schedules_agree(&scene, &[*scene.camera(), up], 1, "looking at the sky");
    assert_eq!(r.covered, 0, "no pixel has a surface");
    assert!(r.ao.iter().all(|t| f32::from_bits(t[0]) == 1.0), "the sky's AO is 1");
}

#[test]
fn schedules_agree_with_every_pixel_covered() {
    let scene = raygraph::scene::builtin::default_scene();
    let top = scene.preset("top").unwrap();
    let (r, schedule) = assert_schedules_agree(&scene, &[top; 2], 1, "top view");
    assert_eq!(schedule, "ao/ao", "the second frame runs four lanes");
    assert_eq!(r.covered, (SIZE.0 * SIZE.1) as usize, "the floor fills the frame");
    assert!(occluded_share(&r) > 0.05, "around the cube and spheres the floor is occluded: {:.3}", occluded_share(&r));
}

#[test]
fn schedules_agree_through_alpha_tested_and_blend_foliage() {
    // The BLEND leaf cards are not in the G-buffer: the trunk (from far enough to cover under
    // an eighth of the frame: 220 px of 1,200 from 25 units away were too many), whose AO rays pass
    // through them (transmittance); then the cards cut out at alpha 0.5 (MASK), so that they
    // have AO rays of their own, alpha-tested wherever they meet the atlas.
    let mut scene = common::open("assets/gltf/smallpine/scene.gltf");
    let trunk = Camera::look(Vec3::new(0.0, 12.0, 40.0), Vec3::new(0.0, 12.0, 0.0), 35.0, 0.1, 500.0);
    let (r, schedule) = assert_schedules_agree(&scene, &[trunk; 2], 1, "pine's trunk");
    assert_eq!(schedule, "ao/ao_spread", "the second frame spreads the rays");
    assert!(r.covered > 20 && occluded_share(&r) > 0.01, "the trunk covers pixels, the leaves occlude it: {} px, {:.3}", r.covered, occluded_share(&r));
    // Under an eighth of the frame: the spread schedule gives each pixel more than four lanes.
    assert!(8 * r.covered < (SIZE.0 * SIZE.1) as usize, "the trunk covers under an eighth of the frame: {} px", r.covered);
    for m in scene.materials_mut().iter_mut().filter(|m| m.alpha_mode == AlphaMode::Blend) {
        m.alpha_mode = AlphaMode::Mask(0.5);
    }
    let (r, _) = assert_schedules_agree(&scene, &[*scene.camera(); 2], 1, "pine cut out");
    // Measured: 68 pixels, 0.038 of the frame occluded (most of the tree's pixels).
    assert!(r.covered > 20 && occluded_share(&r) > 0.01, "the cut-out pine covers pixels and occludes itself: {} px, {:.3}", r.covered, occluded_share(&r));
}

#[test]
fn each_frame_runs_the_schedule_the_coverage_of_the_frame_before_picks() {
    // Far (under an eighth of the frame covered), then the top view (all of it), then far again:
    // the first frame has no count yet and runs four lanes; every other frame runs the schedule
    // its predecessor's coverage picks, and traces the four-lane schedule's rays.
    let scene = raygraph::scene::builtin::default_scene();
    let far = Camera::look(Vec3::new(0.0, 6.0, 40.0), Vec3::new(0.0, 0.5, 0.0), 20.0, 0.1, 200.0);
    let top = scene.preset("top").unwrap();
    let cameras = [far, far, top, top, far];
    let (four, spread) = ("ao/ao", "ao/ao_spread");
    let expected = [four, spread, spread, four, four];
    let gpu = gpu();
    for &backend in gpu.backends() {
        let lanes = render(&gpu, &scene, &cameras, backend, FOUR_LANES, 1);
        let (r, schedules) = render_with_schedules(&gpu, &scene, &cameras, backend, SPREAD, 1);
        let expected: Vec<Vec<String>> = expected.iter().map(|name| vec![name.to_string()]).collect();
        assert_eq!(schedules, expected, "{backend}: the trace passes of each frame");
        assert_eq!(r.rays, lanes.rays, "{backend}: {SPREAD} traces other rays than {FOUR_LANES}, frame by frame");
        // The last frame (far, after the top view) ran four lanes: the same bits.
        assert!(r.ao == lanes.ao && r.partial == lanes.partial, "{backend}: the four-lane frame's AO differs from {FOUR_LANES}'s");
    }
}
