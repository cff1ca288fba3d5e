//! The render graph: file formats ([`desc`]), shader reflection ([`reflect`]), the compiler
//! ([`compile`]) that turns a graph file into a [`compile::Plan`], Graphviz output ([`dot`]),
//! and the built-in project files read when the disk has none ([`files`]).
//! Nothing here touches the GPU; [`crate::runtime`] executes plans.

pub mod builtins;
pub mod compile;
pub mod desc;
pub mod dot;
pub mod files;
pub mod reflect;
pub(crate) mod ron_spans;

pub use compile::{compile, Plan, Project};

/// The paper's three rendering modes, each a built-in graph file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Mode {
    Raster,
    Hybrid,
    FullRt,
}

impl Mode {
    pub const ALL: [Mode; 3] = [Mode::Raster, Mode::Hybrid, Mode::FullRt];

    /// The mode's graph file, relative to the project root (built in, see [`files`]).
    pub fn graph(self) -> &'static str {
        match self {
            Mode::Raster => "graph/raster.ron",
            Mode::Hybrid => "graph/hybrid.ron",
            Mode::FullRt => "graph/full_rt.ron",
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            Mode::Raster => "raster",
            Mode::Hybrid => "hybrid",
            Mode::FullRt => "full RT",
        }
    }
}
