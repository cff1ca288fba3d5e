//! Golden-image test of `graph/raster.ron` on the built-in scene at 160x90.
//!
//! Metric: RMSE over the RGB channels in 8-bit units must be <= 2.0, and at most 0.5% of the
//! pixels may differ by more than 24/255 in any channel (rasterization edges may move by a
//! pixel between driver versions). The reference `assets/reference/raster_160x90.png` is
//! regenerated only on purpose: `RAYGRAPH_BLESS=1 cargo test --test golden` (the test then
//! fails once, saying it wrote the file).

mod common;
use raygraph::graph::{compile, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::default_scene;

const W: u32 = 160;
const H: u32 = 90;
const MAX_RMSE: f64 = 2.0;
const MAX_OUTLIER_FRACTION: f64 = 0.005;
const OUTLIER_DIFF: i32 = 24;

#[test]
fn raster_graph_matches_reference_image() {
    let graph = common::repo().join("graph/raster.ron");
    let plan = compile(&graph, &Project::beside_graph(&graph), (W, H)).unwrap();
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, &scene.camera, &scene).unwrap();
    let img = exec.read_output(&gpu).unwrap();

    let reference_path = common::repo().join("assets/reference/raster_160x90.png");
    if std::env::var_os("RAYGRAPH_BLESS").is_some() {
        img.save(&reference_path).unwrap();
        panic!("wrote {}; rerun without RAYGRAPH_BLESS", reference_path.display());
    }
    let reference = image::open(&reference_path).unwrap_or_else(|e| panic!("cannot read {}: {e}", reference_path.display())).to_rgba8();
    assert_eq!(reference.dimensions(), img.dimensions());

    let mut sq = 0.0f64;
    let mut outliers = 0usize;
    for (a, b) in img.pixels().zip(reference.pixels()) {
        let mut worst = 0;
        for c in 0..3 {
            let d = a[c] as i32 - b[c] as i32;
            sq += (d * d) as f64;
            worst = worst.max(d.abs());
        }
        if worst > OUTLIER_DIFF {
            outliers += 1;
        }
    }
    let n = (W * H) as f64;
    let rmse = (sq / (3.0 * n)).sqrt();
    let outlier_fraction = outliers as f64 / n;
    println!("RMSE {rmse:.3} (8-bit units), outliers {:.3}%", outlier_fraction * 100.0);
    if rmse > MAX_RMSE || outlier_fraction > MAX_OUTLIER_FRACTION {
        let diff_path = std::env::temp_dir().join("raygraph_raster_actual.png");
        let _ = img.save(&diff_path);
        panic!(
            "image differs from the reference: RMSE {rmse:.3} (max {MAX_RMSE}), outliers {:.3}% (max {}%); actual image at {}",
            outlier_fraction * 100.0,
            MAX_OUTLIER_FRACTION * 100.0,
            diff_path.display()
        );
    }
    // The image is not trivially uniform: the scene is there.
    let distinct: std::collections::HashSet<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 100, "the render looks empty");
}
