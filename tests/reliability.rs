//! Reliability: GPU faults end a run with a clear message, a non-zero exit and no output file;
//! the shortened soak keeps memory and live GPU objects flat; every file the fuzzers start from
//! is accepted and every input they found a crash with is now a clear error.

mod common;

use std::path::Path;
use std::process::Command;

fn raygraph() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_raygraph"));
    c.current_dir(common::repo());
    c
}

fn temp_png(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("raygraph-reliability-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let _ = std::fs::remove_file(&path);
    path
}

/// The device is destroyed at the start of frame 2 (`RAYGRAPH_INJECT_DEVICE_LOSS`, which calls
/// wgpu's `Device::destroy`: the loss callback and every later call see a lost device).
#[test]
fn a_lost_device_ends_the_run_with_a_message_and_no_output() {
    let out_png = temp_png("lost.png");
    let out = raygraph()
        .env("RAYGRAPH_INJECT_DEVICE_LOSS", "2")
        .args(["render", "--mode", "hybrid", "--width", "32", "--height", "32", "--frames", "4", "--out"])
        .arg(&out_png)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stderr}");
    assert!(!out.status.success(), "a lost device must fail the run");
    assert!(stderr.contains("the GPU device was lost") && stderr.contains("destroyed"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!out_png.exists(), "nothing may be written after a device loss");
}

/// A real allocation failure: the process's address space is capped (`ulimit -v`, 4 GB) and
/// the hybrid graph at 12000x12000 needs a 2.2 GB position texture among others, which
/// lavapipe cannot map. The message names the resource and the sizes; the output file of an
/// earlier run is left as it was.
#[test]
fn out_of_gpu_memory_ends_the_run_with_a_message_naming_the_resource_and_no_output() {
    let out_png = temp_png("oom.png");
    let previous = b"the previous run's output".to_vec();
    std::fs::write(&out_png, &previous).unwrap();
    let cmd = format!(
        "ulimit -v 4000000 && exec {} render --mode hybrid --width 12000 --height 12000 --frames 1 --out {}",
        env!("CARGO_BIN_EXE_raygraph"),
        out_png.display()
    );
    let out = Command::new("sh").arg("-c").arg(cmd).current_dir(common::repo()).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stderr}");
    assert!(!out.status.success(), "running out of memory must fail the run");
    assert!(stderr.contains("the GPU ran out of memory") && stderr.contains("gbuffer.position"), "{stderr}");
    assert!(stderr.contains("MiB of textures and buffers in") && stderr.contains("12000x12000 frame"), "the message names the sizes: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(std::fs::read(&out_png).unwrap(), previous, "the previous output must be left intact");
    let _ = std::fs::remove_file(&out_png);
}

/// A scene duplicated until it no longer fits: the atrium 5x5x5 with a mesh per copy needs a
/// vertex buffer larger than one storage binding may be on lavapipe (128 MiB). The message
/// names the scene, the buffer and both sizes; an earlier output file is left as it was.
#[test]
fn a_duplicated_scene_beyond_the_device_ends_the_run_with_the_sizes_and_no_output() {
    let out_png = temp_png("duplicated.png");
    let previous = b"the previous run's output".to_vec();
    std::fs::write(&out_png, &previous).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .current_dir(common::repo())
        .args([
            "render",
            "--mode",
            "hybrid",
            "--scene",
            "atrium",
            "--duplicate",
            "5",
            "--no-dedup",
            "--width",
            "32",
            "--height",
            "32",
            "--frames",
            "1",
            "--out",
        ])
        .arg(&out_png)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stderr}");
    assert!(!out.status.success(), "a scene beyond the device must fail the run");
    assert!(stderr.contains("scene `atriumx5` does not fit the GPU: the vertex buffer (one storage binding) needs"), "{stderr}");
    assert!(stderr.contains("MiB (") && stderr.contains("the device allows"), "the message names both sizes: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(std::fs::read(&out_png).unwrap(), previous, "the previous output must be left intact");
    let _ = std::fs::remove_file(&out_png);
}

/// The shortened soak on `backend`: 3 cycles of 100 frames at 32x32 with every kind of change,
/// its per-check lines kept with `--log`.
fn short_soak(backend: &str) {
    let log = temp_png(&format!("soak-{backend}.log"));
    let out = raygraph()
        .args(["soak", "--frames", "300", "--cycle", "100", "--width", "32", "--height", "32", "--backend", backend, "--log"])
        .arg(&log)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stdout}");
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(
        stdout.contains("300 frames: 75 with instances moving, 3 meshes added and 3 removed, 6 graph swaps, 3 shader errors caught and 3 fixed"),
        "{stdout}"
    );
    assert!(stdout.contains("resolve.wgsl:") && stdout.contains("WGSL does not parse"), "the shader error names the file and line: {stdout}");
    assert!(stdout.contains("ok: memory and live GPU objects flat, image finite, over 3 checks"), "{stdout}");
    let logged = std::fs::read_to_string(&log).unwrap();
    assert!(logged.contains(&format!("back-end: {backend}")) && logged.contains("GPU MiB al/res"), "{logged}");
    let checks: Vec<&str> = logged.lines().filter(|l| l.trim_start().starts_with(['1', '2', '3']) && l.contains("buffers")).collect();
    assert_eq!(checks.len(), 3, "one log line per check: {logged}");
    assert!(logged.ends_with("over 3 checks\n"), "the verdict ends the log: {logged}");
}

#[test]
fn the_short_soak_on_compute_keeps_memory_and_gpu_objects_flat() {
    short_soak("compute");
}

#[test]
fn the_short_soak_on_ray_query_keeps_memory_and_gpu_objects_flat() {
    short_soak("ray-query");
}

#[test]
fn the_short_soak_on_rt_pipeline_keeps_memory_and_gpu_objects_flat() {
    short_soak("rt-pipeline");
}

/// A soak whose graph has no HDR resource fails the finite-image check (it has nothing to
/// check) instead of passing it.
#[test]
fn a_soak_without_an_hdr_target_fails_its_finite_image_check() {
    let gpu = common::gpu();
    let mut cfg = raygraph::soak::SoakConfig::new(&common::repo(), 32, 16, (16, 16));
    cfg.graphs = [Path::new("graph/raster.ron").into(), Path::new("graph/raster.ron").into()];
    cfg.broken_shader = Path::new("tonemap/tonemap.wgsl").into();
    let report = raygraph::soak::run(&gpu, &cfg, |_, _| {}).unwrap();
    println!("{:#?}", report.failures);
    assert_eq!(report.checks.len(), 2);
    assert!(report.checks.iter().all(|c| c.finite.is_none()));
    let missing = report.failures.iter().filter(|f| f.contains("the finite-image check has no input: the graph has no HDR resource `resolve.hdr`")).count();
    assert_eq!(missing, 2, "every check fails for the missing HDR image: {:#?}", report.failures);
}

/// A check made without wgpu's registry report fails the live-object check, and one without an
/// HDR image fails the finite-image check; with both inputs and nothing changed it passes.
#[test]
fn a_soak_check_without_its_inputs_fails() {
    use raygraph::soak::Check;
    let first = Check { frame: 100, rss_mib: 100.0, live: None, finite: Some(true), gpu_memory: None, seconds: 1.0 };
    let failures = first.failures(None, 32.0, "resolve.hdr");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("live GPU objects not checked: wgpu gave no registry report"), "{failures:?}");
    let no_hdr = Check { finite: None, ..first.clone() };
    let failures = no_hdr.failures(Some(&first), 32.0, "resolve.hdr");
    assert!(failures.iter().any(|f| f.contains("the graph has no HDR resource `resolve.hdr`")), "{failures:?}");
    let gpu = common::gpu();
    let live = raygraph::soak::LiveObjects::of(&gpu).expect("wgpu-core has a registry report on Vulkan");
    let good = Check { live: Some(live), ..first.clone() };
    assert_eq!(good.failures(Some(&good), 32.0, "resolve.hdr"), Vec::<String>::new());
    let non_finite = Check { finite: Some(false), ..good.clone() };
    assert_eq!(non_finite.failures(Some(&good), 32.0, "resolve.hdr").len(), 1);
}

fn files(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir).map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect()).unwrap_or_default();
    v.sort();
    v
}

/// The seeds of every fuzz target are the project's own files: each is accepted.
#[test]
fn the_fuzz_seeds_are_accepted() {
    let seeds = common::repo().join("fuzz/seeds");
    let mut n = 0;
    for f in files(&seeds.join("graph_file")) {
        raygraph::fuzz::graph_file(&std::fs::read(&f).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        n += 1;
    }
    for f in files(&seeds.join("layer_file")) {
        raygraph::graph::compile::parse_layer(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        n += 1;
    }
    for f in files(&seeds.join("scene_file")) {
        raygraph::fuzz::scene_file(&std::fs::read(&f).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        n += 1;
    }
    for f in files(&seeds.join("track_file")) {
        raygraph::fuzz::track_file(&std::fs::read(&f).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        n += 1;
    }
    assert!(n >= 20, "only {n} seeds");
}

/// Every input a fuzzer found a crash with (`tests/fixtures/fuzz/<target>/`, named after what
/// is wrong with it) is now an error that names the file, from the entry point and, for scene
/// files, from `raygraph scene info`; or, for a file named `loads-with-warning-*`, a scene
/// that loads with a warning (a broken image becomes the fallback texture, as a missing one
/// does).
#[test]
fn every_fuzz_finding_is_a_clear_error() {
    let fixtures = common::repo().join("tests/fixtures/fuzz");
    let entry: [(&str, fn(&[u8]) -> Result<(), String>, &str); 4] = [
        ("graph_file", raygraph::fuzz::graph_file, "graph.ron"),
        ("layer_file", raygraph::fuzz::layer_file, "fuzz.ron"),
        ("scene_file", raygraph::fuzz::scene_file, "scene."),
        ("track_file", raygraph::fuzz::track_file, "track.ron"),
    ];
    let mut n = 0;
    for (target, run, scratch_name) in entry {
        for f in files(&fixtures.join(target)) {
            if f.file_name().unwrap().to_string_lossy().starts_with("loads-with-warning-") {
                let (_, report) = raygraph::scene::open(&f.to_string_lossy(), &Default::default()).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                println!("{}: {:?}", f.display(), report.warnings);
                assert!(!report.warnings.is_empty() && report.missing_images > 0, "{}: {report:?}", f.display());
                n += 1;
                continue;
            }
            let e = run(&std::fs::read(&f).unwrap()).expect_err(&format!("{}: must be refused", f.display()));
            println!("{}: {e}", f.display());
            assert!(e.contains(scratch_name), "{}: the error must name the file: {e}", f.display());
            if target == "scene_file" {
                let out = raygraph().args(["scene", "info"]).arg(&f).output().unwrap();
                let stderr = String::from_utf8_lossy(&out.stderr);
                assert!(!out.status.success() && stderr.contains(&*f.to_string_lossy()) && !stderr.contains("panicked"), "{stderr}");
            }
            n += 1;
        }
    }
    assert!(n >= 1, "no fuzz findings under {}", fixtures.display());
}
