//! The GPU deadline: a layer whose shader loops forever ends the run with an error naming its
//! pass within the deadline, from the library and from `raygraph render`, and nothing is
//! written. (Loop bounding, on for project shaders, bounds a loop at 2^64 iterations: still a
//! hang, so the deadline is what ends these runs.)

mod common;

use raygraph::error::RuntimeError;
use raygraph::graph::compile;
use raygraph::runtime::Executor;
use std::process::Command;
use std::time::{Duration, Instant};

const DEADLINE: Duration = Duration::from_secs(2);
/// Wall time allowed from the submission to the error: the deadline and a margin for a
/// loaded 2-core machine, far below a hang.
const WALL_LIMIT: Duration = Duration::from_secs(30);

fn assert_names_the_fog_pass(message: &str) {
    assert!(message.contains("the GPU ran past its deadline of 2 s"), "{message}");
    assert!(message.contains("`fog/fog`") && message.contains("fog.ron") && message.contains("fog.wgsl"), "the pass and its files: {message}");
    assert!(message.contains("frame 0"), "{message}");
}

#[test]
fn a_shader_that_never_ends_is_a_deadline_error_naming_its_pass() {
    let (project, graph) = common::endless_fog::project();
    let mut gpu = common::gpu();
    gpu.set_gpu_timeout(DEADLINE);
    let plan = compile::compile_with(&graph, &project.project(), (16, 16), &gpu.compile_options()).unwrap();
    let scene = raygraph::scene::builtin::default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    let start = Instant::now();
    let Err(err) = exec.render(&gpu, scene.camera(), &scene) else { panic!("a frame that never ends must fail") };
    let waited = start.elapsed();
    println!("{err}\n(after {waited:?})");
    assert!(matches!(err, RuntimeError::GpuTimeout { .. }), "{err:?}");
    assert!(waited >= DEADLINE && waited < WALL_LIMIT, "the error must come at the deadline, not before or much later: {waited:?}");
    assert_names_the_fog_pass(&err.to_string());
    assert!(gpu.timed_out());
    // The device is still busy: every later frame fails at once with the same error.
    let start = Instant::now();
    let Err(again) = exec.render(&gpu, scene.camera(), &scene) else { panic!("the device is still busy") };
    assert!(start.elapsed() < Duration::from_secs(1), "{:?}", start.elapsed());
    assert_eq!(again.to_string(), err.to_string());
    // Releasing objects the stuck work uses can block in the driver: the run ends here.
    std::mem::forget(exec);
    std::mem::forget(gpu);
}

#[test]
fn render_with_a_shader_that_never_ends_exits_with_status_1_and_writes_nothing() {
    render_past_the_deadline(None);
}

/// The same while polling for the GPU (`RAYGRAPH_GPU_WAIT=spin`, the default on a GPU adapter)
/// and while blocked until shortly before the last wait's length (`tail`): the poll loop keeps
/// the deadline too.
#[test]
fn the_deadline_holds_whichever_way_the_host_waits() {
    for wait in ["spin", "tail:1"] {
        render_past_the_deadline(Some(wait));
    }
}

/// `render` with the endless shader, `RAYGRAPH_GPU_WAIT=wait` where given: status 1 soon after
/// the deadline, an error naming the pass, and nothing written.
fn render_past_the_deadline(wait: Option<&str>) {
    let (project, graph) = common::endless_fog::project();
    let out_png = project.root.join("fog.png");
    let report = project.root.join("report");
    let start = Instant::now();
    let mut command = Command::new(env!("CARGO_BIN_EXE_raygraph"));
    if let Some(wait) = wait {
        command.env("RAYGRAPH_GPU_WAIT", wait);
    }
    let out = command
        .current_dir(&project.root)
        .args(["render", "--width", "16", "--height", "16", "--frames", "2", "--gpu-timeout", "2", "--graph"])
        .arg(&graph)
        .arg("--out")
        .arg(&out_png)
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    let waited = start.elapsed();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stderr}\n(after {waited:?})");
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(waited < WALL_LIMIT, "the process must end promptly after the deadline: {waited:?}");
    assert_names_the_fog_pass(&stderr);
    assert!(stderr.contains("nothing was written"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!out_png.exists(), "no image may be written after a timeout");
    assert!(!report.exists(), "no report may be written after a timeout");
    let leftovers: Vec<_> = std::fs::read_dir(&project.root).unwrap().filter_map(|e| e.ok()).map(|e| e.file_name()).collect();
    assert!(leftovers.iter().all(|n| ["graph", "layers", "shaders"].contains(&n.to_str().unwrap())), "no temporary file either: {leftovers:?}");
}

#[test]
fn a_gpu_timeout_that_is_not_a_positive_number_is_refused() {
    for bad in ["0", "-1", "nan", "inf"] {
        let out = Command::new(env!("CARGO_BIN_EXE_raygraph"))
            .current_dir(common::repo())
            .args(["render", "--width", "8", "--height", "8", &format!("--gpu-timeout={bad}"), "--out", "/nonexistent/never.png"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "--gpu-timeout {bad}: {stderr}");
        assert!(stderr.contains("--gpu-timeout") && !stderr.contains("panicked"), "--gpu-timeout {bad}: {stderr}");
    }
}

/// Polling for the GPU draws the frames that blocking draws, and an unknown way of waiting is
/// an error naming the variable.
#[test]
fn every_way_of_waiting_draws_the_same_frames() {
    let render = |wait: &str, out: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_raygraph"))
            .current_dir(common::repo())
            .env("RAYGRAPH_GPU_WAIT", wait)
            .args(["render", "--mode", "hybrid", "--width", "48", "--frames", "2", "--out"])
            .arg(out)
            .output()
            .unwrap()
    };
    let dir = common::TempProject::new();
    let images: Vec<Vec<u8>> = ["block", "spin", "tail"]
        .iter()
        .map(|wait| {
            let png = dir.root.join(format!("{wait}.png"));
            let out = render(wait, &png);
            assert!(out.status.success(), "{wait}: {}", String::from_utf8_lossy(&out.stderr));
            std::fs::read(&png).unwrap()
        })
        .collect();
    assert!(images.windows(2).all(|w| w[0] == w[1]), "the images differ between ways of waiting");
    let out = render("sometimes", &dir.root.join("never.png"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("RAYGRAPH_GPU_WAIT=sometimes") && !stderr.contains("panicked"), "{stderr}");
    assert!(!dir.root.join("never.png").exists());
}
