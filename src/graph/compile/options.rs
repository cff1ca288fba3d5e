//! What a compilation is given besides the graph file: [`Project`] (where layer files and
//! shaders live) and [`CompileOptions`] (reuse, include substitutions, back-end, parameter
//! overrides, node switches).

use crate::backend::Backend;
use crate::graph::desc::ParamValue;
use crate::graph::reflect;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where layer files and shaders are found.
#[derive(Debug, Clone)]
pub struct Project {
    /// Directory holding `<layer>.ron` files.
    pub layers_dir: PathBuf,
    /// Directory that shader paths in layer files are relative to.
    pub shaders_dir: PathBuf,
}

impl Project {
    /// The layout of this repository: `graph/`, `layers/` and `shaders/` side by side. A file
    /// missing there is read from the built-in copy ([`crate::graph::files`]).
    pub fn beside_graph(graph_file: &Path) -> Self {
        let root = graph_file.parent().and_then(|p| p.parent()).unwrap_or(Path::new("."));
        let root = if root.as_os_str().is_empty() { Path::new(".") } else { root };
        Self { layers_dir: root.join("layers"), shaders_dir: root.join("shaders") }
    }
}

/// Compiler switches.
#[derive(Debug, Clone)]
pub struct CompileOptions {
    /// Let identical resources with disjoint lifetimes share memory.
    pub reuse: bool,
    /// Include substitutions of the device (see `reflect::IncludeAliases`).
    pub includes: reflect::IncludeAliases,
    /// Layer substitutions of the device: a node of layer `k` is compiled from the file of
    /// layer `v` instead (a layer the device cannot run, replaced by one with the same
    /// interface that it can: `forward` by `forward_fragment` without primitive indices).
    pub layers: BTreeMap<String, String>,
    /// The traversal back-end trace passes are compiled for: `trace/trace.wgsl` becomes its
    /// module.
    pub backend: Backend,
    /// Parameter values that override the graph file's, as `("node", "param") -> value`
    /// (benches, the viewer); checked like the file's own.
    pub params: BTreeMap<(String, String), ParamValue>,
    /// Layer nodes switched on (`true`) or off (`false`) over the graph file's `enabled`
    /// (the viewer's effect switches).
    pub enabled: BTreeMap<String, bool>,
}

impl Default for CompileOptions {
    fn default() -> Self {
        Self {
            reuse: true,
            includes: reflect::IncludeAliases::new(),
            layers: BTreeMap::new(),
            backend: Backend::Compute,
            params: BTreeMap::new(),
            enabled: BTreeMap::new(),
        }
    }
}

impl CompileOptions {
    /// The include substitutions in effect: the device's, plus the back-end's trace module.
    pub fn all_includes(&self) -> reflect::IncludeAliases {
        let mut a = self.includes.clone();
        // `trace/trace.wgsl` itself includes the compute back-end, the default.
        if self.backend != Backend::Compute {
            a.insert(TRACE_INCLUDE.into(), self.backend.trace_module().into());
        }
        a
    }
}

/// The include every trace pass uses; the back-end substitutes its module for it.
const TRACE_INCLUDE: &str = "trace/trace.wgsl";
