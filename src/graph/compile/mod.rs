//! The graph compiler: [`compile_with`] is its list of phases, each in its own file:
//!
//! 1. `source`: read and parse the graph file; `resolve`: apply the options' node switches;
//!    `bypass`: hand the readers of a switched-off filter what feeds it; `resolve`: check that
//!    there is at most one `Accel` node, read each node's layer file and check its
//!    parameters and the options' overrides;
//! 2. `connect`: declare every output, transient and history, connect every input to its
//!    producer;
//! 3. `schedule`: collect the passes (one producer per resource), find cycles, the output
//!    (and the HDR output), the passes that reach them and their order;
//! 4. `interface`: reflect every pass's shader and check its interface;
//! 5. `lifetimes`: the kept passes as [`PlannedPass`]es, each resource's lifetime and usage;
//! 6. `allocate`: slots, shared by identical resources whose lifetimes do not overlap;
//! 7. `plan`: the resulting [`Plan`].

mod allocate;
mod bypass;
mod connect;
mod interface;
mod lifetimes;
mod options;
mod plan;
mod resolve;
mod schedule;
mod source;

pub use options::{CompileOptions, Project};
pub use plan::{fmt_bytes, Plan, PlannedPass, PlannedResource, ResourceId, Slot, Usage};
pub(crate) use resolve::check_param;
#[cfg(feature = "cli")]
pub(crate) use source::parse_graph;
pub use source::parse_layer;

use crate::error::GraphError;
use crate::graph::desc::GraphDesc;
use std::path::Path;

/// Compiles a graph file into an executable plan for a frame of `frame_size`.
pub fn compile(graph_file: &Path, project: &Project, frame_size: (u32, u32)) -> Result<Plan, GraphError> {
    compile_with(graph_file, project, frame_size, &CompileOptions::default())
}

/// [`compile`] with explicit options. The phases run in this order, and the first error ends
/// the compilation.
pub fn compile_with(graph_file: &Path, project: &Project, frame_size: (u32, u32), options: &CompileOptions) -> Result<Plan, GraphError> {
    let gsrc = source::read_file(graph_file, None)?;
    let mut graph: GraphDesc = source::parse_ron(&gsrc, "graph")?;
    resolve::apply_switches(&mut graph, &options.enabled, graph_file)?;
    bypass::apply_bypasses(&mut graph, project, &options.layers)?;
    resolve::check_one_accel(&graph, &gsrc)?;
    let mut nodes = resolve::resolve_layers(&graph, &gsrc, project, &options.layers)?;
    for node in &nodes {
        bypass::check_bypass(&node.layer, &node.layer_src, &node.layer_name)?;
    }
    resolve::apply_param_overrides(&mut nodes, &options.params, graph_file)?;

    connect::check_history(&nodes)?;
    let mut resources = connect::declare_resources(&mut nodes, frame_size);
    connect::connect_inputs(&graph, &gsrc, &mut nodes, &mut resources)?;

    let (passes, producers) = schedule::collect_passes(&nodes)?;
    schedule::check_tile_sizes(&nodes, &passes, &resources)?;
    schedule::check_conditions(&nodes, &passes, &resources)?;
    let order = schedule::schedule(&graph, &gsrc, &nodes, &passes, &resources, &producers)?;

    let shaders = interface::check_shaders(project, options, &nodes, &passes, &resources)?;

    let planned = lifetimes::planned_passes(&order.kept, &nodes, &passes, &shaders);
    let used = lifetimes::set_lifetimes_and_usage(&planned, &mut resources, order.output, order.hdr_output);
    let slots = allocate::allocate_slots(&mut resources, used, options.reuse);

    Ok(Plan {
        graph_file: graph_file.to_path_buf(),
        frame_size,
        scene_usage: lifetimes::scene_usage(&planned),
        passes: planned,
        culled: order.culled,
        resources,
        slots,
        output: order.output,
        hdr_output: order.hdr_output,
        backend: options.backend,
    })
}
