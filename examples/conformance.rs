//! The glTF conformance pictures and numbers: every Khronos test model of `assets/khronos`
//! rendered in the three modes (raster, hybrid, full RT) from the reference's view, beside the
//! working group's reference screenshot and that screenshot as aligned on the render, one strip
//! per model, and the ꟻLIP mean of each mode against the reference over the model's pixels
//! (`raygraph::bench::conformance`: view, framing and per-channel gain matched) as a markdown
//! table on stdout:
//! `cargo run --release --example conformance -- [OUT_DIR] [LONG_SIDE] [MODEL]` (default
//! `docs/conformance`, 320, every model). The verdicts per feature, each backed by a test, are in
//! docs/conformance/README.md.

use anyhow::Context;
use raygraph::bench::conformance::{self, MODES};
use raygraph::runtime::Gpu;
use std::path::{Path, PathBuf};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "docs/conformance".into()));
    let long: u32 = args.next().map(|s| s.parse()).transpose().context("LONG_SIDE: a whole number of pixels")?.unwrap_or(320);
    let only = args.next();
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let gpu = Gpu::new()?;
    println!("adapter: {}\n", gpu.describe());
    println!("| model | raster | hybrid | full RT | model pixels | reference placed |\n| --- | --- | --- | --- | --- | --- |");
    for name in models(Path::new("assets/khronos"))?.into_iter().filter(|n| only.as_ref().map_or(true, |o| o == n)) {
        let (strip, row) = model_strip(&gpu, &name, long)?;
        let path = out.join(format!("{name}.png"));
        strip.save(&path).with_context(|| format!("cannot write {}", path.display()))?;
        println!("{row}");
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

/// The reference screenshot, the reference as aligned on the raster frame (black where it does
/// not reach), then raster, hybrid and full RT,
/// each at the reference's aspect with its longer side `long`, and the model's table row.
fn model_strip(gpu: &Gpu, name: &str, long: u32) -> anyhow::Result<(image::RgbaImage, String)> {
    let file = format!("assets/khronos/{name}/glTF/{name}.gltf");
    let reference = reference(name);
    let (w, h) = reference.as_ref().map_or((long, long), |r| conformance::frame_size(r.width(), r.height(), long));
    let (scene, report) = conformance::open(&file).map_err(anyhow::Error::msg)?;
    let camera = conformance::comparison_view(&scene, &report, w as f32 / h as f32);
    let mut strip = image::RgbaImage::from_pixel(w * 5, h, image::Rgba([40, 40, 40, 255]));
    if let Some(r) = &reference {
        image::imageops::overlay(&mut strip, &image::imageops::resize(r, w, h, image::imageops::FilterType::Triangle), 0, 0);
    }
    let mut mask = None;
    let mut alignment = None;
    let mut cells = Vec::new();
    for (i, mode) in MODES.iter().enumerate() {
        let (frame, frame_mask) =
            conformance::render(gpu, &scene, &camera, *mode, (w, h)).map_err(anyhow::Error::msg).with_context(|| format!("{file} in {} mode", mode.label()))?;
        mask = mask.or(frame_mask);
        image::imageops::overlay(&mut strip, &frame, (w * (i as u32 + 2)) as i64, 0);
        let Some(r) = &reference else {
            cells.push("— (no still reference)".into());
            continue;
        };
        let a = *alignment.get_or_insert_with(|| conformance::find_alignment(&frame, r));
        let m = mask.as_ref().context("the raster frame gives the model's pixels")?;
        if i == 0 {
            let aligned = conformance::align_reference(r, a, (w, h));
            let tile = image::RgbaImage::from_fn(w, h, |x, y| {
                let c = aligned[(y * w + x) as usize].unwrap_or([0.0; 3]);
                image::Rgba([0, 1, 2].map(|k| conformance::linear_to_srgb8(c[k])).into_iter().chain([255]).collect::<Vec<u8>>().try_into().expect("4 channels"))
            });
            image::imageops::overlay(&mut strip, &tile, w as i64, 0);
        }
        cells.push(conformance::compare(&frame, m, r, a).map_or_else(|e| format!("— ({e})"), |c| format!("{:.3}", c.flip_mean)));
    }
    let pixels = mask.map_or(0, |m| m.iter().filter(|p| **p).count());
    let placed = alignment.map_or("—".into(), |a| format!("x{:.3} at ({:.0}, {:.0}), edges {:.2}", a.scale, a.offset[0], a.offset[1], a.score));
    Ok((strip, format!("| {name} | {} | {pixels} | {placed} |", cells.join(" | "))))
}

/// The model's still reference screenshot (PNG or JPEG; the animated GIFs are left out).
fn reference(name: &str) -> Option<image::RgbaImage> {
    ["png", "jpg"].iter().find_map(|ext| image::open(format!("assets/khronos/{name}/screenshot/screenshot.{ext}")).ok()).map(|i| i.to_rgba8())
}
