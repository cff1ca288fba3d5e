//! The traversal back-ends and their selection at start-up, as in the paper: `ray-query`
//! (wgpu's EXPERIMENTAL_RAY_QUERY: the driver's BLAS/TLAS, hardware traversal where there is
//! any) where the adapter supports it, else `compute` (the project's own BVH traversed in a
//! WGSL compute shader, which runs everywhere). The third, `rt-pipeline` (the ray-tracing
//! pipeline with a shader binding table through wgpu-hal, [`crate::accel::rt_pipeline`]), runs
//! where the adapter has EXPERIMENTAL_RAY_TRACING_PIPELINES and is chosen only with
//! `--backend rt-pipeline`: see [`select`] for the measurements behind the order.

use std::fmt;
use std::str::FromStr;

/// A traversal back-end: how trace passes find their rays' hits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Inline ray queries against driver acceleration structures (`EXPERIMENTAL_RAY_QUERY`).
    RayQuery,
    /// raygraph's own BVH walked in a compute shader: runs on every adapter.
    Compute,
    /// Ray-tracing pipelines with hit shaders (`EXPERIMENTAL_RAY_TRACING_PIPELINES`, Vulkan).
    RtPipeline,
}

impl Backend {
    /// Every back-end.
    pub const ALL: [Backend; 3] = [Backend::RayQuery, Backend::Compute, Backend::RtPipeline];

    /// The name the command line and graph files use (`ray-query`, `compute`, `rt-pipeline`).
    pub(crate) fn name(self) -> &'static str {
        match self {
            Backend::RayQuery => "ray-query",
            Backend::Compute => "compute",
            Backend::RtPipeline => "rt-pipeline",
        }
    }

    /// The WGSL module that implements `trace/trace.wgsl` for this back-end.
    pub(crate) fn trace_module(self) -> &'static str {
        match self {
            Backend::RayQuery => "trace/ray_query.wgsl",
            Backend::Compute => "trace/compute.wgsl",
            Backend::RtPipeline => "trace/rt_pipeline.wgsl",
        }
    }

    /// Device features the back-end needs.
    pub fn features(self) -> wgpu::Features {
        match self {
            Backend::RayQuery => wgpu::Features::EXPERIMENTAL_RAY_QUERY,
            Backend::Compute => wgpu::Features::empty(),
            // The closest-hit shader reads the primitive index (SPIR-V PrimitiveId, which naga
            // declares under the Geometry capability that PRIMITIVE_INDEX enables).
            Backend::RtPipeline => wgpu::Features::EXPERIMENTAL_RAY_TRACING_PIPELINES.union(wgpu::Features::PRIMITIVE_INDEX),
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "ray-query" | "rayquery" | "ray_query" => Ok(Backend::RayQuery),
            "compute" => Ok(Backend::Compute),
            "rt-pipeline" | "rt_pipeline" | "rtpipeline" => Ok(Backend::RtPipeline),
            other => Err(format!("unknown back-end `{other}`; the back-ends are: ray-query, compute, rt-pipeline")),
        }
    }
}

/// The back-end in use and why it was chosen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Selection {
    /// The back-end.
    pub backend: Backend,
    /// Why it was chosen, for reports.
    pub reason: String,
}

/// Picks the back-end for an adapter with `features`: the requested one if the adapter can run
/// it (an error naming what is missing if not), else `ray-query` where supported, else `compute`.
///
/// `rt-pipeline` is never picked unasked. Measured on the H100 (BENCHMARKS.md, "Three
/// back-ends"; ray-tracing pipelines, no ray queries, no ray-tracing cores): the driver's
/// pipeline traces the paper's Table 3 workloads 1.6x (box) to 5.4x (all-miss rays) slower than
/// `compute`, on every test. Where ray queries exist they reach the same driver traversal
/// without a pipeline, shader binding table or separate command buffers, so they come first.
pub fn select(features: wgpu::Features, requested: Option<Backend>) -> Result<Selection, String> {
    let supports = |b: Backend| features.contains(b.features());
    match requested {
        Some(b) if supports(b) => Ok(Selection { backend: b, reason: "requested with --backend".into() }),
        Some(b) => Err(format!("back-end `{b}` needs {:?}, which this adapter does not have; use --backend compute (runs everywhere)", b.features())),
        None if supports(Backend::RayQuery) => {
            Ok(Selection { backend: Backend::RayQuery, reason: "the adapter supports ray queries (EXPERIMENTAL_RAY_QUERY)".into() })
        }
        None => Ok(Selection { backend: Backend::Compute, reason: "the adapter has no ray queries; using the compute-shader BVH".into() }),
    }
}
