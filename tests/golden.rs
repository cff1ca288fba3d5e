//! Golden-image test of `graph/raster.ron` on the built-in scene at 160x90.
//!
//! Metric: RMSE over the RGB channels in 8-bit units must be <= MAX_RMSE (3x the measured
//! value), and no pixel may differ by more than 24/255 in any channel. The reference
//! `assets/reference/raster_160x90.png` is regenerated only on purpose: `RAYGRAPH_BLESS=1 cargo test --test golden` prints the new
//! image's difference from the old one and writes it only within BLESS_CAP_RMSE and
//! BLESS_CAP_OUTLIERS, or with `RAYGRAPH_BLESS_REASON="why the picture changed"`; each blessing
//! adds a line to `assets/reference/raster_160x90.blessings.md` (the test then fails once,
//! saying it wrote the file).

mod common;
use raygraph::graph::{compile, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::default_scene;

const W: u32 = 160;
const H: u32 = 90;
/// Measured on lavapipe (Mesa 25.0.7), 2026-11-29: RMSE 0.005, no outlier; the bound is 3x
/// that. A driver that moves rasterization edges fails here and the image is blessed again
/// (below), within the caps or with a reason.
const MAX_RMSE: f64 = 0.015;
const MAX_OUTLIER_FRACTION: f64 = 0.0;
const OUTLIER_DIFF: i32 = 24;
/// A blessing that changes the picture more than this needs a reason: what edges moved by a
/// pixel give (the test's bounds before 2026-11-29: RMSE 2, 0.5% of the pixels past
/// OUTLIER_DIFF).
const BLESS_CAP_RMSE: f64 = 2.0;
const BLESS_CAP_OUTLIERS: f64 = 0.005;

#[test]
fn raster_graph_matches_reference_image() {
    let graph = common::repo().join("graph/raster.ron");
    let plan = compile(&graph, &Project::beside_graph(&graph), (W, H)).unwrap();
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    let img = exec.read_output(&gpu).unwrap();

    let reference_path = common::repo().join("assets/reference/raster_160x90.png");
    let old = image::open(&reference_path).map(|i| i.to_rgba8());
    if std::env::var_os("RAYGRAPH_BLESS").is_some() {
        bless(&img, old.ok(), &reference_path);
    }
    let reference = old.unwrap_or_else(|e| panic!("cannot read {}: {e}", reference_path.display()));
    assert_eq!(reference.dimensions(), img.dimensions());
    let (rmse, outlier_fraction) = difference(&img, &reference);
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

/// RMSE over RGB in 8-bit units, and the fraction of pixels with a channel off by more than
/// OUTLIER_DIFF.
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (f64, f64) {
    let mut sq = 0.0f64;
    let mut outliers = 0usize;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let mut worst = 0;
        for c in 0..3 {
            let d = p[c] as i32 - q[c] as i32;
            sq += (d * d) as f64;
            worst = worst.max(d.abs());
        }
        if worst > OUTLIER_DIFF {
            outliers += 1;
        }
    }
    let n = a.pixels().len() as f64;
    ((sq / (3.0 * n)).sqrt(), outliers as f64 / n)
}

/// Whether a new reference that differs from the old one by `rmse` and `outlier_fraction` may
/// be written: within the caps, or with a stated reason.
fn bless_allowed(rmse: f64, outlier_fraction: f64, reason: Option<&str>) -> Result<(), String> {
    let within = rmse <= BLESS_CAP_RMSE && outlier_fraction <= BLESS_CAP_OUTLIERS;
    match reason.map(str::trim).filter(|r| !r.is_empty()) {
        _ if within => Ok(()),
        Some(_) => Ok(()),
        None => Err(format!(
            "refused: the new image differs from the old reference by RMSE {rmse:.3} (cap {BLESS_CAP_RMSE}), outliers {:.3}% (cap {}%); \
             set RAYGRAPH_BLESS_REASON to say why the picture changed",
            outlier_fraction * 100.0,
            BLESS_CAP_OUTLIERS * 100.0
        )),
    }
}

/// `RAYGRAPH_BLESS`: prints the difference from the old reference, refuses above the caps
/// without RAYGRAPH_BLESS_REASON, else writes the new image and a line in the blessing log.
fn bless(img: &image::RgbaImage, old: Option<image::RgbaImage>, path: &std::path::Path) -> ! {
    let reason = std::env::var("RAYGRAPH_BLESS_REASON").ok();
    let (rmse, outliers) = match &old {
        Some(old) if old.dimensions() == img.dimensions() => difference(img, old),
        _ => (f64::INFINITY, 1.0),
    };
    println!("blessing: the new image against the old reference: RMSE {rmse:.3}, outliers {:.3}%", outliers * 100.0);
    if let Err(e) = bless_allowed(rmse, outliers, reason.as_deref()) {
        panic!("{e}");
    }
    img.save(path).unwrap();
    let log = path.with_extension("blessings.md");
    let line = format!(
        "- {}: RMSE {rmse:.3}, outliers {:.3}% against the previous image; {}\n",
        raygraph::util::utc_timestamp(),
        outliers * 100.0,
        reason.as_deref().unwrap_or("within the caps")
    );
    let mut text = std::fs::read_to_string(&log).unwrap_or_else(|_| "# Blessings of raster_160x90.png (tests/golden.rs)\n\n".into());
    text.push_str(&line);
    std::fs::write(&log, text).unwrap();
    panic!("wrote {} and a line in {}; rerun without RAYGRAPH_BLESS", path.display(), log.display());
}

#[test]
fn blessing_is_refused_above_the_caps_without_a_reason() {
    assert!(bless_allowed(0.5, 0.0, None).is_ok(), "a small change needs no reason");
    assert!(bless_allowed(BLESS_CAP_RMSE * 1.01, 0.0, None).is_err(), "RMSE above the cap");
    assert!(bless_allowed(0.5, BLESS_CAP_OUTLIERS * 1.01, None).is_err(), "outliers above the cap");
    assert!(bless_allowed(f64::INFINITY, 1.0, Some("  ")).is_err(), "a blank reason is none");
    assert!(bless_allowed(f64::INFINITY, 1.0, Some("the sky gradient changed")).is_ok(), "a stated reason");
}
