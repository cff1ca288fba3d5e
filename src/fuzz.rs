//! The file inputs a user can hand to raygraph, as entry points that take raw bytes: each
//! writes the bytes to a file in a private temporary folder and runs them through the same
//! path the command line does, so that the fuzz targets (`fuzz/`) and their regression tests
//! (`tests/reliability.rs`) exercise the real parsers, not a copy.
//!
//! Every entry point returns `Ok` or the error a user would see; a panic, a hang or an
//! unbounded allocation is a bug.
//!
//! The targets are driven by `fuzz/run.sh TARGET SECONDS`, which writes the evidence of each
//! run (target, revision, date, command, run count, duration, corpus size before and after,
//! coverage, findings) to `results/fuzz/TARGET-<UTC date>.log` (RELIABILITY.md).

use crate::accel::bvh::{AccelOptions, Blas, BuildConfig, SceneAccel};
use crate::accel::layout::{flatten, merge, merge_instances};
use crate::graph::compile::{compile, parse_layer, Project};
use crate::scene::track::Track;
use std::path::{Path, PathBuf};

/// The binding size the scene target checks the flattened arrays against (the WebGPU default
/// storage-binding limit, 128 MiB).
pub(crate) const FUZZ_MAX_BINDING: u64 = 128 << 20;
/// Frames of a fuzzed track that are evaluated.
pub(crate) const FUZZ_TRACK_FRAMES: u32 = 256;

/// A temporary folder private to this process, created on first use.
fn scratch() -> &'static Path {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("raygraph-inputs-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("layers")).expect("create the scratch folder");
        dir
    })
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("write the scratch file");
    path
}

/// The project's own layers and shaders (the source tree this crate was built from).
pub(crate) fn source_project() -> Project {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    Project { layers_dir: root.join("layers"), shaders_dir: root.join("shaders") }
}

/// A graph file, compiled against the project's layers and shaders for a 64x64 frame.
pub fn graph_file(bytes: &[u8]) -> Result<(), String> {
    let path = write("graph.ron", bytes);
    compile(&path, &source_project(), (64, 64)).map(|_| ()).map_err(|e| e.to_string())
}

/// A layer file, parsed, then compiled as the one node of a graph that shows its `color`
/// output (the project's shaders resolve its shader paths).
pub fn layer_file(bytes: &[u8]) -> Result<(), String> {
    let layer = write("layers/fuzz.ron", bytes);
    parse_layer(&layer).map_err(|e| e.to_string())?;
    let graph = write("layer_graph.ron", br#"Graph(output: "n.color", nodes: {"n": Layer(layer: "fuzz")})"#);
    let project = Project { layers_dir: scratch().join("layers"), shaders_dir: source_project().shaders_dir };
    compile(&graph, &project, (64, 64)).map(|_| ()).map_err(|e| e.to_string())
}

/// A glTF or GLB file, imported, then everything the acceleration-structure cache does with
/// it before an upload: both layouts built and flattened, and their arrays sized against
/// `FUZZ_MAX_BINDING`.
pub fn scene_file(bytes: &[u8]) -> Result<(), String> {
    let ext = if bytes.starts_with(b"glTF") { "glb" } else { "gltf" };
    let path = write(&format!("scene.{ext}"), bytes);
    let (mut scene, _) = crate::scene::load::open(path.to_str().expect("a UTF-8 scratch path"), &Default::default()).map_err(|e| e.to_string())?;
    // Every clip posed at a few times, meshes deformed on the CPU: every position finite or
    // dropped by the builds below, never a panic.
    let clips = scene.rig().map_or(0, |r| r.animations.len());
    for clip in 0..clips.min(4) {
        for time in [0.0, 0.37, 1e6, f32::NAN] {
            scene.pose(Some(clip), time);
        }
    }
    let two_level = flatten(&scene, &SceneAccel::build(&scene, &AccelOptions::default()));
    crate::accel::cache::check_fits(scene.name(), &two_level, FUZZ_MAX_BINDING).map_err(|e| e.to_string())?;
    let (mesh, origin) = merge_instances(&scene);
    let merged = merge(&mesh, &origin, Blas::build(&mesh, &BuildConfig::default()));
    crate::accel::cache::check_fits(scene.name(), &merged, FUZZ_MAX_BINDING).map_err(|e| e.to_string())?;
    let _ = scene.bounds();
    Ok(())
}

/// A camera track file, loaded and played for `FUZZ_TRACK_FRAMES` frames; every camera it
/// gives must be finite.
pub fn track_file(bytes: &[u8]) -> Result<(), String> {
    let path = write("track.ron", bytes);
    let track = Track::load(&path).map_err(|e| e.to_string())?;
    let base = crate::scene::Camera::look(glam::Vec3::new(0.0, 1.0, 5.0), glam::Vec3::ZERO, 60.0, 0.01, 100.0);
    for frame in 0..track.frame_count().min(FUZZ_TRACK_FRAMES) {
        let c = track.camera_at_frame(frame, &base);
        if !(c.position.is_finite() && c.target.is_finite() && c.fov_y.is_finite()) {
            return Err(format!("frame {frame} of a loaded track gives a non-finite camera"));
        }
    }
    Ok(())
}
