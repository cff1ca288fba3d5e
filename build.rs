//! Embeds the git revision the binary is built from (with `-dirty` for uncommitted changes), so
//! benchmark results name the code that produced them wherever the binary runs, and writes the
//! table of built-in files (`graph/`, `layers/`, `shaders/`) that `graph::files` embeds.

use std::path::Path;

/// The folders whose files are built in.
const BUILTIN_DIRS: [&str; 3] = ["graph", "layers", "shaders"];

fn main() {
    write_builtin_table();
    let git = |args: &[&str]| {
        std::process::Command::new("git").args(args).output().ok().filter(|o| o.status.success()).map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let revision = match git(&["rev-parse", "--short", "HEAD"]) {
        Some(rev) => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{rev}-dirty")
            } else {
                rev
            }
        }
        None => "unknown".to_string(),
    };
    println!("cargo:rustc-env=RAYGRAPH_REVISION={revision}");
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/index");
}

/// Writes `$OUT_DIR/builtin_files.rs`: `(relative path, include_str!(file))` for every file of
/// [`BUILTIN_DIRS`], sorted by path.
fn write_builtin_table() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let mut files = Vec::new();
    for dir in BUILTIN_DIRS {
        println!("cargo:rerun-if-changed={dir}");
        collect(Path::new(&manifest), Path::new(dir), &mut files);
    }
    files.sort();
    let mut out =
        String::from("/// Every built-in file: its path relative to the project root, and its text.\npub static BUILTIN_FILES: &[(&str, &str)] = &[\n");
    for rel in &files {
        out.push_str(&format!("    ({rel:?}, include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/\", {rel:?}))),\n"));
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("builtin_files.rs");
    std::fs::write(&dest, out).expect("write the built-in file table");
}

/// The `.ron` and `.wgsl` files under `root/rel`, as `/`-separated paths relative to `root`.
fn collect(root: &Path, rel: &Path, files: &mut Vec<String>) {
    let entries = std::fs::read_dir(root.join(rel)).unwrap_or_else(|e| panic!("cannot list {}: {e}", rel.display()));
    for entry in entries.flatten() {
        let child = rel.join(entry.file_name());
        if entry.path().is_dir() {
            collect(root, &child, files);
        } else if matches!(child.extension().and_then(|e| e.to_str()), Some("ron" | "wgsl")) {
            let parts: Vec<String> = child.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
            files.push(parts.join("/"));
        }
    }
}
