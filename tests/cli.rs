//! The `raygraph` binary as a user runs it.

mod common;
use std::process::Command;

fn raygraph() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_raygraph"));
    c.current_dir(common::repo());
    c
}

#[test]
fn graph_check_prints_the_plan() {
    let out = raygraph().args(["graph", "check", "graph/raster.ron"]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("forward/draw") && stdout.contains("tonemap/tonemap"), "{stdout}");
    assert!(stdout.contains("transient memory:"), "{stdout}");
}

#[test]
fn graph_check_of_a_broken_copy_fails_with_a_location() {
    let p = common::TempProject::new();
    for dir in ["layers", "shaders"] {
        let status = Command::new("cp").arg("-r").arg(common::repo().join(dir)).arg(&p.root).status().unwrap();
        assert!(status.success());
    }
    let text = std::fs::read_to_string(common::repo().join("graph/raster.ron")).unwrap().replace("\"forward.color\"", "\"forward.colour\"");
    let path = p.write("graph/raster.ron", &text);
    let out = Command::new(env!("CARGO_BIN_EXE_raygraph")).args(["graph", "check"]).arg(&path).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = common::line_of(&text, "forward.colour");
    assert!(stderr.contains(&format!("{}:{line}:", path.display())), "{stderr}");
    assert!(stderr.contains("help:"), "{stderr}");
}

#[test]
fn graph_dot_writes_graphviz() {
    let out = raygraph().args(["graph", "dot", "graph/raster.ron"]).output().unwrap();
    assert!(out.status.success());
    let dot = String::from_utf8_lossy(&out.stdout);
    assert!(dot.starts_with("digraph"), "{dot}");
    assert!(dot.contains("forward/draw") && dot.contains("tonemap.color"), "{dot}");
}

#[test]
fn render_writes_a_png_and_prints_the_pass_table() {
    let out_png = std::env::temp_dir().join(format!("raygraph-cli-{}.png", std::process::id()));
    let out = raygraph()
        .args(["render", "--width", "96", "--height", "54", "--frames", "2", "--out"])
        .arg(&out_png)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("adapter:"), "{stdout}");
    assert!(stdout.contains("GPU ms") && stdout.contains("forward/draw"), "{stdout}");
    let img = image::open(&out_png).unwrap();
    assert_eq!((img.width(), img.height()), (96, 54));
    let _ = std::fs::remove_file(out_png);
}

#[test]
fn render_to_an_unwritable_path_fails_cleanly() {
    let out = raygraph().args(["render", "--width", "16", "--height", "16", "--frames", "1", "--out", "/nonexistent-dir/x.png"]).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("/nonexistent-dir/x.png"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
