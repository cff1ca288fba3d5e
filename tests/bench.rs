//! `raygraph bench rays --quick` as a user runs it: the results folder holds the CSV and the
//! markdown with every column, rays counted on the GPU, and no NaN. Speed is not checked.

mod common;
use std::process::Command;

#[test]
fn bench_rays_quick_writes_a_complete_table() {
    let out = common::gltf_doc::temp_dir("bench-rays");
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "rays", "--quick", "--out"]).arg(&out).output().unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("rays.csv")).unwrap();
    let md = std::fs::read_to_string(out.join("rays.md")).unwrap();
    assert!(md.contains("adapter:") && md.contains("revision:") && md.contains("resolution: 48x27"), "{md}");
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, ["test", "backend", "fps", "gpu_ms", "rays_per_frame", "rays_per_pixel", "grays_per_s", "hit_fraction", "rfps"]);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 3 scenes + Miss + Stress, for both back-ends lavapipe has.
    assert_eq!(rows.len(), 10, "{csv}");
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        let rays: u64 = r[4].parse().unwrap();
        assert!(rays > 0, "no rays counted: {r:?}");
        for v in &r[2..8] {
            let x: f64 = v.parse().unwrap();
            assert!(x.is_finite() && x >= 0.0, "{r:?}");
        }
        match r[0] {
            "Miss" => assert_eq!(r[7], "0.0000", "every Miss ray misses"),
            "Stress" => assert_eq!(r[7], "1.0000", "every Stress ray hits"),
            _ => assert!(r[8].parse::<f64>().unwrap() > 0.0, "RFPS of a scene row"),
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_build_quick_writes_a_complete_table() {
    let out = common::gltf_doc::temp_dir("bench-build");
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(common::repo()).args(["bench", "build", "--quick", "--out"]).arg(&out).output().unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.join("build.csv")).unwrap();
    assert!(std::fs::read_to_string(out.join("build.md")).unwrap().contains("adapter:"));
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, ["scene", "factor", "triangles", "backend", "blas_ms", "tlas_ms", "total_ms", "blas_sah", "tlas_sah", "trace_ms", "mrays_per_s"]);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // box and organic, N = 1 and 2, both back-ends.
    assert_eq!(rows.len(), 8, "{csv}");
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
    let _ = std::fs::remove_dir_all(&out);
}
