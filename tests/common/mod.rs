//! Helpers shared by the integration tests: throw-away project directories built from the
//! fixtures in `tests/fixtures`, and line lookup for asserting error locations.
#![allow(dead_code)]

pub mod disk;
pub mod endless_fog;
pub mod gltf_doc;
pub mod lights;
pub mod material_scene;
pub mod modes;
pub mod xvfb;

use glam::Mat4;
use raygraph::graph::{compile, Plan, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{Instance, Material, Mesh, Scene};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn fixtures() -> PathBuf {
    repo().join("tests/fixtures")
}

/// The adapter the GPU tests run on (lavapipe in CI), printed.
pub fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    gpu
}

/// A scene file of the repository (path relative to its root), opened with default options.
pub fn open(rel: &str) -> Scene {
    raygraph::scene::open(repo().join(rel).to_str().unwrap(), &Default::default()).unwrap().0
}

/// Adds each (mesh, material, transform) to `scene` as a new mesh, material and instance.
pub fn add_parts(scene: &mut Scene, parts: impl IntoIterator<Item = (Mesh, Material, Mat4)>) {
    for (mesh, material, transform) in parts {
        let instance = Instance { mesh: scene.meshes().len(), material: scene.materials().len(), transform };
        scene.instances_mut().push(instance);
        scene.push_mesh(mesh);
        scene.materials_mut().push(material);
    }
}

/// The Khronos test models of `assets/khronos` (each a folder with `glTF/NAME.gltf`), sorted:
/// all 14.
pub fn khronos_models() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(repo().join("assets/khronos"))
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("glTF").is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 14);
    names
}

/// Mean, and largest deviation from `expected`, of channel `c` over `texels`.
pub fn judge(texels: &[[f32; 4]], c: usize, expected: f32) -> (f32, f32) {
    let mean = texels.iter().map(|t| t[c]).sum::<f32>() / texels.len() as f32;
    let worst = texels.iter().map(|t| (t[c] - expected).abs()).fold(0.0f32, f32::max);
    (mean, worst)
}

/// The texels of the graph resource `name` after a frame (the plan compiled without reuse).
pub fn channel(gpu: &Gpu, exec: &Executor, name: &str) -> Vec<[f32; 4]> {
    let r = exec.plan().resource_by_name(name).unwrap_or_else(|| panic!("no resource {name}"));
    exec.read_texture_f32(gpu, r).unwrap().2
}

/// A directory with `graph/`, `layers/` and `shaders/`, seeded with the fixture layers and
/// shaders, removed on drop.
pub struct TempProject {
    pub root: PathBuf,
}

static COUNTER: AtomicU32 = AtomicU32::new(0);

pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

impl TempProject {
    pub fn new() -> Self {
        let n = COUNTER.fetch_add(1, Ordering::SeqCst);
        let root = std::env::temp_dir().join(format!("raygraph-test-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        copy_dir(&fixtures().join("layers"), &root.join("layers"));
        copy_dir(&fixtures().join("shaders"), &root.join("shaders"));
        std::fs::create_dir_all(root.join("graph")).unwrap();
        Self { root }
    }

    /// A project with the repository's own `layers/` and `shaders/` (fixtures replaced), for
    /// tests that write variants of the shipped graphs.
    pub fn with_repo_files() -> Self {
        let p = Self::new();
        for dir in ["layers", "shaders"] {
            let _ = std::fs::remove_dir_all(p.root.join(dir));
            copy_dir(&repo().join(dir), &p.root.join(dir));
        }
        p
    }

    pub fn write(&self, rel: &str, text: &str) -> PathBuf {
        let p = self.root.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }

    pub fn project(&self) -> Project {
        Project { layers_dir: self.root.join("layers"), shaders_dir: self.root.join("shaders") }
    }

    /// Writes `graph/<name>` and compiles it at 64x32.
    pub fn compile(&self, name: &str, graph: &str) -> Result<Plan, raygraph::error::GraphError> {
        let path = self.write(&format!("graph/{name}"), graph);
        compile(&path, &self.project(), (64, 32))
    }
}

impl Drop for TempProject {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.root);
    }
}

/// 1-based line of the first line of `text` containing `needle`.
pub fn line_of(text: &str, needle: &str) -> u32 {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("`{needle}` not in text")) as u32 + 1
}

/// `graph/ao.ron` without its `blend` node (AO and shadows from the G-buffer, resolved), written
/// to a file of its own; the repository's layers and shaders.
pub fn ao_graph_without_blend() -> (std::path::PathBuf, Project) {
    let text = std::fs::read_to_string(repo().join("graph/ao.ron")).unwrap();
    let start = text.find("        // BLEND surfaces composited").expect("graph/ao.ron has its blend node");
    let end = text.find("        \"tonemap\"").unwrap();
    // The tone map and the graph's HDR output read the resolve's image instead.
    let text = format!("{}{}", &text[..start], &text[end..]).replace("\"blend.color\"", "\"resolve.hdr\"");
    let dir = std::env::temp_dir().join(format!("raygraph-ao-graph-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ao_without_blend.ron");
    std::fs::write(&path, text).unwrap();
    (path, Project { layers_dir: repo().join("layers"), shaders_dir: repo().join("shaders") })
}
