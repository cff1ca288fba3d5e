//! The built-in graphs, layers and shaders, embedded in the binary, and the one way project
//! files are read: from disk when the file is there, else the built-in copy of the same
//! relative path (`layers/forward.ron`), named `<built-in>/layers/forward.ron` in errors.

use std::path::{Component, Path, PathBuf};

include!(concat!(env!("OUT_DIR"), "/builtin_files.rs"));

/// The folders whose files are built in.
const BUILTIN_DIRS: [&str; 3] = ["graph", "layers", "shaders"];

/// What the path of a built-in file starts with.
pub(crate) const BUILTIN_PREFIX: &str = "<built-in>";

/// A project file's text, and the path its errors name.
#[derive(Debug, Clone)]
pub struct FileText {
    /// The disk path, or `<built-in>/<relative path>` for an embedded copy.
    pub path: PathBuf,
    /// The file's text.
    pub text: String,
    /// The text is the built-in copy's, byte for byte (read from the binary, or a file on
    /// disk identical to it).
    pub builtin: bool,
}

/// The built-in text of a relative path such as `layers/forward.ron`.
pub fn builtin(relative: &str) -> Option<&'static str> {
    BUILTIN_FILES.binary_search_by(|(p, _)| (*p).cmp(relative)).ok().map(|i| BUILTIN_FILES[i].1)
}

/// The relative path a built-in copy of `path` would have: its part from the last `graph`,
/// `layers` or `shaders` folder on (`/proj/layers/x.ron` -> `layers/x.ron`).
pub(crate) fn builtin_name(path: &Path) -> Option<String> {
    let mut parts: Vec<String> = Vec::new();
    for c in path.components() {
        match c {
            Component::Normal(s) => parts.push(s.to_string_lossy().into_owned()),
            Component::ParentDir => {
                parts.pop();
            }
            _ => {}
        }
    }
    let start = parts.iter().rposition(|p| BUILTIN_DIRS.contains(&p.as_str()))?;
    (start + 1 < parts.len()).then(|| parts[start..].join("/"))
}

/// The built-in copy of `path`, if there is one: its relative path and text.
fn builtin_of(path: &Path) -> Option<(String, &'static str)> {
    let name = builtin_name(path)?;
    builtin(&name).map(|text| (name, text))
}

/// Reads `path` from disk; when no such file exists, its built-in copy.
pub fn read(path: &Path) -> std::io::Result<FileText> {
    match std::fs::read_to_string(path) {
        Ok(text) => {
            let builtin = builtin_of(path).is_some_and(|(_, copy)| copy == text);
            Ok(FileText { path: path.to_path_buf(), text, builtin })
        }
        // A browser has no file system (`Unsupported`): every file is the built-in copy.
        Err(e) if matches!(e.kind(), std::io::ErrorKind::NotFound | std::io::ErrorKind::Unsupported) => match builtin_of(path) {
            Some((name, text)) => Ok(FileText { path: Path::new(BUILTIN_PREFIX).join(name), text: text.to_string(), builtin: true }),
            None => Err(e),
        },
        Err(e) => Err(e),
    }
}

/// Whether [`read`] finds `path`, on disk or built in.
pub fn exists(path: &Path) -> bool {
    path.is_file() || builtin_of(path).is_some()
}

/// The stems of the `.ron` files of `dir`, on disk and built in, sorted and without repeats.
pub(crate) fn ron_stems(dir: &Path) -> Vec<String> {
    let mut stems: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "ron"))
                .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
                .collect()
        })
        .unwrap_or_default();
    if let Some(prefix) = builtin_name(&dir.join("x")).and_then(|n| n.strip_suffix('x').map(str::to_string)) {
        for (name, _) in BUILTIN_FILES {
            if let Some(stem) = name.strip_prefix(prefix.as_str()).and_then(|rest| rest.strip_suffix(".ron")).filter(|s| !s.contains('/')) {
                stems.push(stem.to_string());
            }
        }
    }
    stems.sort();
    stems.dedup();
    stems
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_names_are_the_part_from_the_last_project_folder() {
        assert_eq!(builtin_name(Path::new("./layers/forward.ron")).as_deref(), Some("layers/forward.ron"));
        assert_eq!(builtin_name(Path::new("/a/graph/b/shaders/common/x.wgsl")).as_deref(), Some("shaders/common/x.wgsl"));
        assert_eq!(builtin_name(Path::new("shaders/rt/../common/x.wgsl")).as_deref(), Some("shaders/common/x.wgsl"));
        assert_eq!(builtin_name(Path::new("/tmp/x.ron")), None);
        assert_eq!(builtin_name(Path::new("layers")), None);
    }

    #[test]
    fn a_missing_file_reads_as_its_builtin_copy() {
        let dir = std::env::temp_dir().join(format!("raygraph-files-{}", std::process::id()));
        let f = read(&dir.join("layers/tonemap.ron")).expect("built-in tonemap layer");
        assert_eq!(f.path, Path::new("<built-in>/layers/tonemap.ron"));
        assert_eq!(f.text, builtin("layers/tonemap.ron").unwrap());
        assert!(read(&dir.join("layers/no_such_layer.ron")).is_err());
        assert!(ron_stems(&dir.join("layers")).contains(&"forward".to_string()));
        assert!(ron_stems(&dir.join("graph")).contains(&"raster".to_string()));
    }
}
