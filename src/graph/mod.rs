//! The render graph: file formats ([`desc`]), shader reflection ([`reflect`]), the compiler
//! ([`compile`](mod@compile)) that turns a graph file into a [`compile::Plan`], Graphviz output ([`dot`]),
//! and the built-in project files read when the disk has none ([`files`]).
//! Nothing here touches the GPU; [`crate::runtime`] executes plans.

pub(crate) mod builtins;
pub mod compile;
pub mod desc;
pub mod dot;
pub mod files;
pub mod reflect;
pub(crate) mod ron_spans;

pub use compile::{compile, Plan, Project};

/// The paper's three rendering modes, each a built-in graph file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Mode {
    /// Rasterization: forward shading with shadow maps (`graph/raster.ron`).
    Raster,
    /// A rasterized G-buffer, then ray-traced shadows, AO and reflections (`graph/hybrid.ron`).
    Hybrid,
    /// Full ray tracing: the G-buffer from primary rays as well (`graph/full_rt.ron`).
    FullRt,
}

impl Mode {
    /// The three modes, in the paper's order.
    pub const ALL: [Mode; 3] = [Mode::Raster, Mode::Hybrid, Mode::FullRt];

    /// The mode's graph file, relative to the project root (built in, see [`files`]).
    pub fn graph(self) -> &'static str {
        match self {
            Mode::Raster => "graph/raster.ron",
            Mode::Hybrid => "graph/hybrid.ron",
            Mode::FullRt => "graph/full_rt.ron",
        }
    }

    /// The mode's name in reports (`raster`, `hybrid`, `full RT`).
    pub fn label(self) -> &'static str {
        match self {
            Mode::Raster => "raster",
            Mode::Hybrid => "hybrid",
            Mode::FullRt => "full RT",
        }
    }
}
