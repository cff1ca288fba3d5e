//! The text of graph and layer files: reading them ([`crate::graph::files`]: from disk or the
//! built-in copy), parsing their RON, and [`SourceText::locate`], which finds where a name is
//! written (comments left out) so that errors point at it.

use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::desc::*;
use std::path::{Path, PathBuf};

/// Text of a file with helpers to find where a name is written.
#[derive(Clone)]
pub(super) struct SourceText {
    pub(super) path: PathBuf,
    pub(super) text: String,
    /// `text` with its comments blanked (same byte offsets): what `locate` searches.
    pub(super) code: String,
}

impl SourceText {
    /// Location of the last anchor, each searched after the previous one; falls back to the
    /// last anchor found (or the file start).
    pub(super) fn locate(&self, anchors: &[&str]) -> Location {
        let mut pos = 0usize;
        let mut found = 0usize;
        for a in anchors {
            if let Some(p) = self.code[pos..].find(a) {
                found = pos + p;
                pos = found + a.len();
            }
        }
        Location::at_offset(&self.path, &self.text, found)
    }

    pub(super) fn quoted(s: &str) -> String {
        format!("\"{s}\"")
    }
}

/// `text` with every `//` and `/* */` comment (nested ones too, as RON allows) made spaces,
/// byte for byte, so that a name in a comment is never where an error points; string contents
/// are kept.
fn blank_comments(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = bytes.to_vec();
    let (mut i, mut in_string, mut depth) = (0usize, false, 0usize);
    while i < bytes.len() {
        let pair = (bytes[i], bytes.get(i + 1).copied().unwrap_or(0));
        let width = if depth > 0 {
            match pair {
                (b'*', b'/') => depth -= 1,
                (b'/', b'*') => depth += 1,
                _ => {}
            }
            let width = if matches!(pair, (b'*', b'/') | (b'/', b'*')) { 2 } else { 1 };
            out[i..i + width].iter_mut().filter(|b| **b != b'\n').for_each(|b| *b = b' ');
            width
        } else if in_string {
            in_string = bytes[i] != b'"';
            if bytes[i] == b'\\' {
                2
            } else {
                1
            }
        } else {
            match pair {
                (b'/', b'/') => {
                    let end = text[i..].find('\n').map_or(bytes.len(), |e| i + e);
                    out[i..end].fill(b' ');
                    end - i
                }
                (b'/', b'*') => {
                    depth = 1;
                    out[i..i + 2].fill(b' ');
                    2
                }
                _ => {
                    in_string = bytes[i] == b'"';
                    1
                }
            }
        };
        i += width;
    }
    // Whole characters were replaced, each byte by an ASCII space: still UTF-8.
    String::from_utf8(out).unwrap_or_else(|_| text.to_string())
}

pub(super) fn read_file(path: &Path, from: Option<Location>) -> Result<SourceText, GraphError> {
    match crate::graph::files::read(path) {
        Ok(f) => Ok(SourceText { path: f.path, code: blank_comments(&f.text), text: f.text }),
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
pub(crate) fn parse_graph(path: &Path) -> Result<GraphDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "graph")
}

/// Phase 1 for layers: parse a layer file.
pub fn parse_layer(path: &Path) -> Result<LayerDesc, GraphError> {
    let src = read_file(path, None)?;
    parse_ron(&src, "layer")
}
