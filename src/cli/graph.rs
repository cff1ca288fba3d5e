//! `raygraph graph`: graph files validated or drawn.

use anyhow::{Context, Result};
use raygraph::graph::{self, Project};
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub(crate) enum GraphCommand {
    /// Validate a graph file (and its layers and shaders) and print the plan.
    Check {
        file: PathBuf,
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
    },
    /// Write the compiled graph as Graphviz (to stdout, or --out).
    Dot {
        file: PathBuf,
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// `raygraph graph check` and `raygraph graph dot`.
pub(crate) fn run(command: GraphCommand) -> Result<()> {
    match command {
        GraphCommand::Check { file, width, height } => {
            let plan = graph::compile(&file, &Project::beside_graph(&file), (width, height))?;
            print!("{}", plan.report());
            println!("ok: {} is valid", file.display());
        }
        GraphCommand::Dot { file, out } => {
            let plan = graph::compile(&file, &Project::beside_graph(&file), (1280, 720))?;
            let dot = graph::dot::to_dot(&plan);
            match out {
                Some(path) => std::fs::write(&path, dot).with_context(|| format!("could not write {}", path.display()))?,
                None => print!("{dot}"),
            }
        }
    }
    Ok(())
}
