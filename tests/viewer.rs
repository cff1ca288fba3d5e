//! `raygraph view` under Xvfb on lavapipe (CI installs `xvfb`; without `Xvfb` these tests fail
//! rather than skip): a script that switches the mode, changes a parameter, switches an
//! effect off and clicks a pass, checked through its screenshots and the overlay's text; and a
//! WGSL file broken and fixed while the viewer runs.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

use common::xvfb::XServer;

impl XServer {
    /// `raygraph view ARGS` on this display, run from the repository.
    fn viewer(&self, args: &[&str]) -> Command {
        let mut c = Command::new(env!("CARGO_BIN_EXE_raygraph"));
        c.current_dir(common::repo()).env("DISPLAY", &self.display).env_remove("WAYLAND_DISPLAY").arg("view").args(args);
        c
    }
}

/// Runs `c` to its end (killed after `secs`), returning its status, its stdout lines and all
/// of its output as one text.
fn run_with_timeout(mut c: Command, secs: u64) -> (bool, Vec<String>, String) {
    let mut child = c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let rx = lines(&mut child);
    let err_rx = read_lines(child.stderr.take().unwrap());
    let deadline = Instant::now() + Duration::from_secs(secs);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    // The readers end when the pipes close with the process.
    let out: Vec<String> = rx.iter().collect();
    let log = format!("{}\n{}", out.join("\n"), err_rx.iter().collect::<Vec<_>>().join("\n"));
    assert!(status.is_some(), "the viewer did not finish within {secs} s:\n{log}");
    (status.is_some_and(|s| s.success()), out, log)
}

fn load(path: &Path) -> image::RgbaImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgba8()
}

/// Mean absolute difference of two same-sized images, in 8-bit units.
fn mean_abs_diff(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels().zip(b.pixels()).map(|(p, q)| (0..3).map(|c| (p[c] as f64 - q[c] as f64).abs()).sum::<f64>() / 3.0).sum::<f64>() / (a.width() * a.height()) as f64
}

/// Writes `Script(steps: [STEPS])` into `dir` and runs the viewer with `args` and the script to
/// its end: it must exit successfully with no step failing. Returns its stdout lines and all of
/// its output.
fn run_script(x: &XServer, dir: &Path, steps: &str, args: &[&str]) -> (Vec<String>, String) {
    let script = dir.join("script.ron");
    std::fs::write(&script, format!("Script(steps: [\n                {steps}\n            ])")).unwrap();
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["--script", script.to_str().unwrap()]);
    let (ok, out, log) = run_with_timeout(x.viewer(&all), 600);
    assert!(ok, "{log}");
    assert!(!out.iter().any(|l| l.starts_with("error:")), "no step failed: {log}");
    (out, log)
}

/// The viewer script of [`script_switches_mode_sets_a_parameter_and_shows_a_pass`]: screenshots
/// and the recorded track go to `dir`.
fn script_steps(dir: &Path) -> String {
    let shot = |name: &str| dir.join(name).display().to_string();
    format!(
        r#"(frame: 2, action: Screenshot("{overlay}")),
                (frame: 3, action: Overlay(false)),
                (frame: 4, action: Screenshot("{raster}")),
                (frame: 5, action: Mode(FullRt)),
                (frame: 7, action: Screenshot("{full_rt}")),
                (frame: 8, action: Param(node: "ao", name: "rays", value: 3)),
                (frame: 9, action: SelectPass("ao/sum")),
                (frame: 11, action: Screenshot("{ao}")),
                (frame: 12, action: Overlay(true)),
                (frame: 13, action: Screenshot("{ao_overlay}")),
                (frame: 14, action: Enable(node: "ao", on: false)),
                (frame: 16, action: Screenshot("{ao_off}")),
                (frame: 17, action: Backend("compute")),
                (frame: 18, action: Record),
                (frame: 19, action: Camera(position: (0.0, 2.0, 6.0), target: (0.0, 0.5, 0.0))),
                (frame: 21, action: SaveTrack("{track}")),
                (frame: 22, action: PlayTrack("{track}")),
                (frame: 24, action: Screenshot("{compute}")),
                (frame: 25, action: Quit),"#,
        overlay = shot("overlay.png"),
        raster = shot("raster.png"),
        full_rt = shot("full_rt.png"),
        ao = shot("ao.png"),
        ao_overlay = shot("ao_overlay.png"),
        ao_off = shot("ao_off.png"),
        track = shot("track.ron"),
        compute = shot("compute.png"),
    )
}

/// After the script's AO steps: the parameter reached the running graph and the inspector shows
/// the AO texture.
fn check_ao_inspection(dir: &Path, full_rt: &image::RgbaImage) {
    let text = |name: &str| std::fs::read_to_string(dir.join(format!("{name}.png.overlay.txt"))).unwrap();
    // The parameter reached the running graph, the clicked pass's texture is shown (`ao/sum`,
    // the AO layer's pass that writes `ao.ao`; `ao/ao` writes the lanes' partial sums).
    let ao = text("ao_overlay");
    for needle in ["mode: full RT", "view: ao.ao", "ao.rays = 3", "ao/ao: GPU", "gbuffer/primary: GPU", "rays/px"] {
        assert!(ao.contains(needle), "overlay after the script's steps lacks `{needle}`:\n{ao}");
    }
    // The running AO pass traces at most 3 rays per pixel now (8 before).
    let ao_line = ao.lines().find(|l| l.trim_start().starts_with("ao/ao:")).unwrap();
    let per_px: f64 = ao_line.split_whitespace().collect::<Vec<_>>().windows(2).find(|w| w[1] == "rays/px").map(|w| w[0].parse().unwrap()).unwrap();
    assert!(per_px > 0.0 && per_px <= 3.0, "AO rays per pixel after setting 3 rays: {ao_line}");
    // AO is one value per pixel: the inspector shows it grey, unlike the shaded frame.
    let img = load(&dir.join("ao.png"));
    let grey = img.pixels().filter(|p| p[0].abs_diff(p[1]) <= 2 && p[1].abs_diff(p[2]) <= 2).count() as f64 / (img.width() * img.height()) as f64;
    assert!(grey > 0.95, "the AO texture is shown as grey ({:.1}% grey pixels)", grey * 100.0);
    assert!(mean_abs_diff(&img, full_rt) > 5.0, "the viewport shows the AO texture, not the output");
}

#[test]
fn script_switches_mode_sets_a_parameter_and_shows_a_pass() {
    let x = XServer::start();
    let dir = common::gltf_doc::temp_dir("viewer-script");
    let steps = script_steps(&dir);
    let (_, log) = run_script(&x, &dir, &steps, &["default", "--mode", "raster", "--width", "320", "--height", "180"]);

    // The overlay lists the running plan's passes with their timings, the adapter and back-end.
    let text = |name: &str| std::fs::read_to_string(dir.join(format!("{name}.png.overlay.txt"))).unwrap();
    let raster = text("overlay");
    for needle in ["mode: raster", "passes:", "shadow_map/", "forward/", "tonemap/tonemap: GPU", "adapter: ", "back-end: "] {
        assert!(raster.contains(needle), "overlay of the raster graph lacks `{needle}`:\n{raster}");
    }
    // Overlay drawn over the frame: the screenshot with it differs from the one without.
    let (with, without) = (load(&dir.join("overlay.png")), load(&dir.join("raster.png")));
    assert!(mean_abs_diff(&with, &without) > 5.0, "the overlay is drawn");

    // The image changes with the mode (overlay hidden in both). The modes share one shading
    // model and one reading of the materials, so they differ only where their techniques do
    // (shadow maps against ray-traced shadows, AO, reflections): measured 1.35 on lavapipe
    // (8-bit mean |diff|); a frame the switch did not reach differs by 0.
    let full_rt = load(&dir.join("full_rt.png"));
    let d = mean_abs_diff(&without, &full_rt);
    assert!(d > 0.5, "raster and full RT frames differ (mean |diff| {d:.2})");

    check_ao_inspection(&dir, &full_rt);

    // Switching the effect off culls its passes.
    let off = text("ao_off");
    assert!(off.contains("switched off: ao") && !off.contains("ao/ao:"), "AO switched off:\n{off}");

    // The back-end switch, and a recorded track that loads and plays.
    let compute = text("compute");
    assert!(compute.contains("back-end: compute") && compute.contains("gbuffer/primary: GPU"), "after the back-end switch:\n{compute}");
    let track = raygraph::scene::track::Track::load(&dir.join("track.ron")).unwrap();
    assert!(track.keys.len() >= 2, "recorded keys: {}", track.keys.len());
    assert!(log.contains("track saved to"), "{log}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Lines the child prints on stdout, as they come.
fn lines(child: &mut Child) -> Receiver<String> {
    read_lines(child.stdout.take().unwrap())
}

fn read_lines(stream: impl std::io::Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stream).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// Reads lines until one satisfies `want` (within 180 s); returns it.
fn wait_for(rx: &Receiver<String>, seen: &mut Vec<String>, what: &str, want: impl Fn(&str) -> bool) -> String {
    let deadline = Instant::now() + Duration::from_secs(180);
    while let Some(left) = deadline.checked_duration_since(Instant::now()) {
        match rx.recv_timeout(left) {
            Ok(line) => {
                seen.push(line.clone());
                if want(&line) {
                    return line;
                }
            }
            Err(_) => break,
        }
    }
    panic!("waited for {what}; the viewer printed:\n{}", seen.join("\n"));
}

fn frame_number(line: &str) -> Option<u64> {
    line.strip_prefix("frame ")?.parse().ok()
}

struct KillOnDrop(Child);

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn a_broken_shader_keeps_the_last_good_graph_running_until_it_is_fixed() {
    let x = XServer::start();
    let dir = common::gltf_doc::temp_dir("viewer-reload");
    for d in ["graph", "layers", "shaders"] {
        common::copy_dir(&common::repo().join(d), &dir.join(d));
    }
    let shader: PathBuf = dir.join("shaders/tonemap/tonemap.wgsl");
    let good = std::fs::read_to_string(&shader).unwrap();
    let graph = dir.join("graph/hybrid.ron");
    let mut child = x
        .viewer(&["default", "--graph", graph.to_str().unwrap(), "--width", "160", "--height", "90", "--frames", "100000", "--verbose"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let rx = lines(&mut child);
    let child = KillOnDrop(child);
    let mut seen = Vec::new();
    wait_for(&rx, &mut seen, "the first frames", |l| frame_number(l).is_some_and(|n| n >= 3));

    // Break the file: an error naming the file and line, and frames go on.
    let broken_line = good.lines().count() + 2;
    raygraph::util::write_atomic(&shader, format!("{good}\n fn broken( {{\n").as_bytes()).unwrap();
    let error = wait_for(&rx, &mut seen, "the reload error", |l| l.starts_with("reload failed"));
    let location = format!("tonemap.wgsl:{broken_line}:");
    assert!(error.contains(&location), "the error names {location}: {error}");
    let at_error = seen.iter().rev().find_map(|l| frame_number(l)).unwrap_or(0);
    wait_for(&rx, &mut seen, "frames after the error", |l| frame_number(l).is_some_and(|n| n >= at_error + 5));

    // Fix it: the graph is compiled again and keeps rendering.
    raygraph::util::write_atomic(&shader, good.as_bytes()).unwrap();
    wait_for(&rx, &mut seen, "the reload after the fix", |l| l.starts_with("reloaded"));
    let at_fix = seen.iter().rev().find_map(|l| frame_number(l)).unwrap_or(0);
    wait_for(&rx, &mut seen, "frames after the fix", |l| frame_number(l).is_some_and(|n| n >= at_fix + 3));
    drop(child);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A layer whose shader never ends: the frame runs past the GPU deadline, and the viewer ends
/// with the error naming the pass (status 1) instead of hanging.
#[test]
fn a_shader_that_never_ends_stops_the_viewer_with_the_deadline_error() {
    let x = XServer::start();
    let (_project, graph) = common::endless_fog::project();
    let start = Instant::now();
    let args = ["default", "--graph", graph.to_str().unwrap(), "--width", "32", "--height", "32", "--frames", "20", "--gpu-timeout", "2"];
    let (ok, _, log) = run_with_timeout(x.viewer(&args), 60);
    println!("{log}\n(after {:?})", start.elapsed());
    assert!(!ok, "a frame past the deadline must fail the viewer:\n{log}");
    assert!(log.contains("the GPU ran past its deadline of 2 s") && log.contains("`fog/fog`"), "{log}");
    assert!(!log.contains("panicked"), "{log}");
}

/// The viewer on an accumulating graph (`graph/hybrid_denoised.ron`): a camera move restarts
/// the history, and with the reset switched off (`ResetHistoryOnMove(false)`) a small move
/// keeps it, as the overlay's history line reports.
#[test]
fn a_camera_move_resets_the_accumulation_unless_switched_off() {
    let x = XServer::start();
    let dir = common::gltf_doc::temp_dir("viewer-history");
    let shot = |name: &str| dir.join(name).display().to_string();
    let steps = format!(
        r#"(frame: 2, action: Camera(position: (0.0, 2.0, 6.0), target: (0.0, 0.5, 0.0))),
                (frame: 6, action: Screenshot("{reset}")),
                (frame: 7, action: ResetHistoryOnMove(false)),
                (frame: 8, action: Camera(position: (0.02, 2.0, 6.0), target: (0.0, 0.5, 0.0))),
                (frame: 11, action: Screenshot("{kept}")),
                (frame: 12, action: Quit),"#,
        reset = shot("reset.png"),
        kept = shot("kept.png"),
    );
    run_script(&x, &dir, &steps, &["default", "--graph", "graph/hybrid_denoised.ron", "--width", "160", "--height", "90"]);
    // (frames valid, resets) from the overlay's history line.
    let history = |name: &str| {
        let text = std::fs::read_to_string(dir.join(format!("{name}.png.overlay.txt"))).unwrap();
        let line = text.lines().find(|l| l.starts_with("history: ")).unwrap_or_else(|| panic!("no history line:\n{text}")).to_string();
        let numbers: Vec<u64> = line.split(|c: char| !c.is_ascii_digit()).filter(|s| !s.is_empty()).map(|s| s.parse().unwrap()).collect();
        (numbers[0], numbers[1], line)
    };
    let (valid, resets, line) = history("reset");
    assert_eq!(resets, 1, "the move at frame 2 reset the history: {line}");
    assert!((1..=4).contains(&valid), "valid again since the move: {line}");
    let (valid_after, resets_after, line) = history("kept");
    assert_eq!(resets_after, 1, "no reset with the switch off: {line}");
    assert!(valid_after >= valid + 4 && line.contains("kept across camera moves"), "the history stayed valid across the small move: {line}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An animated file in the viewer: the clock plays (1/60 s a frame in scripted runs), pauses,
/// seeks and runs at another speed; the overlay shows the clip, the time and what the
/// acceleration-structure cache did; paused frames are identical and the played ones move.
#[test]
fn the_animation_clock_plays_pauses_seeks_and_changes_speed() {
    let x = XServer::start();
    let dir = common::gltf_doc::temp_dir("viewer-anim");
    let shot = |name: &str| dir.join(name).display().to_string();
    let steps = format!(
        r#"(frame: 1, action: Overlay(false)),
                (frame: 3, action: Screenshot("{playing}")),
                (frame: 4, action: Play(false)),
                (frame: 4, action: Seek(0.5)),
                (frame: 6, action: Screenshot("{paused}")),
                (frame: 8, action: Screenshot("{still}")),
                (frame: 9, action: Speed(2.0)),
                (frame: 9, action: Play(true)),
                (frame: 14, action: Screenshot("{fast}")),
                (frame: 15, action: Quit),"#,
        playing = shot("playing.png"),
        paused = shot("paused.png"),
        still = shot("still.png"),
        fast = shot("fast.png"),
    );
    run_script(
        &x,
        &dir,
        &steps,
        &["assets/gltf/animated/skinned_cylinder.gltf", "--mode", "hybrid", "--backend", "compute", "--width", "160", "--height", "90"],
    );
    let overlay = |name: &str| std::fs::read_to_string(dir.join(format!("{name}.png.overlay.txt"))).unwrap();
    let clock = |name: &str| {
        let text = overlay(name);
        let line = text.lines().find(|l| l.starts_with("animation: ")).unwrap_or_else(|| panic!("no animation line:\n{text}")).to_string();
        let time: f32 = line.split(" at ").nth(1).and_then(|r| r.split(' ').next()).and_then(|t| t.parse().ok()).unwrap_or_else(|| panic!("{line}"));
        (time, line)
    };
    let (t, line) = clock("playing");
    assert!(line.contains("`bend`") && line.contains("playing at 1.00x") && t > 0.0 && t < 0.1, "{line}");
    let (t, line) = clock("paused");
    assert!(line.contains("paused") && (t - 0.5).abs() < 1e-6, "{line}");
    assert_eq!(clock("still").0, t, "paused: the time stays");
    let (t_fast, line) = clock("fast");
    assert!(line.contains("playing at 2.00x") && t_fast > 0.5 + 4.0 * 2.0 / 60.0 - 1e-4 && t_fast < 0.5 + 7.0 * 2.0 / 60.0, "{line}");
    let accel = overlay("fast");
    assert!(
        accel.lines().any(|l| l.starts_with("acceleration structures this frame:") && l.contains("1 deforming meshes") && l.contains("refitted")),
        "{accel}"
    );
    assert_eq!(mean_abs_diff(&load(&dir.join("paused.png")), &load(&dir.join("still.png"))), 0.0, "paused frames are identical");
    assert!(mean_abs_diff(&load(&dir.join("still.png")), &load(&dir.join("fast.png"))) > 0.05, "played frames move");
    let _ = std::fs::remove_dir_all(&dir);
}
