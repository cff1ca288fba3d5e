//! What a check runs on: a back-end with one of its layouts (`Variant`), on a device, with its
//! shaders (`Target`), and the signature of a case (`Case`).

use crate::accel::cache::AccelSettings;
use crate::backend::Backend;
use crate::runtime::batch::BatchTracer;
use crate::runtime::Gpu;
use crate::scene::Scene;
use std::path::Path;

/// A case on one back-end and layout; notes are what it measured, for the log.
pub type Case = fn(&Target, &mut Vec<String>) -> Result<(), String>;

/// A back-end with one of its acceleration-structure layouts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Variant {
    /// The name in the report: the back-end, `-merged` for the merged layout.
    pub name: &'static str,
    /// The traversal back-end.
    pub backend: Backend,
    /// The merged layout (one BVH over all instances in world space) instead of two levels.
    pub merge: bool,
}

/// Every back-end and layout the suites run on.
pub const VARIANTS: [Variant; 5] = [
    Variant { name: "compute", backend: Backend::Compute, merge: false },
    Variant { name: "compute-merged", backend: Backend::Compute, merge: true },
    Variant { name: "ray-query", backend: Backend::RayQuery, merge: false },
    Variant { name: "rt-pipeline", backend: Backend::RtPipeline, merge: false },
    Variant { name: "rt-pipeline-merged", backend: Backend::RtPipeline, merge: true },
];

/// What a case runs on: the device, the variant, and the shaders folder its tracers read
/// (a file missing there is taken from the built-in copy).
pub struct Target<'a> {
    /// The device.
    pub gpu: &'a Gpu,
    /// The back-end and layout.
    pub variant: Variant,
    /// The `shaders/` folder.
    pub shaders: &'a Path,
}

impl Target<'_> {
    /// A batch tracer of `scene` on this target's back-end and layout.
    pub fn tracer(&self, scene: &Scene) -> Result<BatchTracer, String> {
        let settings = AccelSettings { dedup: true, merge: self.variant.merge };
        BatchTracer::with_settings(self.gpu, self.variant.backend, scene, self.shaders, settings)
            .map_err(|e| format!("{}: making the tracer: {e}", self.variant.name))
    }

    /// Why this target cannot run on its device (`None`: it can).
    pub fn not_applicable(&self) -> Option<String> {
        if self.gpu.backends().contains(&self.variant.backend) {
            return None;
        }
        Some(match self.variant.backend {
            Backend::RayQuery => "the adapter has no ray queries (VK_KHR_ray_query)".to_string(),
            Backend::RtPipeline => "the adapter has no ray-tracing pipelines (VK_KHR_ray_tracing_pipeline)".to_string(),
            Backend::Compute => "the adapter cannot run compute shaders".to_string(),
        })
    }

    /// Runs one case, a panic in it caught and reported as a failure.
    pub fn run_case(&self, case: Case, notes: &mut Vec<String>) -> Result<(), String> {
        self.run_case_with(case, notes)
    }

    /// Runs a check given as a closure, a panic in it caught and reported as a failure.
    pub fn run_case_with(&self, case: impl FnOnce(&Self, &mut Vec<String>) -> Result<(), String>, notes: &mut Vec<String>) -> Result<(), String> {
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| case(self, notes))) {
            Ok(result) => result,
            Err(panic) => {
                let message = panic.downcast_ref::<String>().cloned().or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()));
                Err(format!("panicked: {}", message.unwrap_or_else(|| "(no message)".into())))
            }
        }
    }
}
