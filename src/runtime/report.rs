//! The per-pass profiling report: statistics over timed frames ([`Report`], [`PassStats`],
//! [`Summary`]) and their exports — CSV, a markdown table and a Chrome trace (the Trace Event
//! Format that chrome://tracing and Perfetto open) — plus [`Report::write_all`], which writes
//! all three atomically. The terminal table stays [`super::profiler::pass_table`].
//!
//! Statistics skip values that are not finite (NaN, ±inf): a [`Summary`] is over the finite
//! values only, its `n` says how many there were, and it is `None` when there are none. A
//! frame whose GPU or CPU times include a non-finite value has no total for that side.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::profiler::{median, FrameTimings};

/// Mean, median, minimum and maximum of the finite values of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// The arithmetic mean.
    pub mean: f64,
    /// The median.
    pub median: f64,
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// Values used (the finite ones).
    pub n: usize,
}

impl Summary {
    /// `None` when no value is finite.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Option<Summary> {
        let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        let n = v.len();
        let mean = v.iter().sum::<f64>() / n as f64;
        let median = median(&mut v); // sorts
        Some(Summary { mean, median, min: v[0], max: v[n - 1], n })
    }
}

/// One pass over all frames.
#[derive(Debug, Clone, PartialEq)]
pub struct PassStats {
    /// The pass's name, `layer/pass`.
    pub name: String,
    /// The pass's kind ([`crate::graph::desc::PassKind::name`]).
    pub kind: &'static str,
    /// GPU milliseconds, over the frames that have a timestamp for this pass (`None` without
    /// timestamp queries).
    pub gpu_ms: Option<Summary>,
    /// CPU milliseconds recording the pass.
    pub cpu_ms: Option<Summary>,
    /// Median rays traced per frame (closest + any-hit); `None` for passes that trace nothing.
    pub rays: Option<f64>,
    /// Median hits per frame.
    pub hits: Option<f64>,
    /// `rays` over the frame's pixels.
    pub rays_per_pixel: Option<f64>,
    /// Median rays / median GPU seconds / 1e9 (`None` without GPU times or at 0 ms).
    pub grays_per_s: Option<f64>,
}

/// Per-pass statistics and per-frame totals of a run, with the frames it came from (the
/// Chrome trace shows each frame).
#[derive(Debug, Clone)]
pub struct Report {
    /// One entry per pass, in plan order.
    pub passes: Vec<PassStats>,
    /// Pixels per frame.
    pub pixels: u64,
    /// Per-frame sum of the passes' GPU times (frames with a GPU time for every pass).
    pub gpu_total_ms: Option<Summary>,
    /// Per-frame sum of the passes' CPU recording times.
    pub cpu_total_ms: Option<Summary>,
    /// Frame wall time (`FrameTimings::frame_ms`).
    pub frame_ms: Option<Summary>,
    /// The frames the statistics are of.
    pub frames: Vec<FrameTimings>,
}

/// CSV column names, in order.
pub const CSV_COLUMNS: [&str; 14] = [
    "pass",
    "kind",
    "gpu_ms_mean",
    "gpu_ms_median",
    "gpu_ms_min",
    "gpu_ms_max",
    "cpu_ms_mean",
    "cpu_ms_median",
    "cpu_ms_min",
    "cpu_ms_max",
    "rays",
    "hits",
    "rays_per_pixel",
    "grays_per_s",
];

/// Track ids of the Chrome trace (process id 1).
pub const TRACE_GPU_TID: u32 = 1;
/// Track id of the CPU recording times in the Chrome trace.
pub const TRACE_CPU_TID: u32 = 2;

impl Report {
    /// `names` as [`super::profiler::pass_table`] takes them (schedule order, matching the
    /// per-pass vectors of `frames`); `frames` are the timed frames, after warm-up.
    pub fn new(names: &[(String, &'static str)], pixels: u64, frames: &[FrameTimings]) -> Report {
        let passes = names
            .iter()
            .enumerate()
            .map(|(i, (name, kind))| {
                let gpu_ms = Summary::of(frames.iter().filter_map(|f| f.gpu_ms.as_ref()?.get(i).copied()));
                let cpu_ms = Summary::of(frames.iter().filter_map(|f| f.cpu_ms.get(i).copied()));
                let traced: Vec<_> = frames.iter().filter_map(|f| f.pass_rays.get(i).copied().flatten()).collect();
                let rays = Summary::of(traced.iter().map(|r| r.traced() as f64)).map(|s| s.median);
                let hits = Summary::of(traced.iter().map(|r| r.hits as f64)).map(|s| s.median);
                let gpu_s = gpu_ms.map(|s| s.median * 1e-3).filter(|s| *s > 0.0);
                PassStats {
                    name: name.clone(),
                    kind,
                    gpu_ms,
                    cpu_ms,
                    rays,
                    hits,
                    rays_per_pixel: rays.map(|r| r / pixels.max(1) as f64),
                    grays_per_s: rays.zip(gpu_s).map(|(r, s)| r / s / 1e9),
                }
            })
            .collect();
        let n = names.len();
        let total = |v: &[f64]| if v.len() >= n { v[..n].iter().sum() } else { f64::NAN };
        Report {
            passes,
            pixels,
            gpu_total_ms: Summary::of(frames.iter().filter_map(|f| f.gpu_ms.as_deref().map(total))),
            cpu_total_ms: Summary::of(frames.iter().map(|f| total(&f.cpu_ms))),
            frame_ms: Summary::of(frames.iter().map(|f| f.frame_ms)),
            frames: frames.to_vec(),
        }
    }

    /// One row per pass under a header of [`CSV_COLUMNS`]; numbers at full precision, an
    /// empty cell for a missing value.
    pub fn to_csv(&self) -> String {
        let mut s = CSV_COLUMNS.join(",") + "\n";
        for p in &self.passes {
            let mut cells = vec![csv_field(&p.name), csv_field(p.kind)];
            cells.extend(p.numbers().iter().map(|v| v.map(|x| x.to_string()).unwrap_or_default()));
            s += &cells.join(",");
            s.push('\n');
        }
        s
    }

    /// A markdown table with the CSV's columns (3 decimals, GigaRays/s 4), then a line of
    /// per-frame totals (medians).
    pub fn to_markdown(&self) -> String {
        let mut s = format!("| {} |\n|{}\n", CSV_COLUMNS.join(" | "), " --- |".repeat(CSV_COLUMNS.len()));
        for p in &self.passes {
            let nums = p.numbers();
            let cells = nums.iter().enumerate().map(|(c, v)| match v {
                Some(x) if c + 1 == nums.len() => format!("{x:.4}"),
                Some(x) => format!("{x:.3}"),
                None => String::new(),
            });
            let row: Vec<String> = [md_cell(&p.name), md_cell(p.kind)].into_iter().chain(cells).collect();
            let _ = writeln!(s, "| {} |", row.join(" | "));
        }
        let med = |m: Option<Summary>| m.map(|m| format!("{:.3} ms", m.median)).unwrap_or_else(|| "n/a".into());
        let _ = writeln!(
            s,
            "\n{} frames, {} pixels; medians per frame: GPU total {}, CPU total {}, frame wall time {}",
            self.frames.len(),
            self.pixels,
            med(self.gpu_total_ms),
            med(self.cpu_total_ms),
            med(self.frame_ms)
        );
        let _ = writeln!(s, "outside the passes (medians): {}", crate::runtime::profiler::FramePhases::describe_frames(&self.frames));
        s
    }

    /// A Chrome trace: thread-name metadata for the "GPU" and "CPU" tracks, then one complete
    /// event (`"ph": "X"`) per pass per frame and track. The times are durations, not measured
    /// start times: within a frame the passes are laid out back to back on each track, and
    /// each frame starts where the previous one (its finite wall time, or the longer of its
    /// track sums) ended. Passes with a non-finite time get no event; `args` has the frame
    /// index and the pass's rays and hits of that frame where counted.
    pub fn to_chrome_trace(&self) -> String {
        let mut events = Vec::new();
        for (tid, name) in [(TRACE_GPU_TID, "GPU"), (TRACE_CPU_TID, "CPU")] {
            events.push(format!(r#"{{"name": "thread_name", "ph": "M", "pid": 1, "tid": {tid}, "args": {{"name": {}}}}}"#, json_string(name)));
        }
        let mut start_us = 0.0;
        for (k, f) in self.frames.iter().enumerate() {
            let wall_us = if f.frame_ms.is_finite() { f.frame_ms.max(0.0) * 1e3 } else { 0.0 };
            let mut end_us = start_us + wall_us;
            for (tid, times) in [(TRACE_GPU_TID, f.gpu_ms.as_deref()), (TRACE_CPU_TID, Some(f.cpu_ms.as_slice()))] {
                let mut t = start_us;
                for (i, (p, ms)) in self.passes.iter().zip(times.unwrap_or_default()).enumerate() {
                    if !ms.is_finite() {
                        continue;
                    }
                    let dur = ms.max(0.0) * 1e3;
                    let mut args = format!(r#""frame": {k}"#);
                    if let Some(r) = f.pass_rays.get(i).copied().flatten() {
                        let _ = write!(args, r#", "rays": {}, "hits": {}"#, r.traced(), r.hits);
                    }
                    events.push(format!(
                        r#"{{"name": {}, "cat": {}, "ph": "X", "ts": {t:.3}, "dur": {dur:.3}, "pid": 1, "tid": {tid}, "args": {{{args}}}}}"#,
                        json_string(&p.name),
                        json_string(p.kind)
                    ));
                    t += dur;
                }
                end_us = end_us.max(t);
            }
            start_us = end_us;
        }
        format!("{{\"traceEvents\": [\n{}\n], \"displayTimeUnit\": \"ms\"}}\n", events.join(",\n"))
    }

    /// Writes `stem.csv`, `stem.md` and `stem.trace.json` into `dir` (created if missing),
    /// each atomically; returns their paths.
    pub fn write_all(&self, dir: &Path, stem: &str) -> std::io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let files = [("csv", self.to_csv()), ("md", self.to_markdown()), ("trace.json", self.to_chrome_trace())];
        let mut paths = Vec::new();
        for (ext, text) in files {
            let path = dir.join(format!("{stem}.{ext}"));
            crate::util::write_atomic(&path, text.as_bytes())?;
            paths.push(path);
        }
        Ok(paths)
    }
}

impl PassStats {
    /// The numeric columns, in [`CSV_COLUMNS`] order (after pass and kind).
    fn numbers(&self) -> [Option<f64>; 12] {
        let g = self.gpu_ms;
        let c = self.cpu_ms;
        [
            g.map(|s| s.mean),
            g.map(|s| s.median),
            g.map(|s| s.min),
            g.map(|s| s.max),
            c.map(|s| s.mean),
            c.map(|s| s.median),
            c.map(|s| s.min),
            c.map(|s| s.max),
            self.rays,
            self.hits,
            self.rays_per_pixel,
            self.grays_per_s,
        ]
    }
}

/// RFC 4180 quoting where needed.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace(['\n', '\r'], " ")
}

/// A JSON string literal.
fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for ch in s.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
