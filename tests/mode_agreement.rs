//! The three modes agree where their techniques do not differ: with shadows (raster: the
//! shadow map's switch, `forward.shadows: false`; hybrid and full RT: the `shadow` node),
//! ambient occlusion and reflections switched off, raster, hybrid and full RT shade the same
//! G-buffer inputs with the same lights and one shading function, so their final images agree
//! within a stated ꟻLIP mean (whole image, silhouettes and sky included, default viewing
//! conditions of `nv_flip`) on both real assets and on the procedural metallic-roughness scene.
//! What is left between them: raster and hybrid share the rasterized inputs (they differ by
//! the resolve's rounding through the G-buffer formats); full RT picks texture levels by ray
//! cones instead of derivatives, and edges by ray hits instead of coverage. Each limit is three
//! times its measured mean.

mod common;

use common::{gpu, open};

use common::material_scene::metallic_roughness_scene;
use common::modes::render_without_effects;
use raygraph::backend::Backend;
use raygraph::bench::modes::flip_mean;
use raygraph::runtime::Gpu;
use raygraph::scene::{AlphaMode, Scene};

/// The Khronos models' limits (raster / hybrid, hybrid / full RT, raster / full RT). Measured
/// (lavapipe), the largest over the 14 models: 0.0220, 0.0002, 0.0220 (UnlitTest and
/// EmissiveStrengthTest; the raster G-buffer is a visibility buffer read as primary rays read
/// their hits, so hybrid and full RT agree but for edges); limits 3x that, rounded up.
const KHRONOS_LIMITS: [f32; 3] = [0.07, 0.001, 0.07];

/// ꟻLIP means of hybrid against raster, full RT against hybrid and full RT against raster.
fn check(gpu: &Gpu, what: &str, scene: &Scene, size: (u32, u32), limits: [f32; 3]) {
    let [raster, hybrid, full_rt] = ["graph/raster.ron", "graph/hybrid.ron", "graph/full_rt.ron"]
        .map(|g| render_without_effects(gpu, g, Backend::Compute, scene, size).read_output(gpu).unwrap());
    let pairs = [("raster / hybrid", &raster, &hybrid), ("hybrid / full RT", &hybrid, &full_rt), ("raster / full RT", &raster, &full_rt)];
    let mut failures = Vec::new();
    for ((name, a, b), limit) in pairs.into_iter().zip(limits) {
        let mean = flip_mean(a, b);
        println!("{what} ({}x{}): {name}: FLIP mean {mean:.4} (limit {limit})", size.0, size.1);
        if mean > limit {
            failures.push(format!("{name}: FLIP mean {mean:.4} > {limit}"));
        }
    }
    assert!(failures.is_empty(), "{what}: the modes differ with effects off:\n{}", failures.join("\n"));
}

#[test]
fn damaged_helmet_looks_the_same_in_every_mode_with_effects_off() {
    let gpu = gpu();
    // Measured: 0.0014, 0.0034, 0.0035 (lavapipe); limits 3x that, rounded up.
    check(&gpu, "DamagedHelmet", &open("assets/gltf/DamagedHelmet/DamagedHelmet.glb"), (128, 96), [0.005, 0.011, 0.011]);
}

#[test]
fn pine_looks_the_same_in_every_mode_with_effects_off() {
    let gpu = gpu();
    // The leaf cards are BLEND: hybrid and full RT composite them in depth order per pixel,
    // raster sorts whole instances (the cards of one mesh blend in their draw order), so they
    // differ where cards overlap, by design; both are checked against closed-form answers in
    // tests/blend.rs. Here the cards are cut
    // out at alpha 0.5 (MASK), so the comparison keeps covering the atlas's alpha test and
    // everything else on a real asset in all three modes.
    let mut pine = open("assets/gltf/smallpine/scene.gltf");
    for m in pine.materials_mut().iter_mut().filter(|m| m.alpha_mode == AlphaMode::Blend) {
        m.alpha_mode = AlphaMode::Mask(0.5);
    }
    // Measured: 0.0010, 0.0026, 0.0027 (lavapipe); limits 3x that, rounded up.
    check(&gpu, "smallpine", &pine, (128, 96), [0.003, 0.008, 0.009]);
}

#[test]
fn metallic_roughness_scene_looks_the_same_in_every_mode_with_effects_off() {
    let gpu = gpu();
    // Measured: 0.0082, 0.0054, 0.0107 (lavapipe: the far, minified ground carries most of it);
    // limits 3x that, rounded up.
    check(&gpu, "metallic-roughness scene", &metallic_roughness_scene().0, (128, 96), [0.025, 0.017, 0.033]);
}

/// The 14 Khronos test models, each from the view it is compared with its reference from
/// (`raygraph::bench::conformance::comparison_view`), at its reference's aspect, 128 pixels on
/// the longer side: one limit for all of them.
#[test]
fn every_khronos_model_looks_the_same_in_every_mode_from_its_reference_view() {
    use raygraph::bench::conformance;
    let gpu = gpu();
    let root = common::repo().join("assets/khronos");
    for name in common::khronos_models() {
        let file = root.join(format!("{name}/glTF/{name}.gltf"));
        let (mut scene, report) = conformance::open(file.to_str().unwrap()).unwrap();
        let reference = ["png", "jpg", "gif"].iter().map(|ext| root.join(format!("{name}/screenshot/screenshot.{ext}"))).find(|p| p.exists()).unwrap();
        let (w, h) = image::image_dimensions(&reference).unwrap_or((128, 128));
        let size = conformance::frame_size(w, h, 128);
        *scene.camera_mut() = conformance::comparison_view(&scene, &report, size.0 as f32 / size.1 as f32);
        check(&gpu, &name, &scene, size, KHRONOS_LIMITS);
    }
}
