//! The glTF conformance pictures: every Khronos test model of `assets/khronos` rendered in the
//! three modes (raster, hybrid, full RT) from the file's default view, beside the working
//! group's reference screenshot, one strip per model:
//! `cargo run --release --example conformance -- [OUT_DIR] [SIZE]` (default `docs/conformance`,
//! 240). The verdicts per feature, each backed by a test, are in docs/conformance/README.md.
//! The references were rendered by the glTF Sample Viewer with image-based lighting, so their
//! lighting differs from raygraph's default sun and sky; geometry, texture placement, colours
//! and what each model tests should match.

use anyhow::Context;
use raygraph::graph::{self, Mode, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::LoadOptions;
use std::path::{Path, PathBuf};

const MODES: [Mode; 3] = [Mode::Raster, Mode::Hybrid, Mode::FullRt];

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "docs/conformance".into()));
    let size: u32 = args.next().map(|s| s.parse()).transpose().context("SIZE: a whole number of pixels")?.unwrap_or(240);
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.describe());
    for name in models(Path::new("assets/khronos"))? {
        let strip = model_strip(&gpu, &name, size)?;
        let path = out.join(format!("{name}.png"));
        strip.save(&path).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The model folders (each with `glTF/NAME.gltf`), sorted.
fn models(root: &Path) -> anyhow::Result<Vec<String>> {
    let mut names: Vec<String> = std::fs::read_dir(root)
        .with_context(|| format!("cannot read {} (run from the repository root)", root.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("glTF").is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    Ok(names)
}

/// The reference screenshot, then raster, hybrid and full RT, each `size` pixels square.
fn model_strip(gpu: &Gpu, name: &str, size: u32) -> anyhow::Result<image::RgbaImage> {
    let mut strip = image::RgbaImage::from_pixel(size * 4, size, image::Rgba([40, 40, 40, 255]));
    if let Some(reference) = reference(name) {
        image::imageops::overlay(&mut strip, &fit(&reference, size), 0, 0);
    }
    let file = format!("assets/khronos/{name}/glTF/{name}.gltf");
    for (i, mode) in MODES.iter().enumerate() {
        let frame = render(gpu, &file, *mode, size).with_context(|| format!("{file} in {} mode", mode.label()))?;
        image::imageops::overlay(&mut strip, &frame, (size * (i as u32 + 1)) as i64, 0);
    }
    Ok(strip)
}

/// The model's still reference screenshot (PNG or JPEG; the animated GIFs are left out).
fn reference(name: &str) -> Option<image::RgbaImage> {
    ["png", "jpg"].iter().find_map(|ext| image::open(format!("assets/khronos/{name}/screenshot/screenshot.{ext}")).ok()).map(|i| i.to_rgba8())
}

/// `img` scaled to fit a `size` square, centred on black.
fn fit(img: &image::RgbaImage, size: u32) -> image::RgbaImage {
    let scale = size as f32 / img.width().max(img.height()) as f32;
    let (w, h) = (((img.width() as f32 * scale) as u32).max(1), ((img.height() as f32 * scale) as u32).max(1));
    let scaled = image::imageops::resize(img, w, h, image::imageops::FilterType::Triangle);
    let mut tile = image::RgbaImage::from_pixel(size, size, image::Rgba([0, 0, 0, 255]));
    image::imageops::overlay(&mut tile, &scaled, ((size - w) / 2) as i64, ((size - h) / 2) as i64);
    tile
}

/// One frame of `file` through `mode`'s built-in graph from the file's default view.
fn render(gpu: &Gpu, file: &str, mode: Mode, size: u32) -> anyhow::Result<image::RgbaImage> {
    let graph_file = Path::new(mode.graph());
    let plan = graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), (size, size), &gpu.compile_options())?;
    let (scene, _) = raygraph::scene::open(file, &LoadOptions { textures: plan.scene_usage().textures, ..LoadOptions::default() })?;
    let mut exec = Executor::new(gpu, plan, &scene)?;
    exec.render(gpu, &scene.camera, &scene)?;
    Ok(exec.read_output(gpu)?)
}
