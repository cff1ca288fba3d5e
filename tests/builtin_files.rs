//! The built-in graphs, layers and shaders: `raygraph render` from a directory without them,
//! a file on disk overriding its built-in copy, and the headless example from anywhere.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[allow(dead_code)] // `main` is the example's; the test calls its `run`
#[path = "../examples/headless.rs"]
mod headless;

/// An empty directory under the system temp dir, removed on drop.
struct EmptyDir(PathBuf);

impl EmptyDir {
    fn new(tag: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("raygraph-builtin-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    fn write(&self, rel: &str, text: &str) -> PathBuf {
        let p = self.0.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for EmptyDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `raygraph render` of the default scene at 64x36 into `<dir>/x.png`, run in `dir`.
fn render_in(dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .current_dir(dir)
        .args(["render", "--width", "64", "--height", "36", "--frames", "1", "--out"])
        .arg(dir.join("x.png"))
        .output()
        .unwrap()
}

fn repo_file(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap()
}

#[test]
fn render_from_an_empty_directory_uses_the_builtin_files() {
    let dir = EmptyDir::new("empty");
    let out = render_in(&dir.0);
    assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let img = image::open(dir.0.join("x.png")).unwrap().to_rgba8();
    assert_eq!((img.width(), img.height()), (64, 36));
    // The built-in copies are the repository's files: the same picture as a render in the
    // repository, byte for byte.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let beside = EmptyDir::new("repo-render");
    let out = Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .current_dir(repo)
        .args(["render", "--width", "64", "--height", "36", "--frames", "1", "--out"])
        .arg(beside.0.join("x.png"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let from_repo = image::open(beside.0.join("x.png")).unwrap().to_rgba8();
    assert!(img == from_repo, "the built-in files draw what the repository's draw");
}

#[test]
fn a_layer_on_disk_overrides_its_builtin_copy() {
    let plain = EmptyDir::new("plain");
    assert!(render_in(&plain.0).status.success());
    let no_sky = EmptyDir::new("no-sky");
    let tonemap = repo_file("layers/tonemap.ron");
    let sky = "\"sky\": Bool(default: true)";
    assert!(tonemap.contains(sky), "layers/tonemap.ron no longer declares `{sky}`");
    no_sky.write("layers/tonemap.ron", &tonemap.replace(sky, "\"sky\": Bool(default: false)"));
    let out = render_in(&no_sky.0);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let with = image::open(plain.0.join("x.png")).unwrap().to_rgba8();
    let without = image::open(no_sky.0.join("x.png")).unwrap().to_rgba8();
    let changed: Vec<_> = with.pixels().zip(without.pixels()).filter(|(a, b)| a != b).map(|(_, b)| b.0).collect();
    assert!(!changed.is_empty(), "the disk copy's `sky: false` must remove the sky");
    assert!(changed.iter().all(|p| p[..3] == [0, 0, 0]), "only sky texels change, to black: {:?}", &changed[..changed.len().min(4)]);
}

#[test]
fn a_broken_layer_on_disk_is_reported_at_its_disk_path() {
    let dir = EmptyDir::new("broken");
    let text = repo_file("layers/tonemap.ron").replace("kind: Compute,", "kind: Compute,,");
    dir.write("layers/tonemap.ron", &text);
    let out = render_in(&dir.0);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = text.lines().position(|l| l.contains("Compute,,")).unwrap() + 1;
    assert!(stderr.contains(&format!("layers/tonemap.ron:{line}:")), "{stderr}");
    assert!(!stderr.contains("<built-in>") && !stderr.contains("panicked"), "{stderr}");
    assert!(!dir.0.join("x.png").exists());
}

#[test]
fn an_error_in_a_builtin_file_names_it_as_built_in() {
    let dir = EmptyDir::new("mismatch");
    let graph = repo_file("graph/raster.ron").replace("{\"hdr\": \"forward.color\"}", "{\"hdr\": \"shadow_map.depth\"}");
    assert!(graph.contains("shadow_map.depth\"}"), "graph/raster.ron no longer feeds the tone map from forward.color");
    dir.write("graph/g.ron", &graph);
    let out = Command::new(env!("CARGO_BIN_EXE_raygraph")).current_dir(&dir.0).args(["graph", "check", "graph/g.ron"]).output().unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = repo_file("layers/tonemap.ron").lines().position(|l| l.contains("\"hdr\":")).unwrap() + 1;
    assert!(stderr.contains(&format!("<built-in>/layers/tonemap.ron:{line}:")), "{stderr}");
    assert!(stderr.contains("graph/g.ron:"), "{stderr}");
}

#[test]
fn the_headless_example_renders_from_an_empty_directory() {
    let dir = EmptyDir::new("example");
    // The only test of this binary that depends on the working directory.
    std::env::set_current_dir(&dir.0).unwrap();
    let out = dir.0.join("frame.png");
    headless::run([out.to_string_lossy().into_owned()].into_iter()).unwrap();
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), headless::SIZE);
    let first = img.get_pixel(0, 0);
    assert!(img.pixels().any(|p| p != first), "the frame is one flat colour");
    assert!(headless::run(["x.png".to_string(), "sideways".to_string()].into_iter()).unwrap_err().to_string().contains("unknown mode"));
}
