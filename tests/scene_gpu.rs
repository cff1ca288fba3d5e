//! The scene on the GPU: a glTF written by the test is rendered through `graph/raster.ron`
//! (the textured quad shows in the image), only what the graph reads is uploaded, and a scene
//! beyond the device's limits is an error with the numbers.

mod common;

use common::gltf_doc::{png, temp_dir, Doc};
use glam::Vec3;
use raygraph::graph::{compile, Project};
use raygraph::runtime::scene_upload::{GpuScene, SceneTextures};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{builtin, gltf_import, Camera, LoadOptions, Scene, TextureImage};
use serde_json::json;

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    gpu
}

#[test]
fn a_written_gltf_renders_through_the_raster_graph() {
    let dir = temp_dir("gltf-render");
    // A textured quad (green texture, white factor) facing +z, and a small red one in front.
    let mut d = Doc::new();
    let green = d.texture_embedded(&png(8, 8, [20, 230, 40, 255]));
    let m_green = d.material(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": green}}}));
    let m_red = d.material(json!({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.05, 0.05, 1.0]}}));
    let p = d.positions(&[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
    let uv = d.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 4);
    let i = d.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let quad_green = d.mesh(&[("POSITION", p), ("TEXCOORD_0", uv)], Some(i), Some(m_green), None);
    let quad_red = d.mesh(&[("POSITION", p), ("TEXCOORD_0", uv)], Some(i), Some(m_red), None);
    d.node(json!({"mesh": quad_green, "scale": [3.0, 3.0, 1.0]}), true);
    d.node(json!({"mesh": quad_red, "translation": [1.5, 0.0, 0.5], "scale": [0.5, 0.5, 1.0]}), true);
    let path = d.write_glb(&dir, "quads");

    let graph = common::repo().join("graph/raster.ron");
    let plan = compile(&graph, &Project::beside_graph(&graph), (96, 64)).unwrap();
    let (mut scene, _) = gltf_import::load(&path, &LoadOptions { textures: plan.scene_usage().textures, ..Default::default() }).unwrap();
    scene.light_mut().direction = Vec3::Z; // light from the camera's side
    let camera = Camera::look(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 50.0, 0.1, 100.0);
    let gpu = gpu();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, &camera, &scene).unwrap();
    let img = exec.read_output(&gpu).unwrap();
    let _ = img.save(std::env::temp_dir().join("raygraph_gltf_quads.png"));
    let at = |x: f32, y: f32| img.get_pixel((x * 96.0) as u32, (y * 64.0) as u32).0;
    let ndc = camera.view_proj(96.0 / 64.0).project_point3(Vec3::new(1.5, 0.0, 0.5));
    let (g, r) = (at(0.3, 0.5), at(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y));
    println!("green quad pixel {g:?}, red quad pixel {r:?}");
    let (g, r) = (g.map(u32::from), r.map(u32::from));
    assert!(g[1] > 100 && g[1] > 2 * g[0].max(g[2]), "the textured quad is green: {g:?}");
    assert!(r[0] > 200 && r[0] > r[1].max(r[2]) + 80, "the red quad is red: {r:?}");
    let corner = at(0.02, 0.02).map(u32::from);
    assert!(corner != g, "the background is not the quad");
    let _ = std::fs::remove_dir_all(&dir);
}

const FLAT_LAYER: &str = r#"// Draws the scene in flat white: reads instances, samples no textures.
Layer(
    outputs: { "color": Texture(format: Rgba8Unorm) },
    transients: { "depth": Texture(format: Depth32Float) },
    passes: [
        Pass(name: "draw", kind: SceneRaster, shader: "test/flat.wgsl", writes: ["color", "depth"]),
    ],
)"#;

const FLAT_WGSL: &str = r#"//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return frame.view_proj * (scene_instances[instance].model * vec4<f32>(position, 1.0));
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0);
}
"#;

#[test]
fn only_what_the_graph_reads_is_uploaded() {
    let p = common::TempProject::new();
    common::copy_dir(&common::repo().join("shaders/common"), &p.root.join("shaders/common"));
    p.write("layers/flat.ron", FLAT_LAYER);
    p.write("shaders/test/flat.wgsl", FLAT_WGSL);
    let plan = p.compile("flat.ron", r#"Graph(output: "flat.color", nodes: {"flat": Layer(layer: "flat")})"#).unwrap();
    assert!(plan.scene_usage().geometry && plan.scene_usage().instances);
    assert!(!plan.scene_usage().textures && !plan.scene_usage().materials, "{:?}", plan.scene_usage());
    let gpu = gpu();
    let scene = builtin::default_scene();
    let exec = Executor::new(&gpu, plan, &scene).unwrap();
    let up = exec.uploaded_scene().expect("the scene is drawn");
    assert!(up.textures().is_none() && up.materials().is_none(), "no textures or materials uploaded");
    assert!(up.vertices().is_some() && up.instances().is_some());

    // The raster graph samples textures: they are uploaded with their mip chain.
    let graph = common::repo().join("graph/raster.ron");
    let plan = compile(&graph, &Project::beside_graph(&graph), (32, 32)).unwrap();
    assert!(plan.scene_usage().textures && plan.scene_usage().materials);
    let exec = Executor::new(&gpu, plan, &scene).unwrap();
    let Some(SceneTextures::Array { texture, .. }) = exec.uploaded_scene().unwrap().textures() else { panic!("the default options bind a texture array") };
    assert_eq!(texture.depth_or_array_layers(), scene.textures().len() as u32 + 1);
    assert_eq!(texture.mip_level_count(), raygraph::runtime::scene_upload::TEXTURE_MIPS);
}

/// Metric: RMSE over RGB in 8-bit units <= 3 between the texture-array and binding-array
/// renders of the default scene (its textures are 256², so only filtering details differ).
#[test]
fn texture_binding_arrays_and_the_texture_array_draw_the_same_picture() {
    let gpu = gpu();
    assert!(gpu.texture_binding_arrays(), "lavapipe has texture binding arrays; CI must exercise them");
    let graph = common::repo().join("graph/raster.ron");
    let scene = builtin::default_scene();
    let mut images = Vec::new();
    for options in [raygraph::graph::compile::CompileOptions::default(), gpu.compile_options()] {
        let plan = raygraph::graph::compile::compile_with(&graph, &Project::beside_graph(&graph), (160, 90), &options).unwrap();
        let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
        match exec.uploaded_scene().unwrap().textures().unwrap() {
            SceneTextures::Array { .. } => assert!(options.includes.is_empty()),
            SceneTextures::Pooled { textures, views } => {
                // One array per size and encoding: the layers hold every texture and white.
                let pool = raygraph::scene::texture_pool::TexturePool::of(&scene);
                assert_eq!(views.len(), pool.arrays.len());
                assert!(pool.arrays.len() < scene.textures().len() + 1, "the default scene's textures share sizes: {}", pool.arrays.len());
                let layers: u32 = textures.iter().map(|t| t.depth_or_array_layers()).sum();
                assert_eq!(layers as usize, scene.textures().len() + 1);
            }
        }
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        images.push(exec.read_output(&gpu).unwrap());
    }
    let sq: f64 = images[0].pixels().zip(images[1].pixels()).flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).powi(2))).sum();
    let rmse = (sq / (3.0 * 160.0 * 90.0)).sqrt();
    println!("texture array vs binding array: RMSE {rmse:.3}");
    // Measured on lavapipe (Mesa 25.0.7), 2026-11-29: identical (RMSE 0): the same texels
    // sampled through either binding.
    assert!(rmse == 0.0, "RMSE {rmse}");
}

/// The default scene with its textures replaced by `count` white 1x1 ones.
fn default_scene_with_tiny_textures(count: usize) -> Scene {
    let mut scene: Scene = builtin::default_scene();
    let tiny = TextureImage { name: "t".into(), width: 1, height: 1, rgba: vec![255; 4].into() };
    *scene.textures_mut() = vec![tiny; count];
    scene
}

#[test]
fn a_scene_beyond_the_device_limits_is_an_error_with_the_numbers() {
    let gpu = gpu();
    let limit = gpu.device().limits().max_texture_array_layers;
    let scene = default_scene_with_tiny_textures(limit as usize + 5);
    let usage = raygraph::scene::usage::SceneUsage { textures: true, ..Default::default() };
    let err = match GpuScene::upload(gpu.device(), gpu.queue(), &scene, usage, None) {
        Ok(_) => panic!("{} texture layers uploaded with a limit of {limit}", limit + 6),
        Err(e) => e.to_string(),
    };
    println!("{err}");
    assert!(err.contains(&(limit as u64 + 6).to_string()) && err.contains(&limit.to_string()), "{err}");
    assert!(err.contains("default"), "names the scene: {err}");
}

/// More textures than the device has binding-array elements upload pooled: the limit applies to
/// the arrays (one per size and encoding, and per 256 textures of one).
#[test]
fn more_textures_than_binding_array_elements_upload_pooled() {
    let gpu = gpu();
    let limit = gpu.device().limits().max_binding_array_elements_per_shader_stage;
    let scene = default_scene_with_tiny_textures(limit as usize + 5);
    let usage = raygraph::scene::usage::SceneUsage { textures: true, texture_binding_array: true, ..Default::default() };
    let uploaded = GpuScene::upload(gpu.device(), gpu.queue(), &scene, usage, None).expect("pooled upload");
    let Some(SceneTextures::Pooled { textures, .. }) = uploaded.textures() else { panic!("a binding array was asked for") };
    // White and the 1x1 textures share arrays of 256 layers.
    let pool = raygraph::scene::texture_pool::POOL_LAYERS as u32;
    assert_eq!(textures.len() as u32, (limit + 6).div_ceil(pool), "limit {limit}");
    assert!(textures.iter().all(|t| t.depth_or_array_layers() <= pool));
}

/// An executor made for one scene renders a changed scene exactly as a fresh executor made for
/// the changed scene does: moved instances (records rewritten in place), an added mesh and
/// instance, and their removal (scene uploaded again), through a raster and a hybrid graph.
#[test]
fn the_executor_follows_a_changing_scene() {
    let gpu = gpu();
    let size = (80, 48);
    let base = builtin::default_scene();
    let mut moved = base.clone();
    moved.instances_mut()[0].transform = glam::Mat4::from_translation(Vec3::new(0.4, 0.2, -0.3)) * moved.instances()[0].transform;
    let mut added = base.clone();
    added.push_mesh(builtin::sphere("added", 8, 16));
    let mesh = added.meshes().len() - 1;
    added.instances_mut().push(raygraph::scene::Instance {
        mesh,
        material: 0,
        transform: glam::Mat4::from_translation(base.camera().target + Vec3::Y * 0.3) * glam::Mat4::from_scale(Vec3::splat(0.6)),
    });
    for graph in ["graph/raster.ron", "graph/hybrid.ron"] {
        let path = common::repo().join(graph);
        let project = Project::beside_graph(&path);
        let plan = || raygraph::graph::compile::compile_with(&path, &project, size, &gpu.compile_options()).unwrap();
        let render = |exec: &mut Executor, scene: &Scene| {
            exec.render(&gpu, scene.camera(), scene).unwrap();
            exec.read_output(&gpu).unwrap()
        };
        let mut exec = Executor::new(&gpu, plan(), &base).unwrap();
        let first = render(&mut exec, &base);
        for (what, scene) in [("moved", &moved), ("added", &added), ("base again", &base)] {
            let followed = render(&mut exec, scene);
            let fresh = render(&mut Executor::new(&gpu, plan(), scene).unwrap(), scene);
            let differing = followed.pixels().zip(fresh.pixels()).filter(|(a, b)| a != b).count();
            assert_eq!(differing, 0, "{graph}, {what}: {differing} pixels differ from a fresh executor's image");
            let changed = followed.pixels().zip(first.pixels()).filter(|(a, b)| a != b).count();
            println!("{graph}, {what}: same as a fresh executor; {changed} pixels differ from the first frame");
            if what == "base again" {
                assert_eq!(changed, 0, "{graph}: back to the first scene, the image must be the first one");
            } else {
                assert!(changed > 20, "{graph}, {what}: the change must show in the image ({changed} pixels)");
            }
        }
    }
}
