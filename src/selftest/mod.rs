//! `raygraph selftest`: the correctness suites run on whatever adapter is present, one line per
//! suite and back-end: `passed`, `FAILED: <reason>` or `not applicable: <why>` (a back-end the
//! adapter cannot run, such as `ray-query` without ray queries). Nothing is reported as passed
//! that did not run. The integration tests (`tests/hard_cases.rs`) call the same cases and
//! require every one of them on lavapipe.
//!
//! Suites: `hard-cases` (`hard_cases`: watertightness, grazing and degenerate geometry,
//! offsets, culling; each case on every back-end and layout).

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
}

/// The suites' names, in the order they run.
pub const SUITES: [&str; 1] = ["hard-cases"];

/// Runs every suite on every variant `cfg` selects; `on_result` sees each line as it is made.
pub fn run(gpu: &Gpu, cfg: &SelftestConfig, mut on_result: impl FnMut(&SuiteResult)) -> Vec<SuiteResult> {
    let mut results = Vec::new();
    for variant in VARIANTS.iter().filter(|v| cfg.backends.is_empty() || cfg.backends.contains(&v.backend)) {
        let target = Target { gpu, variant: *variant, shaders: &cfg.shaders };
        let result = hard_cases_suite(&target);
        on_result(&result);
        results.push(result);
    }
    results
}

/// The hard cases on one target.
pub fn hard_cases_suite(target: &Target) -> SuiteResult {
    let start = Instant::now();
    let mut result = SuiteResult { suite: SUITES[0], variant: target.variant, outcome: Outcome::Passed, notes: Vec::new(), checks: 0, seconds: 0.0 };
    if let Some(why) = target.not_applicable() {
        result.outcome = Outcome::NotApplicable(why);
        return result;
    }
    let mut failures = Vec::new();
    for (name, case) in hard_cases::CASES {
        if let Err(e) = target.run_case(case, &mut result.notes) {
            failures.push(format!("{name}: {e}"));
        }
        result.checks += 1;
    }
    if !failures.is_empty() {
        result.outcome = Outcome::Failed(failures.join("; "));
    }
    result.seconds = start.elapsed().as_secs_f64();
    result
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
