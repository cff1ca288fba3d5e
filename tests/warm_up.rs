//! The warm-up before timed frames with its full-load kernel (`runtime::clock_pump`, on by
//! default for a hardware GPU): here forced on for lavapipe, it runs under the validation
//! layers without an error, lasts the time it is given, and the frames after it render the
//! same picture as frames without it.

mod common;

use raygraph::backend::Backend;
use raygraph::runtime::warm_up::WarmUp;
use raygraph::scene::builtin::default_scene;
use std::time::Instant;

#[test]
fn the_clock_pump_lasts_its_time_and_leaves_the_frames_as_they_were() {
    let gpu = common::gpu();
    let scene = default_scene();
    let size = (48, 32);
    let policy = WarmUp { min_frames: 6, min_seconds: 0.0, max_seconds: 1.0, tolerance: 0.10, pump_seconds: 0.0 };
    let mut plain = common::modes::render_without_effects(&gpu, "graph/hybrid.ron", Backend::Compute, &scene, size);
    policy.run(&gpu, &mut plain, &scene, scene.camera()).unwrap();
    let mut pumped = common::modes::render_without_effects(&gpu, "graph/hybrid.ron", Backend::Compute, &scene, size);
    let start = Instant::now();
    let frames = WarmUp { pump_seconds: 0.25, ..policy }.run(&gpu, &mut pumped, &scene, scene.camera()).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    assert!(frames >= 6, "{frames} warm-up frames after the pump");
    assert!(seconds >= 0.25, "the pump and the frames took {seconds:.3} s, under the pump's 0.25 s");
    assert!(pumped.read_output(&gpu).unwrap() == plain.read_output(&gpu).unwrap(), "the same picture after the pump");
}
