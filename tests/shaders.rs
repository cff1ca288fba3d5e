//! Every WGSL file in `shaders/` (and the test fixtures) parses and validates with naga.

mod common;
use raygraph::error::Location;
use raygraph::graph::reflect::{reflect, reflect_with};
use raygraph::runtime::gpu::all_include_variants;
use std::path::{Path, PathBuf};

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            wgsl_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
}

fn is_include(f: &Path) -> bool {
    f.components().any(|c| c.as_os_str() == "common" || c.as_os_str() == "trace")
}

/// Shaders with entry points validate under every include substitution a device can select;
/// the included files (`common/`, `trace/`) are validated as part of them, and each must be
/// reached by at least one shader under at least one variant.
#[test]
fn every_wgsl_file_validates() {
    for root in [common::repo().join("shaders"), common::fixtures().join("shaders")] {
        let mut files = Vec::new();
        wgsl_files(&root, &mut files);
        assert!(!files.is_empty(), "no WGSL under {}", root.display());
        let mut reached = std::collections::BTreeSet::new();
        for f in files.iter().filter(|f| !is_include(f)) {
            for aliases in all_include_variants() {
                let info = reflect_with(f, &root, &Location::file_start(f), &aliases).unwrap_or_else(|e| panic!("{e}\n(include substitutions {aliases:?})"));
                assert!(!info.entry_points.is_empty(), "{} has no entry point", f.display());
                for s in info.source.files() {
                    reached.insert(s.to_path_buf());
                }
            }
        }
        for f in files.iter().filter(|f| is_include(f)) {
            assert!(reached.contains(f.as_path()), "{} is included by no shader, so nothing validates it", f.display());
        }
    }
}

#[test]
fn included_files_report_their_own_lines() {
    let root = common::repo().join("shaders");
    let f = root.join("forward/shade.wgsl");
    let info = reflect(&f, &root, &Location::file_start(&f)).unwrap();
    let text = std::fs::read_to_string(&f).unwrap();
    let params = info.binding("params").unwrap();
    assert!(params.location.file.ends_with("forward/shade.wgsl"));
    assert_eq!(params.location.line, common::line_of(&text, "var<uniform> params"));
    // A binding declared in an include names the include's line.
    let frame = info.binding("frame").unwrap();
    assert!(frame.location.file.ends_with("common/scene_bindings.wgsl"), "{}", frame.location);
    let bindings = std::fs::read_to_string(root.join("common/scene_bindings.wgsl")).unwrap();
    assert_eq!(frame.location.line, common::line_of(&bindings, "var<uniform> frame"));
    // An offset inside the appended include maps back into the include.
    let offset = info.source.text().find("struct Instance").unwrap();
    let loc = info.source.locate(offset);
    assert!(loc.file.ends_with("common/scene.wgsl"), "{loc}");
    let inc = std::fs::read_to_string(root.join("common/scene.wgsl")).unwrap();
    assert_eq!(loc.line, common::line_of(&inc, "struct Instance"));
}

/// No two files under `shaders/` share a name: an include's name says what it holds, and an
/// `//#include "common/x.wgsl"` never reads as another folder's `x.wgsl`.
#[test]
fn no_two_shader_files_share_a_name() {
    let mut files = Vec::new();
    wgsl_files(&common::repo().join("shaders"), &mut files);
    let mut by_name: std::collections::BTreeMap<String, Vec<String>> = std::collections::BTreeMap::new();
    for f in &files {
        by_name.entry(f.file_name().unwrap().to_string_lossy().into_owned()).or_default().push(f.display().to_string());
    }
    let clashes: Vec<String> = by_name.values().filter(|paths| paths.len() > 1).map(|paths| paths.join(" and ")).collect();
    assert!(clashes.is_empty(), "shader files sharing a name; name each for what it holds:\n{}", clashes.join("\n"));
}
