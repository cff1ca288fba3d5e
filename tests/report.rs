//! The per-pass profiling report (`runtime::report`) on synthetic frames: statistics against
//! hand-computed values, and the CSV, markdown, Chrome trace and file exports; the frame's time
//! outside the passes by part, in the report and on a rendered frame.

mod common;

use raygraph::accel::cache::RayStats;
use raygraph::runtime::profiler::{FramePhases, FrameTimings};
use raygraph::runtime::report::{Report, Summary, CSV_COLUMNS, TRACE_CPU_TID, TRACE_GPU_TID};
use serde_json::Value;

fn frame(gpu: Option<&[f64]>, cpu: &[f64], frame_ms: f64, pass_rays: &[Option<RayStats>]) -> FrameTimings {
    FrameTimings {
        gpu_ms: gpu.map(|g| g.to_vec()),
        cpu_ms: cpu.to_vec(),
        frame_ms,
        rays: None,
        pass_rays: pass_rays.to_vec(),
        accel: None,
        phases: Default::default(),
        skipped: vec![false; cpu.len()],
    }
}

fn rays(closest: u64, any: u64, hits: u64) -> Option<RayStats> {
    Some(RayStats { closest, any, invalid: 0, hits })
}

fn names(list: &[(&str, &'static str)]) -> Vec<(String, &'static str)> {
    list.iter().map(|(n, k)| (n.to_string(), *k)).collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

fn assert_summary(s: Option<Summary>, mean: f64, median: f64, min: f64, max: f64, n: usize) {
    let s = s.expect("a summary");
    assert!(close(s.mean, mean) && close(s.median, median) && close(s.min, min) && close(s.max, max) && s.n == n, "{s:?} != {mean} {median} {min} {max} n={n}");
}

/// Three frames of a raster pass and a trace pass, with timestamps; 1M pixels.
fn odd_report() -> Report {
    let frames = [
        frame(Some(&[1.0, 0.5]), &[0.5, 0.2], 5.0, &[None, rays(600_000, 400_000, 10)]),
        frame(Some(&[3.0, 1.0]), &[0.1, 0.2], 7.0, &[None, rays(1_000_000, 2_000_000, 30)]),
        frame(Some(&[2.0, 2.0]), &[0.3, 0.8], 6.0, &[None, rays(1_500_000, 500_000, 20)]),
    ];
    Report::new(&names(&[("gbuffer", "SceneRaster"), ("shadows", "Trace")]), 1_000_000, &frames)
}

#[test]
fn odd_frame_count_statistics() {
    let r = odd_report();
    assert_eq!(r.passes.len(), 2);
    let (g, s) = (&r.passes[0], &r.passes[1]);
    assert_eq!((g.name.as_str(), g.kind), ("gbuffer", "SceneRaster"));
    assert_summary(g.gpu_ms, 2.0, 2.0, 1.0, 3.0, 3);
    assert_summary(g.cpu_ms, 0.3, 0.3, 0.1, 0.5, 3);
    assert_eq!((g.rays, g.hits, g.rays_per_pixel, g.grays_per_s), (None, None, None, None), "a raster pass traces nothing");

    assert_summary(s.gpu_ms, 3.5 / 3.0, 1.0, 0.5, 2.0, 3);
    assert_summary(s.cpu_ms, 0.4, 0.2, 0.2, 0.8, 3);
    assert_eq!(s.rays, Some(2e6), "median of 1M, 3M, 2M traced");
    assert_eq!(s.hits, Some(20.0));
    assert!(close(s.rays_per_pixel.unwrap(), 2.0));
    // 2M rays in a median 1 ms: 2e9 rays/s.
    assert!(close(s.grays_per_s.unwrap(), 2.0), "{:?}", s.grays_per_s);

    // Per-frame totals: GPU 1.5, 4, 4; CPU 0.7, 0.3, 1.1; wall 5, 7, 6.
    assert_summary(r.gpu_total_ms, 9.5 / 3.0, 4.0, 1.5, 4.0, 3);
    assert_summary(r.cpu_total_ms, 0.7, 0.7, 0.3, 1.1, 3);
    assert_summary(r.frame_ms, 6.0, 6.0, 5.0, 7.0, 3);
}

#[test]
fn even_frame_count_without_timestamps() {
    let frames = [
        frame(None, &[1.0], 2.0, &[rays(10, 0, 1)]),
        frame(None, &[2.0], 3.0, &[rays(20, 20, 4)]),
        frame(None, &[3.0], 4.0, &[rays(5, 15, 2)]),
        frame(None, &[10.0], 11.0, &[rays(0, 30, 3)]),
    ];
    let r = Report::new(&names(&[("trace", "Trace")]), 10, &frames);
    let p = &r.passes[0];
    assert_eq!(p.gpu_ms, None);
    assert_summary(p.cpu_ms, 4.0, 2.5, 1.0, 10.0, 4);
    assert_eq!(p.rays, Some(25.0), "median of 10, 40, 20, 30");
    assert_eq!(p.hits, Some(2.5), "median of 1, 4, 2, 3");
    assert_eq!(p.rays_per_pixel, Some(2.5));
    assert_eq!(p.grays_per_s, None, "no GPU time, no GigaRays/s");
    assert_eq!(r.gpu_total_ms, None);
    assert_summary(r.frame_ms, 5.0, 3.5, 2.0, 11.0, 4);
}

#[test]
fn pass_beyond_the_timestamp_capacity_has_no_gpu_time() {
    // The timer covered only the first pass.
    let frames = [frame(Some(&[1.0]), &[0.1, 0.2], 3.0, &[]), frame(Some(&[2.0]), &[0.3, 0.4], 4.0, &[])];
    let r = Report::new(&names(&[("a", "Compute"), ("b", "Compute")]), 4, &frames);
    assert_summary(r.passes[0].gpu_ms, 1.5, 1.5, 1.0, 2.0, 2);
    assert_eq!(r.passes[1].gpu_ms, None);
    assert_summary(r.passes[1].cpu_ms, 0.3, 0.3, 0.2, 0.4, 2);
    assert_eq!(r.gpu_total_ms, None, "no frame has a GPU time for every pass");
    assert_eq!(r.passes[1].rays, None, "pass_rays shorter than the pass list reads as no rays");
}

#[test]
fn non_finite_values_are_skipped() {
    let frames = [frame(Some(&[5.0]), &[3.0], f64::INFINITY, &[]), frame(Some(&[f64::NAN]), &[f64::NAN], f64::NAN, &[]), frame(Some(&[1.0]), &[1.0], 2.0, &[])];
    let r = Report::new(&names(&[("a", "Compute")]), 4, &frames);
    assert_summary(r.passes[0].gpu_ms, 3.0, 3.0, 1.0, 5.0, 2);
    assert_summary(r.passes[0].cpu_ms, 2.0, 2.0, 1.0, 3.0, 2);
    assert_summary(r.cpu_total_ms, 2.0, 2.0, 1.0, 3.0, 2);
    assert_summary(r.frame_ms, 2.0, 2.0, 2.0, 2.0, 1);
    let all_nan = Report::new(&names(&[("a", "Compute")]), 4, &frames[1..2]);
    assert_eq!(all_nan.passes[0].gpu_ms, None);
    assert_eq!(all_nan.passes[0].cpu_ms, None);
    // The trace leaves the NaN pass out and stays valid JSON.
    let trace: Value = serde_json::from_str(&r.to_chrome_trace()).expect("valid JSON");
    let events = trace["traceEvents"].as_array().unwrap();
    assert_eq!(events.len(), 2 + 2 * 2);
    // An infinite wall time does not push later frames to infinity: the third frame starts
    // after the first frame's 5 ms of GPU time.
    let gpu: Vec<(f64, u64)> = track(events, TRACE_GPU_TID).iter().map(|e| (e.0, e.2)).collect();
    assert_eq!(gpu, vec![(0.0, 0), (5000.0, 2)]);
}

/// A minimal RFC 4180 reader: fields of each record.
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let (mut row, mut field, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    assert!(!quoted && field.is_empty() && row.is_empty(), "CSV ends with a complete record");
    rows
}

#[test]
fn csv_has_stable_columns_and_one_row_per_pass() {
    let mut frames = vec![frame(Some(&[1.0, 2.0, 3.0]), &[0.1, 0.2, 0.3], 9.0, &[None, rays(8, 0, 4), None])];
    frames.push(frames[0].clone());
    let tricky = "fog, \"thick\"";
    let r = Report::new(&names(&[("gbuffer", "SceneRaster"), ("shadows", "Trace"), (tricky, "Compute")]), 4, &frames);
    let rows = parse_csv(&r.to_csv());
    let header =
        "pass,kind,gpu_ms_mean,gpu_ms_median,gpu_ms_min,gpu_ms_max,cpu_ms_mean,cpu_ms_median,cpu_ms_min,cpu_ms_max,rays,hits,rays_per_pixel,grays_per_s";
    assert_eq!(rows[0].join(","), header);
    assert_eq!(CSV_COLUMNS.join(","), header);
    assert_eq!(rows.len(), 1 + 3);
    for row in &rows {
        assert_eq!(row.len(), 14, "{row:?}");
    }
    let col = |name: &str| CSV_COLUMNS.iter().position(|c| *c == name).unwrap();
    assert_eq!(rows[1][col("pass")], "gbuffer");
    assert_eq!(rows[1][col("rays")], "", "a pass without rays has empty ray cells");
    assert_eq!(rows[1][col("grays_per_s")], "");
    assert_eq!(rows[2][col("gpu_ms_median")].parse::<f64>().unwrap(), 2.0);
    assert_eq!(rows[2][col("rays")].parse::<f64>().unwrap(), 8.0);
    assert_eq!(rows[2][col("hits")].parse::<f64>().unwrap(), 4.0);
    assert_eq!(rows[2][col("rays_per_pixel")].parse::<f64>().unwrap(), 2.0);
    assert!(close(rows[2][col("grays_per_s")].parse::<f64>().unwrap(), 8.0 / 2e-3 / 1e9));
    assert_eq!(rows[3][col("pass")], tricky, "quoted field round-trips");
    assert_eq!(rows[3][col("kind")], "Compute");

    let no_gpu = Report::new(&names(&[("a", "Compute")]), 4, &[frame(None, &[0.5], 1.0, &[])]);
    let rows = parse_csv(&no_gpu.to_csv());
    assert_eq!(&rows[1][2..6], &["", "", "", ""], "no timestamps: empty GPU cells");
    assert_eq!(rows[1][col("cpu_ms_max")], "0.5");
}

#[test]
fn markdown_table_rows_and_decimals() {
    let r = odd_report();
    let md = r.to_markdown();
    let table: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(table.len(), 2 + r.passes.len(), "header, separator, one row per pass:\n{md}");
    for line in &table {
        assert_eq!(line.matches('|').count(), 15, "14 cells: {line}");
    }
    assert!(table[0].contains("| pass | kind | gpu_ms_mean |"));
    let cells: Vec<&str> = table[3].trim_matches('|').split('|').map(str::trim).collect();
    assert_eq!(cells[0], "shadows");
    assert_eq!(cells[3], "1.000", "GPU median, 3 decimals");
    assert_eq!(cells[10], "2000000.000");
    assert_eq!(cells[13], "2.0000", "GigaRays/s, 4 decimals");
    let raster: Vec<&str> = table[2].trim_matches('|').split('|').map(str::trim).collect();
    assert_eq!(&raster[10..], &["", "", "", ""]);
    assert!(md.contains("GPU total 4.000 ms") && md.contains("frame wall time 6.000 ms"), "{md}");

    let piped = Report::new(&names(&[("a|b", "Compute")]), 1, &[frame(None, &[1.0], 1.0, &[])]);
    let row = piped.to_markdown().lines().nth(2).unwrap().to_string();
    assert!(row.starts_with(r"| a\|b | Compute |"), "{row}");
}

/// `(ts, dur, frame)` of the complete events on one track.
fn track(events: &[Value], tid: u32) -> Vec<(f64, f64, u64)> {
    events
        .iter()
        .filter(|e| e["ph"] == "X" && e["tid"] == tid)
        .map(|e| (e["ts"].as_f64().unwrap(), e["dur"].as_f64().unwrap(), e["args"]["frame"].as_u64().unwrap()))
        .collect()
}

#[test]
fn chrome_trace_is_valid_and_laid_out_per_frame() {
    let r = odd_report();
    let trace: Value = serde_json::from_str(&r.to_chrome_trace()).expect("the trace is JSON");
    assert_eq!(trace["displayTimeUnit"], "ms");
    let events = trace["traceEvents"].as_array().unwrap();
    assert_eq!(events.len(), 2 + 3 * 2 * 2, "2 thread names + frames x passes x tracks");
    let thread_names: Vec<(u64, &str)> = events
        .iter()
        .filter(|e| e["ph"] == "M" && e["name"] == "thread_name")
        .map(|e| (e["tid"].as_u64().unwrap(), e["args"]["name"].as_str().unwrap()))
        .collect();
    assert_eq!(thread_names, vec![(TRACE_GPU_TID as u64, "GPU"), (TRACE_CPU_TID as u64, "CPU")]);
    assert!(events.iter().all(|e| e["pid"] == 1));
    assert!(events.iter().filter(|e| e["ph"] == "X").all(|e| e["tid"] == TRACE_GPU_TID || e["tid"] == TRACE_CPU_TID));

    for tid in [TRACE_GPU_TID, TRACE_CPU_TID] {
        let t = track(events, tid);
        assert_eq!(t.len(), 3 * 2);
        for w in t.windows(2) {
            let ((ts0, dur0, f0), (ts1, _, f1)) = (w[0], w[1]);
            assert!(f1 >= f0, "frames in order");
            assert!(ts1 >= ts0 + dur0 - 1e-3, "track {tid}: events overlap: {w:?}");
            if f1 == f0 {
                assert!(close(ts1, ts0 + dur0), "back to back within a frame: {w:?}");
            }
        }
        // A frame starts where the previous frame's wall time ends (5 ms, then 7 ms).
        let firsts: Vec<f64> = (0..3).map(|k| t.iter().find(|e| e.2 == k).unwrap().0).collect();
        assert!(close(firsts[0], 0.0) && close(firsts[1], 5000.0) && close(firsts[2], 12000.0), "{firsts:?}");
    }
    let gpu_durs: Vec<f64> = track(events, TRACE_GPU_TID).iter().map(|e| e.1).collect();
    assert_eq!(gpu_durs, vec![1000.0, 500.0, 3000.0, 1000.0, 2000.0, 2000.0], "microseconds from the GPU times");
    let cpu_durs: Vec<f64> = track(events, TRACE_CPU_TID).iter().map(|e| e.1).collect();
    assert!(cpu_durs.iter().zip([500.0, 200.0, 100.0, 200.0, 300.0, 800.0]).all(|(a, b)| close(*a, b)), "{cpu_durs:?}");

    let shadows: Vec<&Value> = events.iter().filter(|e| e["name"] == "shadows").collect();
    assert_eq!(shadows.len(), 6);
    assert!(shadows.iter().all(|e| e["cat"] == "Trace" && e["args"]["rays"].is_u64()));
    assert_eq!(shadows[0]["args"]["rays"], 1_000_000);
    assert_eq!(shadows[0]["args"]["hits"], 10);
    assert!(events.iter().filter(|e| e["name"] == "gbuffer").all(|e| e["args"].get("rays").is_none()));
}

#[test]
fn chrome_trace_without_timestamps_and_with_odd_names() {
    let name = "say \"hi\"\\\n\t\u{1}é";
    let frames = [frame(None, &[0.25, 0.5], 2.0, &[]), frame(None, &[0.25, 0.5], 2.0, &[])];
    let r = Report::new(&names(&[(name, "Compute"), ("b", "Fullscreen")]), 1, &frames);
    let trace: Value = serde_json::from_str(&r.to_chrome_trace()).expect("escaped names stay valid JSON");
    let events = trace["traceEvents"].as_array().unwrap();
    assert_eq!(events.len(), 2 + 2 * 2, "CPU track only");
    assert!(track(events, TRACE_GPU_TID).is_empty());
    assert_eq!(events[2]["name"], name);
    let cpu = track(events, TRACE_CPU_TID);
    assert_eq!(cpu.iter().map(|e| e.0).collect::<Vec<_>>(), vec![0.0, 250.0, 2000.0, 2250.0]);
}

#[test]
fn write_all_writes_three_files_atomically() {
    let dir = std::env::temp_dir().join(format!("raygraph-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let r = odd_report();
    let paths = r.write_all(&dir.join("nested"), "run1").expect("write_all");
    let names: Vec<String> = paths.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["run1.csv", "run1.md", "run1.trace.json"]);
    assert_eq!(std::fs::read_to_string(&paths[0]).unwrap(), r.to_csv());
    assert_eq!(std::fs::read_to_string(&paths[1]).unwrap(), r.to_markdown());
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&paths[2]).unwrap()).unwrap();
    assert!(json["traceEvents"].is_array());
    let mut listed: Vec<String> = std::fs::read_dir(dir.join("nested")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    listed.sort();
    assert_eq!(listed, names, "exactly the three files, no .partial left");
    // Writing again replaces them in place.
    r.write_all(&dir.join("nested"), "run1").unwrap();
    assert_eq!(std::fs::read_dir(dir.join("nested")).unwrap().count(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_time_outside_the_passes_is_reported_by_part() {
    // Three frames whose parts differ: the report's line carries each part's median.
    let phases = [(0.2, 0.03, 0.5, 4.0, 0.1, 0.35), (0.4, 0.01, 0.7, 6.0, 0.3, 0.45), (0.3, 0.02, 0.6, 5.0, 0.2, 0.4)];
    let frames: Vec<FrameTimings> = phases
        .iter()
        .map(|&(scene_ms, uniforms_ms, submit_ms, wait_ms, readback_ms, finish_ms)| FrameTimings {
            phases: FramePhases { scene_ms, uniforms_ms, submit_ms, wait_ms, readback_ms, finish_ms },
            ..frame(Some(&[1.0]), &[0.1], 7.0, &[None])
        })
        .collect();
    let report = Report::new(&names(&[("a", "compute")]), 100, &frames);
    let md = report.to_markdown();
    assert!(
        md.contains("outside the passes (medians): scene update 0.300, uniforms 0.020, submit 0.600, wait 5.000, read-back 0.200 ms; of submit, finishing the command encoder 0.400 ms"),
        "{md}"
    );
    let table = raygraph::runtime::profiler::pass_table(&names(&[("a", "compute")]), &frames, 100);
    assert!(table.contains("outside the passes (medians): scene update 0.300"), "{table}");
}

#[test]
fn a_rendered_frame_accounts_for_its_time_outside_the_passes() {
    let gpu = common::gpu();
    let scene = raygraph::scene::builtin::default_scene();
    let exec_frames: Vec<FrameTimings> = {
        let mut exec = common::modes::render_graph(&gpu, "graph/hybrid.ron", raygraph::backend::Backend::Compute, &scene, (32, 24));
        (0..3).map(|_| exec.render(&gpu, scene.camera(), &scene).unwrap()).collect()
    };
    for f in &exec_frames {
        let parts = f.phases.parts();
        assert!(parts.iter().all(|(_, ms)| ms.is_finite() && *ms >= 0.0), "{parts:?}");
        let outside: f64 = parts.iter().map(|(_, ms)| ms).sum();
        let recording: f64 = f.cpu_ms.iter().sum();
        // The parts and the passes' recording are disjoint stretches of the frame's wall time.
        assert!(outside + recording <= f.frame_ms + 1e-6, "{parts:?} + recording {recording} > frame {}", f.frame_ms);
        assert!(f.phases.wait_ms > 0.0, "the wait for the GPU is measured");
        assert!(f.phases.finish_ms > 0.0 && f.phases.finish_ms <= f.phases.submit_ms, "finishing the encoder is part of submit: {:?}", f.phases);
    }
}
