//! `raygraph bench`: the experiments of `raygraph::bench`, one module per bench. Each writes its
//! results (CSV, markdown, plots) into its `--out` folder, rewritten as rows finish.

pub(crate) mod anim;
pub(crate) mod build;
pub(crate) mod depth;
pub(crate) mod error;
pub(crate) mod lights;
pub(crate) mod modes;
pub(crate) mod output;
pub(crate) mod rays;
pub(crate) mod roofline;
pub(crate) mod scale;
pub(crate) mod track;
pub(crate) mod truth;

use anyhow::Result;

#[derive(clap::Subcommand)]
pub(crate) enum BenchCommand {
    /// The paper's Table 3: GigaRays/s of the scene workload (primary + 1 shadow + N AO rays per
    /// pixel) on each scene, and the Miss and Stress tests, for every back-end.
    Rays(rays::RaysArgs),
    /// Speed, build time and GPU memory against unique triangles (10^4 to 3x10^7): each step a
    /// scene copied NxNxN without de-duplication, on every back-end (BENCHMARKS.md, "Scale").
    Scale(scale::ScaleArgs),
    /// The paper's Figure 9: BLAS and TLAS build times against triangles, each scene copied
    /// N×N×N (one BLAS per copy), per builder, with SAH cost and the trace time of the result.
    Build(build::BuildArgs),
    /// The paper's Figures 10 and 11: a camera track through raster, hybrid and full RT; FPS
    /// and GigaRays/s per frame.
    Track(track::TrackArgs),
    /// Animated scenes played through the paper's scene workload under each policy of the
    /// acceleration-structure cache (refit until the SAH cost grows past its threshold, always
    /// refit, always rebuild): per frame the update's GPU and CPU milliseconds, what it did, the
    /// SAH growth, and the trace passes' GigaRays/s.
    Anim(anim::AnimArgs),
    /// Ambient occlusion against its closed form (floor under a parallel ceiling): error
    /// (RMSE, relMSE, bias, variance over seeds) against rays per pixel and GPU time, for white
    /// noise and the R2 sequence, with the fitted convergence slopes.
    /// Also AO, soft shadows, GI and glossy reflections of `graph/hybrid_denoised.ron`, noisy
    /// and filtered, against converged references (relMSE, ꟻLIP) and GPU time, with an
    /// equal-time table and a camera track for flicker and ghosting (`filters.md`).
    Error(error::ErrorArgs),
    /// Bytes per ray of Table 3's tests on the compute back-end, counted by its CPU mirror, and
    /// the load-bound ceiling they give; with a `bench rays` CSV, achieved/ceiling (no GPU).
    Roofline(roofline::RooflineArgs),
    /// The three modes on the same scenes, camera and back-end, with their effects on and off:
    /// the images, and ꟻLIP mean and RMSE between every pair (ACCURACY.md, "Real assets").
    Modes(modes::ModesArgs),
    /// Reflection bounces 1..8 against rays/s.
    Depth(depth::DepthArgs),
    /// Raster, hybrid, hybrid_denoised and full RT against the path-traced reference
    /// (`graph/reference.ron`): relMSE and ꟻLIP with GPU and wall ms, the path tracer at each
    /// mode's time, images and error maps (ACCURACY.md, "Modes against ground truth").
    Truth(truth::TruthArgs),
    /// The direct light of many lights: every light's shadow ray, one light picked by
    /// resampling from M candidates (several M), and ReSTIR DI (`graph/hybrid_restir.ron`)
    /// against the path-traced reference: GPU and wall ms, relMSE, ꟻLIP and flicker on a camera
    /// track (ACCURACY.md, "Many lights at equal time").
    Lights(lights::LightsArgs),
}

/// Runs the bench.
pub(crate) fn run(command: BenchCommand) -> Result<()> {
    match command {
        BenchCommand::Rays(args) => rays::run(args),
        BenchCommand::Scale(args) => scale::run(args),
        BenchCommand::Build(args) => build::run(args),
        BenchCommand::Track(args) => track::run(args),
        BenchCommand::Anim(args) => anim::run(args),
        BenchCommand::Error(args) => error::run(args),
        BenchCommand::Roofline(args) => roofline::run(args),
        BenchCommand::Modes(args) => modes::run(args),
        BenchCommand::Depth(args) => depth::run(args),
        BenchCommand::Truth(args) => truth::run(args),
        BenchCommand::Lights(args) => lights::run(args),
    }
}
