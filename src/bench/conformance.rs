//! The glTF conformance comparison (docs/conformance/README.md): a Khronos test model rendered
//! in each mode and compared with the working group's reference screenshot by ꟻLIP, over the
//! pixels where raygraph draws the model.
//!
//! The references were made by the glTF Sample Viewer (image-based lighting, its own camera
//! fit, cropped by hand), so three things are matched before the metric, each the same for
//! every model:
//! - the view ([`comparison_view`]): the file's camera where it has one, else the Sample
//!   Viewer's: on +Z looking towards -Z at the centre of the bounds over the whole animation,
//!   45° vertical field of view, the bounds' x and y extents fitted;
//! - the framing ([`find_alignment`]): the reference was cropped, so it is scaled and moved
//!   onto the render where their edges agree best: the normalised cross-correlation of the
//!   two images' luma gradients, searched over scales and offsets on images an eighth of the
//!   size, then refined at full size;
//! - the lighting (`fit_gains`): the render's linear colour is scaled per channel by the one
//!   gain that fits it to the reference best (least squares over the model's pixels). The
//!   lighting differs (a sun and sky against an environment map), so what is compared is what
//!   a model tests: colours, texture placement, cut-outs, coverage and blending, not brightness.
//!
//! The metric is the mean of ꟻLIP's per-pixel error (`nv-flip`, 67 pixels per degree) over the
//! model's pixels; elsewhere the render takes the reference's colour and adds no error.

use crate::graph::{self, Mode, Project};
use crate::runtime::{Executor, Gpu};
use crate::scene::{Bounds, Camera, ImportReport, LoadOptions, Scene};
use glam::Vec3;
use std::path::Path;

/// The modes compared, in their column order.
pub const MODES: [Mode; 3] = [Mode::Raster, Mode::Hybrid, Mode::FullRt];

/// A render's comparison with its reference.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Mean ꟻLIP error over the model's pixels, 0 (identical) to 1.
    pub flip_mean: f32,
    /// The model's pixels in the render that the aligned reference covers.
    pub pixels: usize,
    /// The per-channel gains applied to the render's linear colour.
    pub gains: [f32; 3],
    /// Where the reference lies on the render.
    pub alignment: Alignment,
}

/// The least edge correlation at which a reference counts as placed: below it the search found
/// no scale and offset where the two images' edges agree, as for a reference taken from another
/// view (checked by eye on the 13 still references: every one above it is placed right; some
/// below it are placed right too).
pub(crate) const PLACED_MIN_SCORE: f32 = 0.45;

/// The reference on the render: render pixel p (its centre) shows reference point
/// `scale x p + offset` (reference pixels); `score` is the edges' normalised cross-correlation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// Reference pixels per render pixel.
    pub scale: f32,
    /// The reference point at the render's corner (reference pixels).
    pub offset: [f32; 2],
    /// The normalised cross-correlation of the edges, -1 to 1.
    pub score: f32,
}

/// The Sample Viewer's view of `scene` (module docs) for a frame of `aspect` (width / height):
/// the file's camera when `report` counts one, else the bounds from the front.
pub fn comparison_view(scene: &Scene, report: &ImportReport, aspect: f32) -> Camera {
    if report.file_cameras > 0 {
        return *scene.camera();
    }
    let bounds = crate::scene::gltf_import::animated_bounds(scene);
    front_fit(bounds, aspect)
}

/// A 45° camera on +Z looking towards -Z at the centre of `bounds`, at the distance where their
/// x and y extents fit the frame, plus half their depth.
fn front_fit(bounds: Bounds, aspect: f32) -> Camera {
    if bounds.is_empty() {
        return Camera::default();
    }
    let extent = bounds.max - bounds.min;
    let half_tan = (0.5 * 45f32.to_radians()).tan();
    let distance = (0.5 * extent.y / half_tan).max(0.5 * extent.x / (half_tan * aspect)) + 0.5 * extent.z;
    let target = bounds.center();
    Camera::look(target + Vec3::Z * distance.max(1e-3), target, 45.0, 0.01, 1.0).fit_clip_planes(bounds)
}

/// One frame of `scene` through `mode`'s built-in graph from `camera`, `size` pixels: the
/// 8-bit output and, for raster, where the model is drawn (the forward layer's alpha).
pub fn render(gpu: &Gpu, scene: &Scene, camera: &Camera, mode: Mode, size: (u32, u32)) -> Result<(image::RgbaImage, Option<Vec<bool>>), String> {
    let graph_file = Path::new(mode.graph());
    let options = graph::compile::CompileOptions { reuse: false, ..gpu.compile_options() };
    let plan = graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), size, &options).map_err(|e| e.to_string())?;
    let mut exec = Executor::new(gpu, plan, scene).map_err(|e| e.to_string())?;
    exec.render(gpu, camera, scene).map_err(|e| e.to_string())?;
    let image = exec.read_output(gpu).map_err(|e| e.to_string())?;
    let mask = match exec.plan().resource_by_name("forward.color") {
        Some(r) => Some(exec.read_texture_f32(gpu, r).map_err(|e| e.to_string())?.2.iter().map(|p| p[3] > 0.5).collect()),
        None => None,
    };
    Ok((image, mask))
}

/// Opens `file` for the built-in graphs (every texture they read).
pub fn open(file: &str) -> Result<(Scene, ImportReport), String> {
    crate::scene::open(file, &LoadOptions::default()).map_err(|e| e.to_string())
}

/// The frame size for a reference of `width` x `height`: its aspect, the larger side `long`.
pub fn frame_size(width: u32, height: u32, long: u32) -> (u32, u32) {
    let scale = long as f32 / width.max(height) as f32;
    (((width as f32 * scale).round() as u32).max(8), ((height as f32 * scale).round() as u32).max(8))
}

/// `render` against `reference` placed by `alignment` ([`find_alignment`]), over the pixels of
/// `mask` (module docs); an error where the alignment's score is below `PLACED_MIN_SCORE`.
pub fn compare(render: &image::RgbaImage, mask: &[bool], reference: &image::RgbaImage, alignment: Alignment) -> Result<Comparison, String> {
    let (w, h) = render.dimensions();
    if !mask.iter().any(|m| *m) {
        return Err("the render shows nothing of the model".into());
    }
    if alignment.score < PLACED_MIN_SCORE {
        return Err(format!("the reference is not placed: edge correlation {:.2} < {PLACED_MIN_SCORE}", alignment.score));
    }
    let aligned = align_reference(reference, alignment, (w, h));
    let pixels: Vec<usize> = (0..mask.len()).filter(|&i| mask[i] && aligned[i].is_some()).collect();
    if pixels.is_empty() {
        return Err("the aligned reference covers none of the model's pixels".into());
    }
    let linear = |c: u8| srgb_to_linear(c as f32 / 255.0);
    let ours: Vec<[f32; 3]> = render.pixels().map(|p| [linear(p[0]), linear(p[1]), linear(p[2])]).collect();
    let theirs: Vec<[f32; 3]> = aligned.iter().map(|p| p.unwrap_or([0.0; 3])).collect();
    let gains = fit_gains(&ours, &theirs, &pixels);
    let mut test = vec![0u8; (w * h * 3) as usize];
    let mut reference_rgb = vec![0u8; (w * h * 3) as usize];
    for i in 0..mask.len() {
        for c in 0..3 {
            let theirs_c = linear_to_srgb8(theirs[i][c]);
            reference_rgb[i * 3 + c] = theirs_c;
            test[i * 3 + c] = if pixels.binary_search(&i).is_ok() { linear_to_srgb8(ours[i][c] * gains[c]) } else { theirs_c };
        }
    }
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &reference_rgb),
        nv_flip::FlipImageRgb8::with_data(w, h, &test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
    .to_vec();
    let flip_mean = pixels.iter().map(|&i| error[i] as f64).sum::<f64>() / pixels.len() as f64;
    Ok(Comparison { flip_mean: flip_mean as f32, pixels: pixels.len(), gains, alignment })
}

/// The reference resampled into the render's frame (bilinear, linear colour) by `alignment`;
/// `None` where it falls outside the reference.
pub fn align_reference(reference: &image::RgbaImage, alignment: Alignment, size: (u32, u32)) -> Vec<Option<[f32; 3]>> {
    let (rw, rh) = reference.dimensions();
    let texel = |x: u32, y: u32| {
        let p = reference.get_pixel(x, y);
        [0, 1, 2].map(|c| srgb_to_linear(p[c] as f32 / 255.0))
    };
    (0..size.0 * size.1)
        .map(|i| {
            let (px, py) = ((i % size.0) as f32 + 0.5, (i / size.0) as f32 + 0.5);
            let qx = alignment.scale * px + alignment.offset[0] - 0.5;
            let qy = alignment.scale * py + alignment.offset[1] - 0.5;
            if qx < 0.0 || qy < 0.0 || qx > (rw - 1) as f32 || qy > (rh - 1) as f32 {
                return None;
            }
            let (x0, y0) = (qx.floor() as u32, qy.floor() as u32);
            let (x1, y1) = ((x0 + 1).min(rw - 1), (y0 + 1).min(rh - 1));
            let (fx, fy) = (qx - x0 as f32, qy - y0 as f32);
            let (a, b, c, d) = (texel(x0, y0), texel(x1, y0), texel(x0, y1), texel(x1, y1));
            Some(std::array::from_fn(|k| (a[k] * (1.0 - fx) + b[k] * fx) * (1.0 - fy) + (c[k] * (1.0 - fx) + d[k] * fx) * fy))
        })
        .collect()
}

/// A grey image's luma-gradient magnitude, `factor` times smaller (box-filtered first).
struct EdgeMap {
    width: usize,
    height: usize,
    values: Vec<f32>,
}

impl EdgeMap {
    fn of(image: &image::RgbaImage, factor: u32) -> Self {
        let (w, h) = ((image.width() / factor).max(2) as usize, (image.height() / factor).max(2) as usize);
        let mut luma = vec![0.0f32; w * h];
        for (x, y, p) in image.enumerate_pixels() {
            let (cx, cy) = (((x / factor) as usize).min(w - 1), ((y / factor) as usize).min(h - 1));
            luma[cy * w + cx] += 0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32;
        }
        let at = |x: usize, y: usize| luma[y.min(h - 1) * w + x.min(w - 1)];
        let values = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let gx = at(x + 1, y) - at(x.saturating_sub(1), y);
                let gy = at(x, y + 1) - at(x, y.saturating_sub(1));
                (gx * gx + gy * gy).sqrt()
            })
            .collect();
        Self { width: w, height: h, values }
    }

    /// The normalised cross-correlation of `self` with `other` seen through `scale` and
    /// `offset` (other = scale x self + offset, in each map's own pixels), over the pixels
    /// where `other` is; `None` where they share less than half of `other` or less than 30% of
    /// `self` (the render frames the whole model, the reference most of it).
    fn correlation(&self, other: &EdgeMap, scale: f32, offset: [f32; 2]) -> Option<f32> {
        let (mut n, mut sa, mut sb, mut saa, mut sbb, mut sab) = (0usize, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for y in 0..self.height {
            let qy = scale * (y as f32 + 0.5) + offset[1];
            if qy < 0.0 || qy >= other.height as f32 {
                continue;
            }
            for x in 0..self.width {
                let qx = scale * (x as f32 + 0.5) + offset[0];
                if qx < 0.0 || qx >= other.width as f32 {
                    continue;
                }
                let a = self.values[y * self.width + x] as f64;
                let b = other.values[qy as usize * other.width + qx as usize] as f64;
                n += 1;
                (sa, sb, saa, sbb, sab) = (sa + a, sb + b, saa + a * a, sbb + b * b, sab + a * b);
            }
        }
        let covered = n as f32 * scale * scale;
        if covered < 0.5 * (other.width * other.height) as f32 || (n as f32) < 0.3 * (self.width * self.height) as f32 {
            return None;
        }
        let nf = n as f64;
        let var = (saa - sa * sa / nf) * (sbb - sb * sb / nf);
        (var > 1e-12).then(|| ((sab - sa * sb / nf) / var.sqrt()) as f32)
    }

    /// The best alignment over `scales` and whole-pixel offsets of `other` within `offsets`
    /// (its x and y ranges, `other`'s pixels).
    fn best(&self, other: &EdgeMap, scales: &[f32], offsets: impl Fn(f32) -> ([i32; 2], [i32; 2])) -> Option<Alignment> {
        let mut best: Option<Alignment> = None;
        for &scale in scales {
            let ([x0, x1], [y0, y1]) = offsets(scale);
            for oy in y0..=y1 {
                for ox in x0..=x1 {
                    let offset = [ox as f32, oy as f32];
                    if let Some(score) = self.correlation(other, scale, offset) {
                        if best.map_or(true, |b| score > b.score) {
                            best = Some(Alignment { scale, offset, score });
                        }
                    }
                }
            }
        }
        best
    }
}

/// Where `reference` lies on `render` (module docs): a search over 33 scales from half to
/// twice the ratio of their sizes and every offset at an eighth of the size, then 9 scales
/// within 3% and offsets within 12 pixels at full size. Scale 1 at the origin where nothing
/// correlates.
pub fn find_alignment(render: &image::RgbaImage, reference: &image::RgbaImage) -> Alignment {
    const COARSE: u32 = 8;
    let ratio = reference.width().max(reference.height()) as f32 / render.width().max(render.height()) as f32;
    let (ours, theirs) = (EdgeMap::of(render, COARSE), EdgeMap::of(reference, COARSE));
    let scales: Vec<f32> = (0..33).map(|k| ratio * 2f32.powf(k as f32 / 16.0 - 1.0)).collect();
    let span = |scale: f32| {
        let (w, h) = (ours.width as f32 * scale, ours.height as f32 * scale);
        ([-(w as i32), theirs.width as i32], [-(h as i32), theirs.height as i32])
    };
    let Some(coarse) = ours.best(&theirs, &scales, span) else {
        return Alignment { scale: 1.0, offset: [0.0, 0.0], score: 0.0 };
    };
    // At full size: render pixel p shows reference point scale x p + offset x COARSE (the
    // coarse maps' pixels are COARSE of each image's).
    let (ours, theirs) = (EdgeMap::of(render, 1), EdgeMap::of(reference, 1));
    let centre = [coarse.offset[0] * COARSE as f32, coarse.offset[1] * COARSE as f32];
    let fine_scales: Vec<f32> = (0..9).map(|k| coarse.scale * (1.0 + 0.0075 * (k as f32 - 4.0))).collect();
    let near = |_: f32| {
        let r = 12;
        ([centre[0] as i32 - r, centre[0] as i32 + r], [centre[1] as i32 - r, centre[1] as i32 + r])
    };
    ours.best(&theirs, &fine_scales, near).unwrap_or(Alignment { offset: centre, ..coarse })
}

/// Per channel, the gain g minimising the squared difference of g x `ours` and `theirs` over
/// `pixels` (1 where the render is black there).
pub(crate) fn fit_gains(ours: &[[f32; 3]], theirs: &[[f32; 3]], pixels: &[usize]) -> [f32; 3] {
    std::array::from_fn(|c| {
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for &i in pixels {
            num += (ours[i][c] * theirs[i][c]) as f64;
            den += (ours[i][c] * ours[i][c]) as f64;
        }
        if den > 1e-12 {
            (num / den) as f32
        } else {
            1.0
        }
    })
}

fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an 8-bit sRGB one.
pub fn linear_to_srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A picture of random flat rectangles on grey, `w` x `h`.
    fn rectangles(w: u32, h: u32) -> image::RgbaImage {
        let mut img = image::RgbaImage::from_pixel(w, h, image::Rgba([90, 90, 90, 255]));
        let mut seed = 12345u32;
        let mut next = |n: u32| {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) % n
        };
        for _ in 0..40 {
            let (x, y, rw, rh) = (next(w), next(h), 8 + next(w / 4), 8 + next(h / 4));
            let colour = image::Rgba([next(256) as u8, next(256) as u8, next(256) as u8, 255]);
            for py in y..(y + rh).min(h) {
                for px in x..(x + rw).min(w) {
                    img.put_pixel(px, py, colour);
                }
            }
        }
        img
    }

    #[test]
    fn the_search_finds_a_crop_scaled_and_moved_back() {
        let render = rectangles(320, 240);
        // A reference of 0.8 of the render from (40, 30), enlarged 1.5 times: render pixel p
        // shows reference point 1.5 x (p - (40, 30)).
        let crop = image::imageops::crop_imm(&render, 40, 30, 256, 192).to_image();
        let reference = image::imageops::resize(&crop, 384, 288, image::imageops::FilterType::Nearest);
        let a = find_alignment(&render, &reference);
        assert!((a.scale - 1.5).abs() < 0.02, "{a:?}");
        assert!((a.offset[0] + 60.0).abs() <= 2.0 && (a.offset[1] + 45.0).abs() <= 2.0, "{a:?}");
        assert!(a.score > PLACED_MIN_SCORE, "{a:?}");
    }

    #[test]
    fn a_render_against_itself_has_no_error_and_unit_gains() {
        let render = rectangles(160, 120);
        let mask = vec![true; 160 * 120];
        let a = Alignment { scale: 1.0, offset: [0.0, 0.0], score: 1.0 };
        let c = compare(&render, &mask, &render, a).unwrap();
        assert!(c.flip_mean < 1e-3, "{c:?}");
        assert!(c.gains.iter().all(|g| (g - 1.0).abs() < 1e-3), "{:?}", c.gains);
        let darker = image::RgbaImage::from_fn(160, 120, |x, y| {
            let p = render.get_pixel(x, y);
            let half = |v: u8| linear_to_srgb8(0.5 * srgb_to_linear(v as f32 / 255.0));
            image::Rgba([half(p[0]), half(p[1]), half(p[2]), 255])
        });
        let c = compare(&darker, &mask, &render, a).unwrap();
        assert!(c.gains.iter().all(|g| (g - 2.0).abs() < 0.05), "a render lit half as bright is scaled back: {:?}", c.gains);
        assert!(c.flip_mean < 0.02, "{}", c.flip_mean);
    }
}
