//! The `raygraph` command line: parses the arguments, hands each subcommand to its module of
//! [`cli`], and on an error prints it and exits with status 1.

mod cli;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "raygraph", version, about = "Render-graph framework for hybrid ray tracing on wgpu")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless, write a PNG and print per-pass timings.
    Render(cli::render::RenderArgs),
    /// Graph files: validate or draw.
    Graph {
        #[command(subcommand)]
        command: cli::graph::GraphCommand,
    },
    /// Scenes: statistics and export.
    Scene {
        #[command(subcommand)]
        command: cli::scene::SceneCommand,
    },
    /// A long headless run in which the scene, the graph and a shader change; checks that
    /// memory and live GPU objects stay flat and the image finite (RELIABILITY.md).
    Soak(cli::soak::SoakArgs),
    /// The correctness suites on this adapter, at the sizes the test suite uses: hard-cases
    /// (watertightness, grazing, degenerate and non-finite geometry, offsets, culling: 13 cases
    /// of up to about 16,000 rays each, on every back-end and layout), agreement (every
    /// back-end against the f64 reference caster: 1,600 rays on each of box, organic and
    /// default, 600 on atrium; the closed organic mesh from inside; invalid rays) and
    /// reference-channels (every ray-traced channel of the full ray-tracing graph against the
    /// f64 reference renderer at 64x48, 8 AO rays, on default and a small scene, on every
    /// back-end and layout). One line per suite and back-end: passed, FAILED or not applicable
    /// (a back-end the adapter lacks); exits non-zero on any failure. On 2-core lavapipe: about
    /// 10 s for hard-cases, 10 s for agreement, 70 s for reference-channels (most of it the
    /// CPU reference, which a GPU machine's cores share out); seconds of GPU time on a GPU.
    Selftest(cli::selftest::SelftestArgs),
    /// The experiments.
    Bench {
        #[command(subcommand)]
        command: cli::bench::BenchCommand,
    },
    /// The live viewer: a window with the running graph, the per-pass profiler overlay, the
    /// parameters panel and hot reload of graph, layer and WGSL files.
    View(cli::view::ViewArgs),
}

/// Runs the subcommand.
fn run(command: Command) -> Result<()> {
    match command {
        Command::Render(args) => cli::render::run(args),
        Command::Graph { command } => cli::graph::run(command),
        Command::Scene { command } => cli::scene::run(command),
        Command::Soak(args) => cli::soak::run(args),
        Command::Selftest(args) => cli::selftest::run(args),
        Command::Bench { command } => cli::bench::run(command),
        Command::View(args) => cli::view::run(args),
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info,wgpu_core=warn,wgpu_hal=warn,naga=warn")).init();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e:#}");
            ExitCode::FAILURE
        }
    }
}
