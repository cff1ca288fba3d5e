//! The program's GPU-heavy paths under the Khronos validation layer with synchronization
//! validation on (`.ci/vk_layer_settings.txt`, which the whole suite runs with, see
//! DEVELOPERS.md), checked here whatever the environment says: `raygraph render` in the three
//! modes on every back-end lavapipe has (the rt-pipeline back-end records its own barriers),
//! `bench build --quick` (the GPU builder of the merged layout) and `bench anim --quick`
//! (acceleration structures refitted and rebuilt on the GPU frame after frame). The layer's
//! reports go to stdout and stop the process, so a hazard fails the run with the report printed.
//!
//! Measured on lavapipe (Mesa 25.0.7, validation layers 1.3.239), 2026-11-29: no report on any
//! of these runs; the layer's start-up message (with info reports on) confirms
//! `VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION`.

mod common;

use std::process::{Command, Output};

/// `raygraph args...` in the repository, under the layer with synchronization validation.
fn run_synchronized(args: &[&str]) -> Output {
    let settings = common::repo().join(".ci/vk_layer_settings.txt");
    let text = std::fs::read_to_string(&settings).unwrap_or_else(|e| panic!("{}: {e}", settings.display()));
    assert!(text.lines().any(|l| l.trim() == "khronos_validation.validate_sync = true"), "{} turns synchronization validation on", settings.display());
    Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .current_dir(common::repo())
        .args(args)
        .env("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation")
        .env("VK_LAYER_SETTINGS_PATH", &settings)
        .env("WGPU_DEBUG", "0")
        .output()
        .unwrap()
}

fn check(what: &str, out: &Output) {
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let reports: Vec<&str> = stdout.lines().chain(stderr.lines()).filter(|l| l.contains("Validation Error") || l.contains("SYNC-HAZARD")).collect();
    assert!(reports.is_empty(), "{what}: {} validation reports:\n{}", reports.len(), reports.join("\n"));
    assert!(out.status.success(), "{what} failed ({}):\n{stdout}\n{stderr}", out.status);
}

#[test]
fn the_three_modes_on_every_back_end_have_no_synchronization_hazard() {
    let out_png = common::gltf_doc::temp_dir("sync").join("x.png");
    let gpu = common::gpu();
    for backend in gpu.backends().iter().map(|b| b.to_string()) {
        for mode in ["raster", "hybrid", "full-rt"] {
            let out = run_synchronized(&[
                "render",
                "--mode",
                mode,
                "--backend",
                &backend,
                "--width",
                "96",
                "--height",
                "64",
                "--frames",
                "2",
                "--out",
                out_png.to_str().unwrap(),
            ]);
            check(&format!("render --mode {mode} --backend {backend}"), &out);
            println!("{mode} on {backend}: no report");
        }
    }
}

#[test]
fn gpu_builds_and_refits_have_no_synchronization_hazard() {
    let dir = common::gltf_doc::temp_dir("sync-bench");
    for bench in ["build", "anim"] {
        let out = run_synchronized(&["bench", bench, "--quick", "--out", dir.join(bench).to_str().unwrap()]);
        check(&format!("bench {bench} --quick"), &out);
        println!("bench {bench} --quick: no report");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
