//! The text of graph and layer files: reading them ([`crate::graph::files`]: from disk or the
//! built-in copy), parsing their RON, and [`SourceText::locate`], which finds where a key or
//! value is written, from the spans of a parse of the file's structure
//! ([`crate::graph::ron_spans`]), so that errors point at it.

use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use crate::graph::ron_spans::RonSpans;
use std::path::{Path, PathBuf};

/// Text of a file with helpers to find where a name is written.
#[derive(Clone)]
pub(super) struct SourceText {
    pub(super) path: PathBuf,
    pub(super) text: String,
    /// The keys and values of `text` with their byte offsets: what `locate` searches.
    pub(super) spans: RonSpans,
}

impl SourceText {
    /// Location of the place the anchors lead to ([`RonSpans::locate`]: each anchor a key or
    /// value inside the previous one's item, quoted for strings); the last anchor found (or the
    /// file start) when one is missing.
    pub(super) fn locate(&self, anchors: &[&str]) -> Location {
        Location::at_offset(&self.path, &self.text, self.spans.locate(anchors))
    }

    pub(super) fn quoted(s: &str) -> String {
        format!("\"{s}\"")
    }
}

pub(super) fn read_file(path: &Path, from: Option<Location>) -> Result<SourceText, GraphError> {
    match crate::graph::files::read(path) {
        Ok(f) => Ok(SourceText { path: f.path, spans: RonSpans::parse(&f.text), text: f.text }),
        Err(e) => Err(GraphError::new(ErrorKind::Io, from.unwrap_or_else(|| Location::file_start(path)), format!("cannot read {}: {e}", path.display()))),
    }
}

pub(super) fn parse_ron<T: serde::de::DeserializeOwned>(src: &SourceText, what: &str) -> Result<T, GraphError> {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES).from_str::<T>(&src.text).map_err(|e| {
        GraphError::new(ErrorKind::Syntax, Location::new(&src.path, e.position.line as u32, e.position.col as u32), format!("invalid {what} file: {}", e.code))
            .help(format!("see docs/ARCHITECTURE.md for the {what} file format"))
    })
}

/// Phase 1: parse a graph file.
#[cfg_attr(not(feature = "cli"), allow(dead_code))]
pub(crate) fn parse_graph(path: &Path) -> Result<GraphDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "graph")
}

/// Phase 1 for layers: parse a layer file.
pub fn parse_layer(path: &Path) -> Result<LayerDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "layer")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every node of every shipped graph file, and every pass of every shipped layer file, is
    /// found where its name is written.
    #[test]
    fn every_node_and_pass_of_the_shipped_files_is_found_at_its_name() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut checked = 0;
        for (dir, anchor, what) in [("graph", "nodes", "node"), ("layers", "passes", "pass")] {
            for entry in std::fs::read_dir(root.join(dir)).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().and_then(|e| e.to_str()) != Some("ron") {
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap();
                let names: Vec<String> = if what == "node" {
                    parse_graph(&path).unwrap_or_else(|e| panic!("{e}")).nodes.keys().cloned().collect()
                } else {
                    parse_layer(&path).unwrap_or_else(|e| panic!("{e}")).passes.iter().map(|p| p.name.clone()).collect()
                };
                let source = read_file(&path, None).unwrap();
                for name in names {
                    let quoted = format!("\"{name}\"");
                    let offset = source.spans.locate(&[anchor, &quoted]);
                    assert!(
                        text[offset..].starts_with(&quoted),
                        "{}: {what} {name} located at {:?}",
                        path.display(),
                        &text[offset..(offset + 40).min(text.len())]
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 40, "only {checked} names checked");
    }
}
