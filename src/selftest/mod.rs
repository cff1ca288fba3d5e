//! `raygraph selftest`: the correctness suites run on whatever adapter is present, one line per
//! suite and back-end: `passed`, `FAILED: <reason>` or `not applicable: <why>` (a back-end the
//! adapter cannot run, such as `ray-query` without ray queries). Nothing is reported as passed
//! that did not run. The integration tests (`tests/hard_cases.rs`) call the same cases and
//! require every one of them on lavapipe.
//!
//! Suites: `hard-cases` (`hard_cases`: watertightness, grazing and degenerate geometry,
//! offsets, culling; each case on every back-end and layout) and `agreement` (`agreement`:
//! every back-end against the f64 reference caster on the built-in scenes, the closed `organic`
//! mesh from inside, invalid rays; on the two-level layout of each back-end) and
//! `reference-channels` (`channels`: every ray-traced channel of the full ray-tracing graph
//! against the f64 reference renderer, pixel by pixel, on every back-end and layout).

#[macro_use]
mod macros {
    /// Returns `Err(format!(...))` from the enclosing function unless the condition holds.
    macro_rules! ensure {
        ($cond:expr, $($fmt:tt)+) => {{
            let holds: bool = $cond;
            if !holds {
                return Err(format!($($fmt)+));
            }
        }};
    }

    /// Returns an error naming both values unless they are equal.
    macro_rules! ensure_eq {
        ($a:expr, $b:expr, $($fmt:tt)+) => {{
            let (a, b) = (&$a, &$b);
            if a != b {
                return Err(format!("{}: {:?} instead of {:?}", format!($($fmt)+), a, b));
            }
        }};
    }
}

pub mod agreement;
pub mod channels;
pub mod hard_cases;
mod target;

pub use target::{Case, Target, Variant, VARIANTS};

use crate::backend::Backend;
use crate::runtime::Gpu;
use std::path::PathBuf;
use std::time::Instant;

/// The result of one suite on one variant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// Every check ran and held.
    Passed,
    /// A check failed or could not run (the reasons, `; `-separated).
    Failed(String),
    /// The suite cannot run on this adapter (why).
    NotApplicable(String),
}

/// One line of the report.
#[derive(Debug, Clone)]
pub struct SuiteResult {
    /// The suite's name.
    pub suite: &'static str,
    /// The back-end and layout.
    pub variant: Variant,
    /// What happened.
    pub outcome: Outcome,
    /// What the cases measured, for `--verbose` and the log.
    pub notes: Vec<String>,
    /// Cases run.
    pub checks: usize,
    /// Seconds taken.
    pub seconds: f64,
}

impl SuiteResult {
    /// The report line: `<suite> on <variant>: passed (...)`, `FAILED: <reason>` or
    /// `not applicable: <why>`.
    pub fn line(&self) -> String {
        let outcome = match &self.outcome {
            Outcome::Passed => format!("passed ({} cases, {:.1} s)", self.checks, self.seconds),
            Outcome::Failed(reason) => format!("FAILED: {reason}"),
            Outcome::NotApplicable(why) => format!("not applicable: {why}"),
        };
        format!("{} on {}: {outcome}", self.suite, self.variant.name)
    }
}

/// What to run.
#[derive(Debug, Clone)]
pub struct SelftestConfig {
    /// The `shaders/` folder (missing files come from the built-in copies).
    pub shaders: PathBuf,
    /// Only these back-ends (empty: all).
    pub backends: Vec<Backend>,
    /// Only these suites, by name (empty: all of `SUITES`).
    pub suites: Vec<String>,
}

/// The suites' names, in the order they run.
pub const SUITES: [&str; 3] = ["hard-cases", "agreement", "reference-channels"];

/// The variants `suite` runs on: every one for the hard cases, the two-level layout of each
/// back-end for the agreement.
pub fn suite_variants(suite: &str) -> impl Iterator<Item = Variant> + '_ {
    VARIANTS.into_iter().filter(move |v| suite != "agreement" || !v.merge)
}

/// Runs every suite on every variant `cfg` selects; `on_result` sees each line as it is made.
pub fn run(gpu: &Gpu, cfg: &SelftestConfig, mut on_result: impl FnMut(&SuiteResult)) -> Vec<SuiteResult> {
    let selected = |v: &Variant| cfg.backends.is_empty() || cfg.backends.contains(&v.backend);
    let wanted = |suite: &str| cfg.suites.is_empty() || cfg.suites.iter().any(|s| s == suite);
    let mut results = Vec::new();
    for variant in suite_variants(SUITES[0]).filter(selected).filter(|_| wanted(SUITES[0])) {
        let result = hard_cases_suite(&Target { gpu, variant, shaders: &cfg.shaders });
        on_result(&result);
        results.push(result);
    }
    let targets: Vec<Target> =
        suite_variants(SUITES[1]).filter(selected).filter(|_| wanted(SUITES[1])).map(|variant| Target { gpu, variant, shaders: &cfg.shaders }).collect();
    for result in agreement_suite(&targets) {
        on_result(&result);
        results.push(result);
    }
    let targets: Vec<Target> =
        suite_variants(SUITES[2]).filter(selected).filter(|_| wanted(SUITES[2])).map(|variant| Target { gpu, variant, shaders: &cfg.shaders }).collect();
    for result in channels_suite(&targets) {
        on_result(&result);
        results.push(result);
    }
    results
}

/// The reference-channel suite on each target: the project and the reference's primary
/// answers are made once per scene and compared with every target's frame.
pub(crate) fn channels_suite(targets: &[Target]) -> Vec<SuiteResult> {
    let mut results: Vec<(SuiteResult, Vec<String>)> = targets.iter().map(|t| (start(SUITES[2], t), Vec::new())).collect();
    let runnable = |r: &SuiteResult| r.outcome == Outcome::Passed;
    let runnable_count = results.iter().filter(|(r, _)| runnable(r)).count();
    if runnable_count > 0 {
        let prepared = channels::ChannelProject::new().and_then(|p| Ok((channels::scenes()?, p)));
        match prepared {
            Ok((scenes, project)) => {
                for scene in scenes {
                    let begin = Instant::now();
                    let scene = channels::ChannelScene::new(scene, &project);
                    let shared = begin.elapsed().as_secs_f64() / runnable_count as f64;
                    for ((result, failures), target) in results.iter_mut().zip(targets).filter(|((r, _), _)| runnable(r)) {
                        let begin = Instant::now();
                        result.checks += 1;
                        result.notes.push(scene.describe());
                        if let Err(e) = target.run_case_with(|t, notes| scene.compare(&project, t, notes), &mut result.notes) {
                            failures.push(e);
                        }
                        result.seconds += shared + begin.elapsed().as_secs_f64();
                    }
                }
            }
            Err(e) => results.iter_mut().for_each(|(_, failures)| failures.push(format!("preparing the suite: {e}"))),
        }
    }
    results
        .into_iter()
        .map(|(mut result, failures)| {
            if runnable(&result) {
                finish(&mut result, failures);
            }
            result
        })
        .collect()
}

/// A line of `suite` on `target`, passed until something fails, not applicable where the
/// adapter lacks the back-end.
fn start(suite: &'static str, target: &Target) -> SuiteResult {
    let outcome = match target.not_applicable() {
        Some(why) => Outcome::NotApplicable(why),
        None => Outcome::Passed,
    };
    SuiteResult { suite, variant: target.variant, outcome, notes: Vec::new(), checks: 0, seconds: 0.0 }
}

/// The hard cases on one target.
pub(crate) fn hard_cases_suite(target: &Target) -> SuiteResult {
    let begin = Instant::now();
    let mut result = start(SUITES[0], target);
    if result.outcome != Outcome::Passed {
        return result;
    }
    let mut failures = Vec::new();
    for (name, case) in hard_cases::CASES {
        if let Err(e) = target.run_case(case, &mut result.notes) {
            failures.push(format!("{name}: {e}"));
        }
        result.checks += 1;
    }
    finish(&mut result, failures);
    result.seconds = begin.elapsed().as_secs_f64();
    result
}

/// Records the failures (if any); a suite in which no case ran fails, it cannot pass.
fn finish(result: &mut SuiteResult, mut failures: Vec<String>) {
    if result.checks == 0 {
        failures.push("no case ran".to_string());
    }
    if !failures.is_empty() {
        let shown: Vec<&str> = failures.iter().take(5).map(String::as_str).collect();
        let more = if failures.len() > 5 { format!("; and {} more", failures.len() - 5) } else { String::new() };
        result.outcome = Outcome::Failed(format!("{}{more}", shown.join("; ")));
        result.notes.extend(failures.iter().map(|f| format!("FAIL {f}")));
    }
}

/// The agreement suite on each target: the reference's answers are made once per scene and
/// compared with every target's; then the closed-mesh and invalid-ray cases on each.
pub(crate) fn agreement_suite(targets: &[Target]) -> Vec<SuiteResult> {
    let mut results: Vec<(SuiteResult, Vec<String>)> = targets.iter().map(|t| (start(SUITES[1], t), Vec::new())).collect();
    let runnable = |r: &SuiteResult| r.outcome == Outcome::Passed;
    let runnable_count = results.iter().filter(|(r, _)| runnable(r)).count();
    if runnable_count > 0 {
        for (name, per_group) in agreement::SCENES {
            let begin = Instant::now();
            let reference = agreement::ReferenceScene::new(name, per_group);
            let shared = begin.elapsed().as_secs_f64() / runnable_count as f64;
            for ((result, failures), target) in results.iter_mut().zip(targets).filter(|((r, _), _)| runnable(r)) {
                let begin = Instant::now();
                result.checks += 1;
                let compared = match &reference {
                    Ok(reference) => target.run_case_with(|t, notes| reference.compare(t, failures, notes), &mut result.notes),
                    Err(e) => Err(e.clone()),
                };
                if let Err(e) = compared {
                    failures.push(format!("reference comparison on {name}: {e}"));
                }
                result.seconds += shared + begin.elapsed().as_secs_f64();
            }
        }
    }
    let cases: [(&str, Case); 2] = [
        ("closed organic mesh from inside", agreement::no_ray_escapes_the_closed_organic_mesh_from_inside),
        ("invalid rays", agreement::invalid_rays_are_counted_and_miss_without_a_crash),
    ];
    let mut out = Vec::new();
    for ((mut result, mut failures), target) in results.into_iter().zip(targets) {
        if runnable(&result) {
            let begin = Instant::now();
            for (name, case) in cases {
                result.checks += 1;
                if let Err(e) = target.run_case(case, &mut result.notes) {
                    failures.push(format!("{name}: {e}"));
                }
            }
            finish(&mut result, failures);
            result.seconds += begin.elapsed().as_secs_f64();
        }
        out.push(result);
    }
    out
}

/// The log of a run: the adapter, the revision, the date, every line, and the verdict.
pub fn log_text(gpu: &Gpu, results: &[SuiteResult], notes: bool) -> String {
    let mut lines =
        vec![format!("adapter: {}", gpu.describe()), format!("revision: {}", env!("RAYGRAPH_REVISION")), format!("date: {}", crate::util::utc_timestamp())];
    for r in results {
        lines.push(r.line());
        if notes {
            lines.extend(r.notes.iter().map(|n| format!("    {n}")));
        }
    }
    lines.push(verdict(results));
    lines.join("\n") + "\n"
}

/// `ok: ...` or `selftest failed: ...`, counting passed, failed and not applicable lines.
pub fn verdict(results: &[SuiteResult]) -> String {
    let count = |f: fn(&Outcome) -> bool| results.iter().filter(|r| f(&r.outcome)).count();
    let passed = count(|o| matches!(o, Outcome::Passed));
    let failed = count(|o| matches!(o, Outcome::Failed(_)));
    let not_applicable = count(|o| matches!(o, Outcome::NotApplicable(_)));
    let counts = format!("{passed} passed, {failed} failed, {not_applicable} not applicable");
    if failed > 0 || passed == 0 {
        format!("selftest failed: {counts}")
    } else {
        format!("ok: {counts}")
    }
}
