//! `raygraph bench rays --quick` as a user runs it: the results folder holds the CSV and the
//! markdown with every column, rays counted on the GPU, and no NaN, also when the run is
//! interrupted. Speed is not checked.

mod common;
use std::process::Command;

/// The back-ends lavapipe (CI) has: ray-query, compute and rt-pipeline.
const LAVAPIPE_BACKENDS: usize = 3;

#[test]
fn bench_rays_quick_writes_a_complete_table() {
    let out = common::gltf_doc::temp_dir("bench-rays");
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "rays", "--quick", "--out"]).arg(&out).output().unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap();
    assert_plots(&out);
    let md = std::fs::read_to_string(out.join("rays.md")).unwrap();
    assert!(md.contains("adapter:") && md.contains("revision:") && md.contains("resolution: 48x27"), "{md}");
    assert!(
        md.contains("4 AO rays of length 0.05 x the scene's bounding radius") && csv.contains("# Scene workload"),
        "the definitions are in both files: {md}"
    );
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header,
        [
            "test",
            "scene",
            "camera",
            "backend",
            "fps",
            "gpu_ms",
            "wall_ms",
            "rays_per_frame",
            "rays_per_pixel",
            "grays_per_s",
            "hit_fraction",
            "rfps",
            "rays_per_pixel_by_pass",
            "executors_gpu_ms"
        ]
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 3 scenes + Miss (outside) + Miss (inside) + Stress on the atrium, for every back-end
    // lavapipe has.
    assert_eq!(rows.len(), 6 * LAVAPIPE_BACKENDS, "{csv}");
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        let rays: u64 = r[7].parse().unwrap();
        assert!(rays > 0, "no rays counted: {r:?}");
        for v in &r[4..11] {
            let x: f64 = v.parse().unwrap();
            assert!(x.is_finite() && x >= 0.0, "{r:?}");
        }
        let (gpu_ms, wall_ms): (f64, f64) = (r[5].parse().unwrap(), r[6].parse().unwrap());
        assert!(wall_ms > 0.0 && gpu_ms > 0.0, "both times measured: {r:?}");
        // lavapipe: one executor a row (src/bench/repeat.rs), the one reported (3 decimals).
        let executors: Vec<f64> = r[13].split(';').map(|v| v.parse().unwrap()).collect();
        assert!(executors.len() == 1 && (executors[0] - gpu_ms).abs() <= 0.0006, "{r:?}");
        // Rays per pixel by pass add up to the row's rays per pixel.
        let by_pass: f64 = r[12].split(';').map(|p| p.split_once('=').unwrap().1.parse::<f64>().unwrap()).sum();
        let per_pixel: f64 = r[8].parse().unwrap();
        assert!((by_pass - per_pixel).abs() <= 0.01 * per_pixel + 0.02, "{r:?}");
        match r[0] {
            "Miss (outside)" | "Miss (inside)" => assert_eq!((r[1], r[10]), ("atrium", "0.0000"), "every Miss ray misses"),
            "Stress" => {
                assert_eq!((r[1], r[2]), ("atrium", "preset `stress`"));
                assert!(r[10].parse::<f64>().unwrap() >= 0.99, "a Stress view shows no sky: {r:?}");
            }
            _ => {
                assert_eq!((r[0], r[2]), (r[1], "the scene's camera"));
                assert!(r[11].parse::<f64>().unwrap() > 0.0, "RFPS of a scene row");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// A glTF file has no `stress` preset: its Stress view is derived (its camera narrowed until it
/// shows no sky) and the row says so; it has no `miss_inside` preset either, so no Miss (inside).
#[test]
fn bench_rays_derives_a_stress_view_for_a_file() {
    let out = common::gltf_doc::temp_dir("bench-rays-file");
    let helmet = "assets/gltf/DamagedHelmet/DamagedHelmet.glb";
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .current_dir(common::repo())
        .args(["bench", "rays", "--quick", "--backend", "compute", "--scenes", helmet, "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let rows: Vec<Vec<&str>> = csv.lines().filter(|l| !l.starts_with('#')).skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), [helmet, "Miss (outside)", "Stress"], "{csv}");
    let stress = &rows[2];
    assert!(stress[2].starts_with("derived: the scene's camera narrowed to"), "{stress:?}");
    assert!(stress[10].parse::<f64>().unwrap() >= 0.99, "{stress:?}");
}

#[test]
fn bench_build_quick_writes_a_complete_table() {
    let out = common::gltf_doc::temp_dir("bench-build");
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "build", "--quick", "--out"]).arg(&out).output().unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("build.csv")).unwrap();
    assert_plots(&out);
    assert!(std::fs::read_to_string(out.join("build.md")).unwrap().contains("adapter:"));
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, ["scene", "factor", "triangles", "backend", "blas_ms", "tlas_ms", "total_ms", "blas_sah", "tlas_sah", "trace_ms", "mrays_per_s"]);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // box and organic, N = 1 and 2, every back-end.
    assert_eq!(rows.len(), 4 * LAVAPIPE_BACKENDS, "{csv}");
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        let n: usize = r[1].parse().unwrap();
        let base = if r[0] == "box" { 12 } else { 3920 };
        assert_eq!(r[2].parse::<usize>().unwrap(), base * n * n * n, "N×N×N copies: {r:?}");
        assert!(r[6].parse::<f64>().unwrap().is_finite());
        assert!(r[9].parse::<f64>().is_ok_and(|x| x > 0.0), "the trace was timed on the GPU: {r:?}");
        if r[3] == "compute" {
            let sah: f64 = r[7].parse().unwrap();
            assert!(sah.is_finite() && sah >= 1.0, "SAH cost of the CPU builder: {r:?}");
        }
    }
    // The merged layout's GPU refit (the run fails if moving the instances did not refit).
    let refit = std::fs::read_to_string(out.join("refit.csv")).unwrap();
    let mut lines = refit.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next().unwrap(), "scene,triangles,levels,dispatches,rebuild_ms,refit_gpu_ms_median,refit_gpu_ms_min,refit_cpu_ms");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), ["box", "organic"], "{refit}");
    for r in &rows {
        assert!(r[2].parse::<usize>().unwrap() >= 1, "tree levels: {r:?}");
        assert!(r[3].parse::<usize>().unwrap() >= 1, "dispatches: {r:?}");
        assert!(r[5].parse::<f64>().is_ok_and(|x| x > 0.0), "the refit was timed on the GPU: {r:?}");
    }
    // The CPU build of each merged scene: timed, with the tree's SAH cost and depth.
    let cpu = std::fs::read_to_string(out.join("cpu_build.csv")).unwrap();
    let mut lines = cpu.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next().unwrap(), "scene,triangles,threads,first_ms,median_ms,min_ms,builds,sah,depth");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.iter().map(|r| (r[0], r[1])).collect::<Vec<_>>(), [("box", "12"), ("organic", "3920")], "{cpu}");
    for r in &rows {
        let ms: Vec<f64> = r[3..6].iter().map(|x| x.parse().unwrap()).collect();
        assert!(ms.iter().all(|&x| x > 0.0) && ms[2] <= ms[1], "build times: {r:?}");
        assert!(r[7].parse::<f64>().is_ok_and(|x| x.is_finite() && x >= 1.0), "SAH cost: {r:?}");
        assert!(r[8].parse::<usize>().is_ok_and(|d| d >= 1), "depth: {r:?}");
    }
    assert!(std::fs::read_to_string(out.join("cpu_build.md")).unwrap().contains("revision:"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_rays_coverage_rows_see_the_scene_at_the_fraction_asked() {
    let out = common::gltf_doc::temp_dir("bench-rays-coverage");
    let args = ["bench", "rays", "--quick", "--scenes", "organic", "--coverage", "0.1", "--backend", "compute", "--out"];
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(args).arg(&out).output().unwrap();
    assert!(run.status.success(), "{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let rows: Vec<Vec<&str>> = csv.lines().filter(|l| !l.starts_with('#')).skip(1).map(|l| l.split(',').collect()).collect();
    let at: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == "organic at 10%").collect();
    assert_eq!(at.len(), 1, "one row on the one back-end: {csv}");
    // "the scene's camera 1.52x as far from its target: 10.4% of the pixels covered"
    let camera = at[0][2];
    let covered: f64 = camera.split(": ").nth(1).and_then(|s| s.split('%').next()).and_then(|s| s.parse().ok()).unwrap_or_else(|| panic!("{camera}"));
    assert!((covered - 10.0).abs() <= 1.5, "within 15% of the fraction asked: {camera}");
    assert!(at[0][8].parse::<f64>().is_ok_and(|x| x > 0.0), "rays counted: {:?}", at[0]);
}

#[test]
fn bench_scale_quick_measures_every_step_on_every_back_end() {
    let out = common::gltf_doc::temp_dir("bench-scale");
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "scale", "--quick", "--out"]).arg(&out).output().unwrap();
    assert!(run.status.success(), "{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(std::fs::read_to_string(out.join("scale.md")).unwrap().contains("revision:"));
    let csv = std::fs::read_to_string(out.join("scale.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let rows = csv_rows(
        &csv,
        "step,triangles,backend,workload_grays,stress_grays,build_cpu_ms,build_gpu_ms,gpu_builder_ms,bytes_per_triangle,frame_wall_ms,frame_gpu_ms",
    );
    // box x1 and organic x2 (8 copies of 3,920 unique triangles), every back-end.
    assert_eq!(rows.len(), 2 * LAVAPIPE_BACKENDS, "{csv}");
    for r in &rows {
        let triangles: usize = r[1].parse().unwrap();
        assert_eq!(triangles, if r[0] == "box x1" { 12 } else { 8 * 3920 }, "{r:?}");
        let positive = |k: usize| r[k].parse::<f64>().is_ok_and(|x| x > 0.0 && x.is_finite());
        assert!(positive(3) && positive(4), "rays counted and timed on the GPU: {r:?}");
        assert!(positive(5) && positive(9) && positive(10), "build and frame times: {r:?}");
        assert!(positive(8), "the scene and its acceleration structure take GPU memory: {r:?}");
        assert_eq!(r[7].is_empty(), r[2] != "compute", "the GPU builder is timed for compute's merged layout only: {r:?}");
    }
}

/// Runs `raygraph bench NAME --quick` and returns the CSV's header and rows.
fn quick_csv(name: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let (header, rows, _) = quick_csv_with(name, &[]);
    (header, rows)
}

/// [`quick_csv`], also returning the text of another results file (if named and present).
fn quick_csv_with(name: &str, others: &[&str]) -> (Vec<String>, Vec<Vec<String>>, Vec<Option<String>>) {
    let out = common::gltf_doc::temp_dir(&format!("bench-{name}"));
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", name, "--quick", "--out"]).arg(&out).output().unwrap();
    assert!(run.status.success(), "{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(std::fs::read_to_string(out.join(format!("{name}.md"))).unwrap().contains("revision:"));
    let csv = std::fs::read_to_string(out.join(format!("{name}.csv"))).unwrap();
    let other = others.iter().map(|other| std::fs::read_to_string(out.join(other)).ok()).collect();
    assert_plots(&out);
    let _ = std::fs::remove_dir_all(&out);
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap().split(',').map(str::to_string).collect::<Vec<_>>();
    let rows = lines.map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>()).collect();
    (header, rows, other)
}

#[test]
fn bench_track_quick_plays_the_track_through_every_mode() {
    let (header, rows) = quick_csv("track");
    assert_eq!(header, ["mode", "backend", "frame", "gpu_ms", "fps", "rays", "grays_per_s"]);
    // raster once, hybrid and full RT per back-end; every 60th frame of the 241-frame track.
    assert_eq!(rows.len(), 5 * (1 + 2 * LAVAPIPE_BACKENDS), "{rows:?}");
    for r in &rows {
        assert_eq!(r.len(), header.len());
        let fps: f64 = r[4].parse().unwrap();
        assert!(fps.is_finite() && fps > 0.0, "{r:?}");
        let rays: u64 = r[5].parse().unwrap();
        assert_eq!(rays > 0, r[0] != "raster", "ray-traced modes count rays, raster none: {r:?}");
    }
}

/// `bench anim --quick`: the two small animated files, 24 frames under each policy: the auto
/// and always-refit policies refit every frame after the first, always-rebuild never; every
/// frame traces rays.
#[test]
fn bench_anim_quick_compares_the_cache_policies() {
    let (header, rows) = quick_csv("anim");
    assert_eq!(header, ["scene", "policy", "frame", "pose_ms", "accel_gpu_ms", "accel_cpu_ms", "work", "sah_growth", "trace_ms", "rays", "grays_per_s"]);
    assert_eq!(rows.len(), 2 * 4 * 24, "2 scenes x 4 policies x 24 frames");
    for scene in ["skinned_cylinder", "spinner"] {
        // (The first timed frame refits too where the warm-up's pose differs from frame 0's.)
        for (policy, refits) in [("refit until SAH x1.1", 23..=24), ("always refit", 23..=24), ("always rebuild", 0..=0)] {
            let sel: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == scene && r[1] == policy).collect();
            assert!(refits.contains(&sel.iter().filter(|r| r[6] == "refit").count()), "{scene}, {policy}: {sel:?}");
            assert!(sel.iter().all(|r| r[9].parse::<u64>().unwrap() > 0), "{scene}, {policy}: rays every frame");
        }
        // The cost policy refits or rebuilds every frame that moved something.
        let cost: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == scene && r[1] == "refit until it cost a rebuild").collect();
        assert!(cost.iter().filter(|r| r[6] != "none").count() >= 23, "{scene}: {cost:?}");
    }
}

#[test]
fn bench_depth_quick_counts_more_reflection_rays_with_more_bounces() {
    let (header, rows) = quick_csv("depth");
    assert_eq!(header, ["backend", "bounces", "reflection_ms", "rays_per_pixel", "grays_per_s", "frame_ms"]);
    assert_eq!(rows.len(), 3 * LAVAPIPE_BACKENDS, "3 bounce counts on every back-end: {rows:?}");
    for pair in rows.windows(2).filter(|w| w[0][0] == w[1][0]) {
        let (a, b): (f64, f64) = (pair[0][3].parse().unwrap(), pair[1][3].parse().unwrap());
        assert!(b >= a && a > 0.0, "rays per pixel grow with the bounce count: {pair:?}");
    }
}

/// Every bench writes PNG plots that decode to a picture with more than a blank page in it.
fn assert_plots(dir: &std::path::Path) {
    let pngs: Vec<_> = std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "png")).collect();
    assert!(!pngs.is_empty(), "no plot in {}", dir.display());
    for p in pngs {
        let img = image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())).to_rgb8();
        let colours: std::collections::HashSet<[u8; 3]> = img.pixels().map(|px| px.0).collect();
        assert!(colours.len() > 10, "{} looks empty", p.display());
    }
}

/// A bench interrupted mid-way (SIGINT, as Ctrl-C sends) leaves its results folder with the rows
/// finished so far, each file whole: the files are rewritten atomically after every row.
#[test]
fn an_interrupted_bench_leaves_the_rows_finished_so_far() {
    let out = common::gltf_doc::temp_dir("bench-interrupted");
    let mut command = Command::new(env!("CARGO_BIN_EXE_raygraph"));
    command
        .current_dir(common::repo())
        .args(["bench", "rays", "--quick", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
    // A shell that starts a job in the background (`cmd &` without job control) ignores SIGINT
    // in it, and children inherit that: the bench would then run to the end. A terminal's Ctrl-C
    // reaches a process with the default action, so restore it.
    // SAFETY: `signal` is async-signal-safe, as `pre_exec` requires.
    unsafe {
        std::os::unix::process::CommandExt::pre_exec(&mut command, || {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = command.spawn().unwrap();
    let data_rows = |csv: &str| csv.lines().filter(|l| !l.starts_with('#')).count().saturating_sub(1);
    let start = std::time::Instant::now();
    loop {
        let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap_or_default();
        if data_rows(&csv) >= 2 {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the bench ended before two rows were written");
        assert!(start.elapsed().as_secs() < 600, "no rows after 10 minutes");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let status = child.wait().unwrap();
    assert!(!status.success(), "the bench was interrupted: {status}");
    let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let columns = lines.next().unwrap().split(',').count();
    let rows: Vec<&str> = lines.collect();
    assert!((2..10).contains(&rows.len()), "{csv}");
    for r in &rows {
        assert_eq!(r.split(',').count(), columns, "a whole row: {r}");
    }
    let md = std::fs::read_to_string(out.join("rays.md")).unwrap();
    // The two files are written one after the other (each atomically), the markdown first: an
    // interrupt between the two writes leaves the markdown one row ahead. (Seen when the CSV was
    // written first: the signal landed between the writes, CSV 2 rows, markdown 1.)
    let md_rows = md.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| test") && !l.starts_with("| ---")).count();
    assert!(md_rows == rows.len() || md_rows == rows.len() + 1, "markdown rows {md_rows}, CSV rows {}: {md}", rows.len());
    println!("interrupted after {} rows: {:?}", rows.len(), std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name()).collect::<Vec<_>>());
    let _ = std::fs::remove_dir_all(&out);
}

/// `raygraph bench error --quick`: AO against its closed form on every back-end; the RMSE of
/// white-noise sampling falls with rays per pixel at the Monte Carlo rate (fitted log-log slope
/// within 0.1 of -0.5) and those of the R2 sequence and of the net fall faster; the bias is within noise; FLIP
/// is reported (mean at most the 99th percentile, both in (0, 1]) and falls from 1 to 64 rays.
#[test]
fn bench_error_quick_converges_at_the_expected_rates() {
    let (header, rows, others) = quick_csv_with("error", &["hybrid.csv", "shadow_maps.csv", "filters.csv", "filters_track.csv"]);
    let [hybrid, shadow_maps, filters, filters_track] = <[Option<String>; 4]>::try_from(others).unwrap();
    check_shadow_map_sweep(&shadow_maps.expect("bench error writes shadow_maps.csv"));
    check_filters(&filters.expect("bench error writes filters.csv"), &filters_track.expect("bench error writes filters_track.csv"));
    // Hybrid against full RT: untextured, the two modes draw the same image (the G-buffer is
    // the only difference); textured, nearly; both rows per back-end.
    let hybrid = hybrid.expect("bench error writes hybrid.csv");
    let mut lines = hybrid.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next().unwrap(), "scene,textures,backend,hybrid_ms,full_rt_ms,rmse,differing,flip_mean,flip_p99");
    let hybrid_rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(hybrid_rows.len(), 2 * LAVAPIPE_BACKENDS, "{hybrid}");
    for r in &hybrid_rows {
        let flip_mean: f64 = r[7].parse().unwrap();
        // Measured on lavapipe (Mesa 25.0.7), 2026-11-29: untextured, RMSE and ꟻLIP 0 on every
        // back-end (identical images); textured, ꟻLIP mean 0.00003-0.00006.
        if r[1] == "false" {
            assert!(flip_mean == 0.0, "untextured, hybrid and full RT draw the same image: {r:?}");
        } else {
            // Textured: full RT's primary rays pick mip levels from their ray cones as the
            // rasterizer does from derivatives (level 0 everywhere measured FLIP 0.196 here).
            assert!(flip_mean < 0.0002, "textured, hybrid and full RT nearly agree: {r:?}");
        }
    }
    assert_eq!(header, ["backend", "sampling", "rays", "ao_ms", "rmse", "relmse", "bias", "variance", "flip_mean", "flip_p99"]);
    let mut backends: Vec<String> = rows.iter().map(|r| r[0].clone()).collect();
    backends.dedup();
    assert_eq!(backends.len(), LAVAPIPE_BACKENDS, "every back-end runs: {backends:?}");
    for b in &backends {
        let slope = |sampling: &str| {
            // Rows of zero error are left out, as the bench's own fit does: the net is exact here
            // from 4 rays on (the open directions are those with u.x >= (h/R)^2 = 1/4, a union
            // of its cells; measured on lavapipe 2026-12-01: RMSE 0 at 4, 8 and 16 rays, 0.0005
            // and 0.0002 at 32 and 64), which leaves it four rows to fit.
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| &r[0] == b && r[1] == sampling && r[4].parse::<f64>().unwrap() > 0.0)
                .map(|r| (r[2].parse::<f64>().unwrap().ln(), r[4].parse::<f64>().unwrap().ln()))
                .collect();
            assert!(pts.len() >= 4, "{b} {sampling}: {} rows", pts.len());
            let n = pts.len() as f64;
            let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
            pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
        };
        let (white, r2, net) = (slope("white"), slope("r2"), slope("net"));
        for sampling in ["white", "r2", "net"] {
            let flip: Vec<f64> = rows.iter().filter(|r| &r[0] == b && r[1] == sampling).map(|r| r[8].parse().unwrap()).collect();
            assert!(flip.last() < flip.first(), "{b} {sampling}: FLIP must fall with more rays: {flip:?}");
        }
        println!("{b}: slope white {white:.3}, r2 {r2:.3}, net {net:.3}");
        assert!((white + 0.5).abs() <= 0.1, "{b}: white-noise slope {white}");
        assert!(r2 < white - 0.1, "{b}: the R2 sequence converges faster than white noise ({r2} against {white})");
        assert!(net < white - 0.1, "{b}: the net converges faster than white noise ({net} against {white})");
        for r in rows.iter().filter(|r| &r[0] == b) {
            let (bias, variance, rays): (f64, f64, f64) = (r[6].parse().unwrap(), r[7].parse().unwrap(), r[2].parse().unwrap());
            assert!(r[3].parse::<f64>().unwrap() > 0.0, "the AO pass was timed: {r:?}");
            // Bias over 1024 pixels x 4 seeds: within 5 sigma of a Bernoulli(0.25) mean.
            let sigma = (0.25 * 0.75 / rays / 4096.0).sqrt();
            assert!(bias.abs() <= 5.0 * sigma + 1e-4 && variance >= 0.0, "{b}: {r:?}");
            let (flip_mean, flip_p99): (f64, f64) = (r[8].parse().unwrap(), r[9].parse().unwrap());
            // FLIP is 0 only where the image is exact (the net's rows of zero error, above).
            let exact = r[4].parse::<f64>().unwrap() == 0.0;
            assert!((flip_mean > 0.0 || exact) && flip_mean <= flip_p99 && flip_p99 <= 1.0, "FLIP mean and 99th percentile: {r:?}");
        }
    }
}

/// The shadow-map sweep of `bench error --quick`: every setting (2 map sizes x 2 normal offsets
/// x 3 biases) compared over a non-empty set of lit and of shadowed pixels, both rates in
/// [0, 1], the shadow-map pass timed; and, at each map size without normal offset, the
/// largest bias gives fewer false shadows (shadow acne) than no bias.
fn check_shadow_map_sweep(csv: &str) {
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next().unwrap(), "scene,resolution,bias,normal_offset,lit_pixels,shadowed_pixels,false_shadow,false_lit,shadow_map_ms,rt_shadow_ms");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').skip(1).map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 12, "{csv}");
    for r in &rows {
        let (lit, shadowed, false_shadow, false_lit, ms) = (r[3], r[4], r[5], r[6], r[7]);
        assert!(lit > 0.0 && shadowed > 0.0, "rates over non-empty sets: {r:?}");
        assert!((0.0..=1.0).contains(&false_shadow) && (0.0..=1.0).contains(&false_lit), "rates: {r:?}");
        assert!(ms > 0.0, "the shadow-map pass was timed: {r:?}");
    }
    let mut sizes: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    sizes.dedup();
    assert_eq!(sizes.len(), 2, "{csv}");
    for size in sizes {
        let unoffset: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == size && r[2] == 0.0).collect();
        let by_bias = |pick: fn(f64, f64) -> bool| *unoffset.iter().reduce(|a, b| if pick(b[1], a[1]) { b } else { a }).unwrap();
        let (none, largest) = (by_bias(|x, y| x < y), by_bias(|x, y| x > y));
        println!("map {size}: false shadows {:.4} without bias, {:.4} at bias {}", none[5], largest[5], largest[1]);
        assert!(largest[1] > none[1] && largest[5] < none[5], "map {size}: a larger bias removes false shadows: {none:?} against {largest:?}");
    }
}

/// `raygraph bench roofline --quick` (CPU only): every test's row, with the bytes per ray that
/// its counts imply, and no ceiling below what Table 3 could hold (the counts are per ray).
#[test]
fn bench_roofline_quick_counts_bytes_per_ray() {
    let out = common::gltf_doc::temp_dir("bench-roofline");
    let run =
        Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "roofline", "--quick", "--out"]).arg(&out).output().unwrap();
    assert!(run.status.success(), "{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("roofline.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "test,rays,interior_per_ray,leaves_per_ray,triangles_per_ray,instances_per_ray,bytes_per_ray,ceiling_grays,achieved_grays,subgroup_share,interior_per_ray_hit_known"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // The quick run's last scene is the organic one: no `miss_inside` preset, so no Miss (inside).
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), ["box", "organic", "Miss (outside)", "Stress"], "{csv}");
    for r in &rows {
        let v: Vec<f64> = r[1..8].iter().map(|x| x.parse().unwrap()).collect();
        assert!(v[0] > 0.0, "rays counted: {r:?}");
        // bytes = 64 interior + 48 triangles + 64 instances, per ray.
        assert!((v[5] - (64.0 * v[1] + 48.0 * v[3] + 64.0 * v[4])).abs() <= 0.1 + 1e-3 * v[5], "{r:?}");
        // Every row's subgroup model: a share of the steps issued.
        let share: f64 = r[9].parse().unwrap();
        assert!(share > 0.0 && share <= 1.0, "subgroup share: {r:?}");
        // The primary tests only: a t_max at the hit from the start keeps a subset of the
        // nodes (the children's order does not depend on t_max), all of them for rays that miss.
        let primary = r[0] == "Miss (outside)" || r[0] == "Stress";
        assert_eq!(r[10].is_empty(), !primary, "hit known: {r:?}");
        if primary {
            let known: f64 = r[10].parse().unwrap();
            assert!(known >= 0.0 && known <= v[1], "hit known: {r:?}");
        }
    }
    assert_eq!(rows[2][10], rows[2][2], "Miss (outside)'s rays hit nothing: knowing that changes nothing: {csv}");
    assert!(rows[3][10].parse::<f64>().unwrap() > 0.0, "Stress's rays descend to their hits: {csv}");
    let stress: f64 = rows[3][6].parse().unwrap();
    let miss: f64 = rows[2][6].parse().unwrap();
    assert!(stress > 100.0 && miss < stress, "all-hit rays load more than all-miss ones: {csv}");
}

/// The rows of a CSV without its `#` comments and header.
fn csv_rows(text: &str, header: &str) -> Vec<Vec<String>> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next().unwrap(), header);
    lines.map(|l| l.split(',').map(str::to_string).collect()).collect()
}

/// `bench error`'s part on the filtered effects (quick: the default scene at 64x36, 1 and 2
/// rays, references of 64 frames at 2 rays). Every row is there and finite. Measured on
/// lavapipe (Mesa 25.0.7), 2026-11-29, and bounded within 3x of those ratios: AO's noisy error
/// falls with rays (relMSE 0.0271 at 1 ray, 0.0150 at 2: 0.55, the Monte Carlo rate's 0.5;
/// bound 0.7); GI's filtered error after the still frames is below its noisy one (0.0235
/// against 0.525 at 1 ray: 0.045; bound 0.135); and filtering cuts AO's and GI's flicker on the
/// still stretch (0.00079 against 0.00535: 0.15, bound 0.44; 0.0096 against 0.106: 0.091, bound
/// 0.27). Soft shadows (a penumbra of a few pixels in this scene at this size, so the noisy
/// signal is nearly exact) and glossy reflections (one mirror-like sphere) against their
/// references, measured the same day with the shadows filtered as a visibility ratio and the
/// temporal layer's consistent history taps: filtered shadows at rest ꟻLIP 0.0022 against the
/// noisy 0.0035 (0.63; bound 1.0: no worse), 1 and 8 frames after the turn 0.0035 and 0.0033
/// (bound 0.0105; the shadowed light filtered as it was before measured 0.0291 and 0.0242);
/// reflections after 8 still frames 0.00033 (bound 0.001) and 8 frames after the turn 0.0013
/// (bound 0.004).
fn check_filters(filters: &str, track: &str) {
    let rows = csv_rows(filters, "scene,effect,rays,filtered_frames,ms,relmse,flip_mean");
    assert_eq!(rows.len(), 3 * 2 * 3 + 3, "three effects x two ray counts x (noisy, 1st frame, settled), and reflections' three:\n{filters}");
    let value = |effect: &str, rays: &str, frames: &str, column: usize| -> f64 {
        let r = rows.iter().find(|r| r[1] == effect && r[2] == rays && r[3] == frames).unwrap_or_else(|| panic!("no row {effect} {rays} {frames}"));
        r[column].parse().unwrap()
    };
    for r in &rows {
        for c in 4..7 {
            let v: f64 = r[c].parse().unwrap();
            assert!(v.is_finite() && v >= 0.0, "{r:?}");
        }
        assert!(r[4].parse::<f64>().unwrap() > 0.0, "the passes were timed: {r:?}");
    }
    assert!(value("AO", "2", "0", 5) < 0.7 * value("AO", "1", "0", 5), "AO's noisy error falls with rays:\n{filters}");
    assert!(value("GI", "1", "8", 5) < 0.135 * value("GI", "1", "0", 5), "filtered GI beats noisy GI:\n{filters}");
    let track = csv_rows(track, "scene,effect,filtered,flicker_flip,still_flip,after_turn_1,after_turn_2,after_turn_4,after_turn_8");
    assert_eq!(track.len(), 4 * 2, "{track:?}");
    let cell =
        |effect: &str, filtered: &str, column: usize| -> f64 { track.iter().find(|r| r[1] == effect && r[2] == filtered).unwrap()[column].parse().unwrap() };
    for (effect, bound) in [("AO", 0.44), ("GI", 0.27)] {
        assert!(cell(effect, "true", 3) < bound * cell(effect, "false", 3), "{effect}: filtering cuts flicker: {track:?}");
    }
    for r in &track {
        assert!(r[3..].iter().all(|v| v.parse::<f64>().unwrap().is_finite()), "{r:?}");
    }
    assert!(cell("soft shadows", "true", 4) <= cell("soft shadows", "false", 4), "filtered shadows at rest no worse than noisy: {track:?}");
    for column in [5, 8] {
        assert!(cell("soft shadows", "true", column) < 0.0105, "filtered shadows after the turn (column {column}): {track:?}");
    }
    assert!(value("reflections", "1", "8", 6) < 0.001, "filtered reflections at rest against their reference:\n{filters}");
    assert!(cell("reflections", "true", 8) < 0.004, "filtered reflections 8 frames after the turn: {track:?}");
}
