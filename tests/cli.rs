//! The `raygraph` binary as a user runs it.

mod common;
use std::process::Command;

fn raygraph() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_raygraph"));
    c.current_dir(common::repo());
    c
}

#[test]
fn graph_check_prints_the_plan() {
    let out = raygraph().args(["graph", "check", "graph/raster.ron"]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("forward/visibility") && stdout.contains("forward/shade") && stdout.contains("tonemap/tonemap"), "{stdout}");
    assert!(stdout.contains("transient memory:"), "{stdout}");
}

#[test]
fn graph_check_of_a_broken_copy_fails_with_a_location() {
    let p = common::TempProject::with_repo_files();
    let text = std::fs::read_to_string(common::repo().join("graph/raster.ron")).unwrap().replace("\"hdr\": \"forward.color\"", "\"hdr\": \"forward.colour\"");
    let path = p.write("graph/raster.ron", &text);
    let out = Command::new(env!("CARGO_BIN_EXE_raygraph")).args(["graph", "check"]).arg(&path).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = common::line_of(&text, "forward.colour");
    assert!(stderr.contains(&format!("{}:{line}:", path.display())), "{stderr}");
    assert!(stderr.contains("help:"), "{stderr}");
}

#[test]
fn graph_dot_writes_graphviz() {
    let out = raygraph().args(["graph", "dot", "graph/raster.ron"]).output().unwrap();
    assert!(out.status.success());
    let dot = String::from_utf8_lossy(&out.stdout);
    assert!(dot.starts_with("digraph"), "{dot}");
    assert!(dot.contains("forward/shade") && dot.contains("tonemap.color"), "{dot}");
}

#[test]
fn render_writes_a_png_and_prints_the_pass_table() {
    let out_png = std::env::temp_dir().join(format!("raygraph-cli-{}.png", std::process::id()));
    let out = raygraph().args(["render", "--width", "96", "--height", "54", "--frames", "2", "--out"]).arg(&out_png).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("adapter:"), "{stdout}");
    assert!(stdout.contains("GPU ms") && stdout.contains("forward/shade"), "{stdout}");
    let img = image::open(&out_png).unwrap().to_rgba8();
    assert_eq!((img.width(), img.height()), (96, 54));
    // The pixels are the library's: the default graph (graph/raster.ron) on the default scene,
    // two frames, read back from an executor of its own.
    let graph = common::repo().join("graph/raster.ron");
    let plan = raygraph::graph::compile(&graph, &raygraph::graph::Project::beside_graph(&graph), (96, 54)).unwrap();
    let gpu = common::gpu();
    let scene = raygraph::scene::builtin::default_scene();
    let mut exec = raygraph::runtime::Executor::new(&gpu, plan, &scene).unwrap();
    for _ in 0..2 {
        exec.render(&gpu, scene.camera(), &scene).unwrap();
    }
    let library = exec.read_output(&gpu).unwrap();
    let differing = img.pixels().zip(library.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the PNG is the library's image byte for byte");
    let _ = std::fs::remove_file(out_png);
}

#[test]
fn render_to_an_unwritable_path_fails_cleanly() {
    let out = raygraph().args(["render", "--width", "16", "--height", "16", "--frames", "1", "--out", "/nonexistent-dir/x.png"]).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("/nonexistent-dir/x.png"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// A path under the temp dir for this test process, `tag` in its name.
fn temp_out(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("raygraph-cli-{}-{tag}", std::process::id()))
}

/// The tone map of `layers/tonemap.ron` (`shaders/tonemap/tonemap.wgsl`) on the CPU at its
/// defaults: the sky gradient behind 1 - alpha (row `y` of `height`), exposure 1, the ACES fit,
/// the sRGB encoding, 8 bits.
fn tone_map(c: [f32; 4], y: u32, height: u32) -> [u8; 3] {
    let v = (y as f32 + 0.5) / height as f32;
    let sky = |i: usize| [0.9f32, 0.85, 0.8][i] * v + [0.35f32, 0.55, 0.9][i] * (1.0 - v);
    std::array::from_fn(|i| {
        let x = c[i] + if c[3] < 1.0 { (1.0 - c[3].max(0.0)) * sky(i) } else { 0.0 };
        let aces = ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
        let srgb = if aces <= 0.0031308 { 12.92 * aces } else { 1.055 * aces.powf(1.0 / 2.4) - 0.055 };
        (srgb * 255.0).round() as u8
    })
}

#[test]
fn render_writes_linear_hdr_as_exr_that_tone_maps_to_the_png() {
    let (exr, png) = (temp_out("hdr.exr"), temp_out("hdr.png"));
    for out in [&exr, &png] {
        let run = raygraph().args(["render", "--width", "64", "--height", "36", "--frames", "1", "--out"]).arg(out).output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    }
    let hdr = image::open(&exr).unwrap();
    assert!(matches!(hdr, image::DynamicImage::ImageRgba32F(_)), "RGBA float32: {:?}", hdr.color());
    let (hdr, ldr) = (hdr.to_rgba32f(), image::open(&png).unwrap().to_rgba8());
    assert_eq!((hdr.width(), hdr.height()), (64, 36));
    assert!(hdr.pixels().all(|p| p.0.iter().all(|c| c.is_finite())), "finite radiance");
    // Linear and scene-referred: the lit floor and the spheres pass 1 (what the PNG clips).
    assert!(hdr.pixels().any(|p| p.0[..3].iter().any(|c| *c > 1.0)), "radiance above 1 somewhere");
    // Tone-mapped on the CPU, the EXR is the PNG within one 8-bit step (measured on lavapipe:
    // 0; the step allows for a GPU whose pow and division round apart from the CPU's).
    let mut worst = 0;
    for (x, y, p) in hdr.enumerate_pixels() {
        let want = tone_map(p.0, y, 36);
        let got = ldr.get_pixel(x, y).0;
        worst = worst.max((0..3).map(|i| want[i].abs_diff(got[i])).max().unwrap());
    }
    println!("tone-mapped EXR against the PNG: at most {worst} 8-bit steps apart");
    assert!(worst <= 1, "the tone-mapped EXR differs from the PNG by {worst} steps");
    for f in [exr, png] {
        let _ = std::fs::remove_file(f);
    }
}

#[test]
fn exr_of_the_cornell_box_shows_its_light_at_its_radiance_and_the_walls_lit_by_it() {
    let exr = temp_out("cornell.exr");
    // With no sun and no sky the light quad is the only source: it shows exactly its emission,
    // and full RT lights the walls by its triangles (rt_shadow's emitter rays), dimmer than it.
    run_ok(&["render", "--mode", "full-rt", "--scene", "cornell", "--width", "48", "--frames", "1", "--out", exr.to_str().unwrap()]);
    let hdr = image::open(&exr).unwrap().to_rgba32f();
    assert_eq!((hdr.width(), hdr.height()), (48, 48), "the classic camera's square film");
    let light = raygraph::scene::procedural::CORNELL_LIGHT_RADIANCE;
    // Half floats: 11 significant bits.
    let is_light = |p: &[f32; 4]| (0..3).all(|i| (p[i] - light[i]).abs() <= light[i] / 1024.0);
    let (mut lit, mut walls_lit) = (0, 0);
    for p in hdr.pixels() {
        if is_light(&p.0) {
            lit += 1;
        } else if p.0[3] == 1.0 && p.0[..3].iter().sum::<f32>() > 0.0 {
            assert!((0..3).all(|i| p.0[i] < light[i]), "{:?}: a wall brighter than the light {light:?}", p.0);
            walls_lit += 1;
        }
    }
    println!("cornell at 48x48: {walls_lit} pixels of wall lit by the quad");
    // The box but the ceiling (which the quad does not face) and a few noisy pixels sees the
    // quad: measured 1,445 of 2,304 on lavapipe, 2026-11-30; at least half.
    assert!(walls_lit * 2 > 48 * 48, "{walls_lit} pixels of wall lit");
    // The light spans 130 x 105 mm at 1.35 m to 1.64 m from the ceiling's front edge: a few
    // pixels at 48x48 (the ceiling hides part of it from the classic camera).
    let covered = hdr.pixels().filter(|p| p.0[3] == 1.0).count();
    println!("cornell at 48x48: {lit} pixels show the light, {covered} the box");
    assert!(lit >= 4, "{lit} pixels show the light");
    // Black walls: the box fills the frame but for a border about a pixel wide outside its front
    // (measured: 2116 pixels of 2304, 46 x 46).
    assert!(covered * 100 > 85 * 48 * 48, "{covered} of {} pixels show the box", 48 * 48);
    let _ = std::fs::remove_file(exr);
    assert!(run_ok(&["scene", "info", "cornell"]).contains("no sun and no sky"), "scene info says what lights it");
    // The other modes render it too (raster: black but for the light).
    let png = temp_out("cornell.png");
    for mode in ["raster", "hybrid"] {
        run_ok(&["render", "--mode", mode, "--scene", "cornell", "--width", "32", "--frames", "1", "--out", png.to_str().unwrap()]);
    }
    let _ = std::fs::remove_file(png);
}

#[test]
fn render_refuses_unknown_extensions_and_graphs_without_hdr_output_and_leaves_no_file() {
    let run = |args: &[&str], out: &std::path::Path| {
        let o = raygraph().args(args).args(["--width", "16", "--height", "16", "--frames", "1", "--out"]).arg(out).output().unwrap();
        assert!(!o.status.success(), "{args:?} {}", out.display());
        assert!(!out.exists(), "{}: no file after an error", out.display());
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!stderr.contains("panicked"), "{stderr}");
        stderr
    };
    let tiff = temp_out("x.tiff");
    let stderr = run(&["render"], &tiff);
    assert!(stderr.contains(&tiff.display().to_string()) && stderr.contains(".png") && stderr.contains(".exr"), "{stderr}");
    // A graph that names no HDR output: the error names the file and what it lacks.
    let p = common::TempProject::with_repo_files();
    let text = std::fs::read_to_string(common::repo().join("graph/raster.ron")).unwrap();
    let without: String = text.lines().filter(|l| !l.contains("hdr_output")).map(|l| format!("{l}\n")).collect();
    assert_ne!(without, text, "graph/raster.ron names its HDR output");
    let graph = p.write("graph/no_hdr.ron", &without);
    let exr = temp_out("no-hdr.exr");
    let stderr = run(&["render", "--graph", graph.to_str().unwrap()], &exr);
    assert!(stderr.contains(&graph.display().to_string()) && stderr.contains("hdr_output"), "{stderr}");
    // The same graph still writes PNGs.
    let png = temp_out("no-hdr.png");
    run_ok(&["render", "--graph", graph.to_str().unwrap(), "--width", "16", "--height", "16", "--frames", "1", "--out", png.to_str().unwrap()]);
    let _ = std::fs::remove_file(png);
    // An unwritable path fails as for a PNG, naming it.
    let nowhere = std::path::Path::new("/nonexistent-dir/x.exr");
    assert!(run(&["render"], nowhere).contains("/nonexistent-dir/x.exr"));
}

fn run_ok(args: &[&str]) -> String {
    let out = raygraph().args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{args:?}: {stdout}{}", String::from_utf8_lossy(&out.stderr));
    stdout
}

/// The number after `key` on its line of `scene info` output.
fn field(info: &str, key: &str) -> f64 {
    let line = info.lines().find(|l| l.starts_with(key)).unwrap_or_else(|| panic!("no `{key}` in {info}"));
    line[key.len()..].split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn scene_info_of_the_atrium_is_within_5_percent_of_the_papers_sponza_row() {
    let info = run_ok(&["scene", "info", "atrium"]);
    println!("{info}");
    for (key, paper) in [("triangles", 262_267.0), ("meshes", 103.0), ("textures", 69.0)] {
        let got = field(&info, key);
        assert!((got - paper).abs() / paper <= 0.05, "{key}: {got} against the paper's {paper}");
    }
    assert!(info.contains("bounds") && info.contains("cameras") && info.contains("ignored"), "{info}");
}

#[test]
fn scene_export_writes_a_glb_that_scene_info_reads_back() {
    let dir = common::gltf_doc::temp_dir("cli-export");
    let glb = dir.join("organic.glb");
    let said = run_ok(&["scene", "export", "organic", glb.to_str().unwrap()]);
    assert!(said.contains("3920 triangles"), "{said}");
    let info = run_ok(&["scene", "info", glb.to_str().unwrap()]);
    assert_eq!(field(&info, "triangles"), 3920.0, "{info}");
    assert_eq!(field(&info, "textures"), 2.0, "{info}");
    // Copies on a grid, each with meshes of its own: 8 x 3,920 unique triangles in 8 meshes.
    let grid = dir.join("organic_2x2x2.glb");
    let said = run_ok(&["scene", "export", "organic", grid.to_str().unwrap(), "--duplicate", "2", "--no-dedup"]);
    assert!(said.contains("31360 triangles, 8 meshes"), "{said}");
    let info = run_ok(&["scene", "info", grid.to_str().unwrap()]);
    assert_eq!(field(&info, "triangles"), 31360.0, "{info}");
    // A failed export (no such directory) reports the path and leaves nothing.
    let out = raygraph().args(["scene", "export", "box", "/nonexistent-dir/b.glb"]).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("/nonexistent-dir/b.glb"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_sizes_its_output_by_the_cameras_aspect_ratio_unless_given_a_height() {
    let dir = common::gltf_doc::temp_dir("cli-aspect");
    let png = |n: &str| dir.join(n).to_str().unwrap().to_string();
    // One triangle and a file camera with aspectRatio 1.5 looking at it.
    let mut d = common::gltf_doc::Doc::new();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mesh = d.mesh(&[("POSITION", p)], None, None, None);
    d.node(serde_json::json!({"mesh": mesh}), true);
    d.json["cameras"] = serde_json::json!([{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}]);
    d.node(serde_json::json!({"camera": 0, "translation": [0.0, 0.0, 3.0]}), true);
    let file = d.write_glb(&dir, "wide");
    let file = file.to_str().unwrap();
    run_ok(&["render", "--scene", file, "--width", "60", "--frames", "1", "--out", &png("wide.png")]);
    assert_eq!(image::open(png("wide.png")).unwrap().to_rgba8().dimensions(), (60, 40), "60 wide over aspect 1.5");
    // Both given: the output size wins, with a warning.
    let out = raygraph().args(["render", "--scene", file, "--width", "60", "--height", "60", "--frames", "1", "--out", &png("square.png")]).output().unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("the camera's aspect ratio 1.5000 is not the output's 60x60"));
    assert_eq!(image::open(png("square.png")).unwrap().to_rgba8().dimensions(), (60, 60));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_takes_a_scene_a_camera_preset_and_a_track() {
    let dir = common::gltf_doc::temp_dir("cli-render");
    let png = |n: &str| dir.join(n).to_str().unwrap().to_string();
    run_ok(&["render", "--scene", "box", "--camera", "front", "--width", "48", "--height", "32", "--frames", "1", "--out", &png("front.png")]);
    run_ok(&["render", "--scene", "box", "--camera", "close", "--width", "48", "--height", "32", "--frames", "1", "--out", &png("close.png")]);
    let (a, b) = (image::open(png("front.png")).unwrap().to_rgba8(), image::open(png("close.png")).unwrap().to_rgba8());
    assert!(a != b, "two presets give two pictures");
    let track = png("orbit.ron");
    run_ok(&["scene", "orbit", "box", &track, "--seconds", "2"]);
    run_ok(&[
        "render",
        "--scene",
        "box",
        "--track",
        &track,
        "--track-frame",
        "15",
        "--width",
        "48",
        "--height",
        "32",
        "--frames",
        "1",
        "--out",
        &png("t15.png"),
    ]);
    run_ok(&[
        "render",
        "--scene",
        "box",
        "--track",
        &track,
        "--track-frame",
        "15",
        "--width",
        "48",
        "--height",
        "32",
        "--frames",
        "1",
        "--out",
        &png("t15b.png"),
    ]);
    assert!(image::open(png("t15.png")).unwrap().to_rgba8() == image::open(png("t15b.png")).unwrap().to_rgba8(), "playback by frame index is deterministic");
    let out = raygraph().args(["render", "--scene", "box", "--camera", "nowhere", "--frames", "1", "--out", &png("x.png")]).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("corner, front, close"), "{stderr}");
    assert!(!dir.join("x.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `raygraph selftest` on lavapipe: every suite passes on every back-end and layout it runs on
/// (lavapipe has them all: none may be not applicable here), and `--out` keeps the same lines with the
/// adapter, revision and date.
#[test]
fn selftest_passes_every_suite_on_every_lavapipe_back_end() {
    let dir = std::env::temp_dir().join(format!("raygraph-selftest-{}", std::process::id()));
    let out = raygraph().arg("selftest").arg("--out").arg(&dir).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    for suite in raygraph::selftest::SUITES {
        for variant in raygraph::selftest::suite_variants(suite) {
            let line = stdout.lines().find(|l| l.starts_with(&format!("{suite} on {}: ", variant.name)));
            let line = line.unwrap_or_else(|| panic!("no line for {suite} on {}: {stdout}", variant.name));
            assert!(line.ends_with(" s)") && line.contains(": passed ("), "{line}");
        }
    }
    let expected: usize = raygraph::selftest::SUITES.iter().map(|s| raygraph::selftest::suite_variants(s).count()).sum();
    assert!(stdout.contains(&format!("ok: {expected} passed, 0 failed, 0 not applicable")), "{stdout}");
    let log = std::fs::read_to_string(dir.join("selftest.log")).unwrap();
    assert!(log.starts_with("adapter: ") && log.contains("\nrevision: ") && log.contains("\ndate: 20"), "{log}");
    assert_eq!(log.lines().filter(|l| l.contains(": passed (")).count(), expected, "{log}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The verdict counts not-applicable lines apart from passed ones: a run where only those
/// remain (every back-end lacking) fails, as does any failure.
#[test]
fn selftest_verdict_never_counts_not_applicable_as_passed() {
    use raygraph::selftest::{verdict, Outcome, SuiteResult, VARIANTS};
    let line = |outcome: Outcome| SuiteResult { suite: "hard-cases", variant: VARIANTS[2], outcome, notes: Vec::new(), checks: 13, seconds: 1.0 };
    let not_applicable = line(Outcome::NotApplicable("the adapter has no ray queries (VK_KHR_ray_query)".into()));
    assert_eq!(not_applicable.line(), "hard-cases on ray-query: not applicable: the adapter has no ray queries (VK_KHR_ray_query)");
    assert_eq!(verdict(std::slice::from_ref(&not_applicable)), "selftest failed: 0 passed, 0 failed, 1 not applicable");
    assert_eq!(verdict(&[line(Outcome::Passed), not_applicable]), "ok: 1 passed, 0 failed, 1 not applicable");
    let failed = line(Outcome::Failed("grazing rays: a ray missed".into()));
    assert_eq!(failed.line(), "hard-cases on ray-query: FAILED: grazing rays: a ray missed");
    assert_eq!(verdict(&[line(Outcome::Passed), failed]), "selftest failed: 1 passed, 1 failed, 0 not applicable");
}

#[test]
fn render_with_an_environment_map_writes_its_backdrop_and_refuses_a_bad_map() {
    let dir = common::gltf_doc::temp_dir("env-cli");
    let out_png = dir.join("beach.png");
    let out = raygraph()
        .args([
            "render",
            "--mode",
            "hybrid",
            "--width",
            "64",
            "--height",
            "36",
            "--frames",
            "1",
            "--env",
            "assets/env/spiaggia_di_mondello_1k.hdr",
            "--env-rotation",
            "-90",
            "--out",
        ])
        .arg(&out_png)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    // The default view's top row is backdrop: the beach's sky, not the analytic sky's tone-map
    // gradient (whose top row is (0.35, 0.55, 0.9) before the tone curve: blue over red by 0.55).
    let img = image::open(&out_png).unwrap().to_rgb8();
    let top: Vec<[u8; 3]> = (0..64).map(|x| img.get_pixel(x, 0).0).collect();
    let analytic =
        raygraph().args(["render", "--mode", "hybrid", "--width", "64", "--height", "36", "--frames", "1", "--out"]).arg(dir.join("sky.png")).output().unwrap();
    assert!(analytic.status.success());
    let sky = image::open(dir.join("sky.png")).unwrap().to_rgb8();
    let differing = (0..64).filter(|&x| sky.get_pixel(x, 0).0 != top[x as usize]).count();
    assert!(differing > 48, "the backdrop is the map's: {differing} of 64 top-row pixels differ from the analytic sky's");
    for (bad, says) in [("missing.hdr", "missing.hdr"), ("README.md", "not an image format raygraph reads")] {
        let png = dir.join("bad.png");
        let out = raygraph().args(["render", "--width", "16", "--height", "16", "--env", bad, "--out"]).arg(&png).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains("environment map") && stderr.contains(says), "{bad}: {stderr}");
        assert!(!png.exists(), "{bad}: no image is written");
    }
    let out = raygraph().args(["render", "--env-intensity", "2"]).output().unwrap();
    assert!(!out.status.success(), "--env-intensity needs --env");
}
