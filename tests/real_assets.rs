//! Hybrid and full RT read every material input the same way: the rasterized G-buffer (layer
//! `deferred`) against the primary-ray one (layer `primary`), channel by channel, on the two
//! real assets (DamagedHelmet: five texture slots; the pine: BLEND leaf cards, double-sided)
//! and on a procedural metallic-roughness scene (data textures, normal maps, occlusion,
//! emission, a large ground plane, mirrored and double-sided instances) whose channels are also
//! checked against their closed forms (glTF conventions: metallic in blue, roughness in green,
//! data textures linear, normal map +Y towards -v, occlusion mixed by its strength).
//!
//! Pixels compared: both G-buffers cover the pixel and its 3x3 neighbours, with no jump of
//! position over 10% of the depth between neighbours (silhouettes and alpha edges excluded).
//! The mip level is the one thing the two producers choose differently (derivatives against
//! ray cones), so textured channels are compared by the share of pixels past a tolerance.

mod common;

use common::{gpu, open};

use common::material_scene::{metallic_roughness_scene, EMISSIVE_TEXEL, MR_TEXEL, OCCLUSION_RED};
use common::modes::render_without_effects;
use glam::Vec3;
use raygraph::backend::Backend;
use raygraph::runtime::Gpu;
use raygraph::scene::{Camera, Scene};

const CHANNELS: [&str; 6] = ["position", "normal", "geo_normal", "albedo", "material", "emissive"];

/// The G-buffer channels of one mode, row-major.
struct GBuffer {
    size: (u32, u32),
    channels: Vec<Vec<[f32; 4]>>,
}

impl GBuffer {
    fn at(&self, channel: usize, x: u32, y: u32) -> [f32; 4] {
        self.channels[channel][(y * self.size.0 + x) as usize]
    }
}

/// The G-buffer `graph` (hybrid or full RT, effects switched off) writes for `scene`.
fn gbuffer(gpu: &Gpu, graph: &str, backend: Backend, scene: &Scene, size: (u32, u32)) -> GBuffer {
    let exec = render_without_effects(gpu, graph, backend, scene, size);
    let channels = CHANNELS
        .iter()
        .map(|c| {
            let r = exec.plan().resource_by_name(&format!("gbuffer.{c}")).unwrap_or_else(|| panic!("{graph}: no gbuffer.{c}"));
            exec.read_texture_f32(gpu, r).unwrap().2
        })
        .collect();
    GBuffer { size, channels }
}

fn v3(t: [f32; 4]) -> Vec3 {
    Vec3::new(t[0], t[1], t[2])
}

/// Pixels both G-buffers cover with their 3x3 neighbourhood, without a position jump of more
/// than 10% of the depth: away from silhouettes and alpha edges.
fn interior(a: &GBuffer, b: &GBuffer, eye: Vec3) -> Vec<(u32, u32)> {
    let (w, h) = a.size;
    let mut out = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let ok = [a, b].iter().all(|g| {
                let p = g.at(0, x, y);
                let depth = v3(p).distance(eye);
                p[3] != 0.0
                    && (-1..=1i32).all(|dy| {
                        (-1..=1i32).all(|dx| {
                            let q = g.at(0, (x as i32 + dx) as u32, (y as i32 + dy) as u32);
                            q[3] != 0.0 && v3(q).distance(v3(p)) < 0.1 * depth
                        })
                    })
            });
            if ok {
                out.push((x, y));
            }
        }
    }
    out
}

/// Per-pixel differences of one quantity over the interior pixels.
struct Diffs {
    name: &'static str,
    values: Vec<f32>,
}

impl Diffs {
    fn mean(&self) -> f32 {
        self.values.iter().sum::<f32>() / self.values.len().max(1) as f32
    }
    fn quantile(&self, q: f64) -> f32 {
        let mut v = self.values.clone();
        v.sort_by(f32::total_cmp);
        v.get(((v.len() as f64 - 1.0) * q).round() as usize).copied().unwrap_or(0.0)
    }
    fn share_over(&self, tolerance: f32) -> f64 {
        self.values.iter().filter(|v| **v > tolerance).count() as f64 / self.values.len().max(1) as f64
    }
}

/// Every channel's per-pixel difference between the two G-buffers: position relative to the
/// depth, normals as angles in degrees, albedo (linear, 0..1), metallic, roughness, emitted
/// radiance (largest component) and occlusion as absolute differences.
fn channel_diffs(a: &GBuffer, b: &GBuffer, eye: Vec3, pixels: &[(u32, u32)]) -> Vec<Diffs> {
    let angle = |n: Vec3, m: Vec3| n.normalize().dot(m.normalize()).clamp(-1.0, 1.0).acos().to_degrees();
    let abs = |c: usize, k: usize| move |x: u32, y: u32| (a.at(c, x, y)[k] - b.at(c, x, y)[k]).abs();
    type Metric<'a> = Box<dyn Fn(u32, u32) -> f32 + 'a>;
    let metrics: Vec<(&'static str, Metric)> = vec![
        ("position / depth", Box::new(|x, y| v3(a.at(0, x, y)).distance(v3(b.at(0, x, y))) / v3(a.at(0, x, y)).distance(eye))),
        ("normal angle (deg)", Box::new(|x, y| angle(v3(a.at(1, x, y)), v3(b.at(1, x, y))))),
        ("geo_normal angle (deg)", Box::new(|x, y| angle(v3(a.at(2, x, y)), v3(b.at(2, x, y))))),
        ("albedo", Box::new(|x, y| (0..3).map(|k| abs(3, k)(x, y)).fold(0.0, f32::max))),
        ("metallic", Box::new(abs(4, 0))),
        ("roughness", Box::new(abs(4, 1))),
        ("emissive", Box::new(|x, y| (0..3).map(|k| abs(5, k)(x, y)).fold(0.0, f32::max))),
        ("occlusion", Box::new(abs(5, 3))),
    ];
    metrics.into_iter().map(|(name, f)| Diffs { name, values: pixels.iter().map(|&(x, y)| f(x, y)).collect() }).collect()
}

/// A tolerance per channel and the share of interior pixels allowed past it.
struct Tolerance {
    name: &'static str,
    tolerance: f32,
    share: f64,
}

/// Renders both G-buffers, prints every channel's statistics and checks them against `limits`.
fn check_agreement(gpu: &Gpu, what: &str, scene: &Scene, size: (u32, u32), backend: Backend, min_pixels: usize, limits: &[Tolerance]) -> (GBuffer, GBuffer) {
    let raster = gbuffer(gpu, "graph/hybrid.ron", backend, scene, size);
    let traced = gbuffer(gpu, "graph/full_rt.ron", backend, scene, size);
    let eye = scene.camera().position;
    let pixels = interior(&raster, &traced, eye);
    println!("{what} ({backend:?}, {}x{}): {} interior pixels", size.0, size.1, pixels.len());
    assert!(pixels.len() >= min_pixels, "{what}: only {} interior pixels", pixels.len());
    let diffs = channel_diffs(&raster, &traced, eye, &pixels);
    let mut failures = Vec::new();
    for d in &diffs {
        let limit = limits.iter().find(|l| l.name == d.name).unwrap_or_else(|| panic!("no tolerance for {}", d.name));
        let share = d.share_over(limit.tolerance);
        println!(
            "  {:<24} mean {:.2e}  p99 {:.2e}  max {:.2e}  over {:.1e}: {:.3}% (allowed {:.3}%)",
            d.name,
            d.mean(),
            d.quantile(0.99),
            d.quantile(1.0),
            limit.tolerance,
            100.0 * share,
            100.0 * limit.share
        );
        if share > limit.share {
            failures.push(format!("{}: {:.3}% of pixels past {} (allowed {:.3}%)", d.name, 100.0 * share, limit.tolerance, 100.0 * limit.share));
        }
    }
    assert!(failures.is_empty(), "{what}: hybrid and full-RT G-buffers differ:\n{}", failures.join("\n"));
    (raster, traced)
}

/// Tolerances on the real assets. Geometry is the same triangles: positions and face normals
/// agree (the interpolation differs by rounding) except at pixel centres within rounding of an
/// edge where two triangles meet at a crease or two surfaces cross (the rasterizer's top-left
/// rule and depth test against the ray's watertight test pick different triangles: 3 of 1526
/// helmet pixels at 96x96, face normals up to 84 degrees apart; 1 of 740 pine pixels at
/// 128x128), so `crossing_share` of the pixels may differ there. Textured channels: the
/// rasterizer's derivative-chosen mip level and the ray cone's differ by a fraction of a
/// level, which changes filtered texels where the texture has detail at that scale (at most
/// 0.3% of the pixels past the tolerance, measured); the allowed share leaves room for other
/// views of the same assets.
/// Measured on lavapipe (Mesa 25.0.7), 2026-11-29, share of pixels over each tolerance: the
/// helmet 0.308% (geometric normal), 0.154% (shading normal, albedo, metallic, occlusion: 2 of
/// 1,300 pixels), the pine 0 everywhere; both shares are 0.5%, within 3x of the largest.
fn real_asset_tolerances(crossing_share: f64, detail_share: f64) -> Vec<Tolerance> {
    vec![
        Tolerance { name: "position / depth", tolerance: 1e-3, share: crossing_share },
        Tolerance { name: "geo_normal angle (deg)", tolerance: 1.0, share: crossing_share },
        Tolerance { name: "normal angle (deg)", tolerance: 10.0, share: detail_share },
        Tolerance { name: "albedo", tolerance: 0.1, share: detail_share },
        Tolerance { name: "metallic", tolerance: 0.1, share: detail_share },
        Tolerance { name: "roughness", tolerance: 0.1, share: detail_share },
        Tolerance { name: "emissive", tolerance: 0.1, share: detail_share },
        Tolerance { name: "occlusion", tolerance: 0.1, share: detail_share },
    ]
}

#[test]
fn damaged_helmet_gbuffers_agree_in_hybrid_and_full_rt() {
    let gpu = gpu();
    let scene = open("assets/gltf/DamagedHelmet/DamagedHelmet.glb");
    check_agreement(&gpu, "DamagedHelmet", &scene, (96, 96), Backend::Compute, 1000, &real_asset_tolerances(0.005, 0.005));
}

#[test]
fn pine_gbuffers_agree_in_hybrid_and_full_rt() {
    let gpu = gpu();
    // The leaf cards are BLEND, which neither G-buffer holds (the rt_blend layer composites
    // them: tests/blend.rs); cut out at alpha 0.5 (MASK) here, both G-buffer producers' alpha
    // test on the atlas is compared on a real asset.
    let mut scene = open("assets/gltf/smallpine/scene.gltf");
    for m in scene.materials_mut().iter_mut().filter(|m| m.alpha_mode == raygraph::scene::AlphaMode::Blend) {
        m.alpha_mode = raygraph::scene::AlphaMode::Mask(0.5);
    }
    check_agreement(&gpu, "smallpine", &scene, (128, 128), Backend::Compute, 500, &real_asset_tolerances(0.005, 0.005));
}

/// The pixel the camera projects `p` to.
fn pixel_of(camera: &Camera, size: (u32, u32), p: Vec3) -> (u32, u32) {
    let clip = camera.view_proj(size.0 as f32 / size.1 as f32) * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (((ndc.x * 0.5 + 0.5) * size.0 as f32) as u32, ((0.5 - ndc.y * 0.5) * size.1 as f32) as u32)
}

/// Both producers, on every back-end lavapipe has and with both texture paths (the binding
/// array, and the 256x256 sRGB texture array of `RAYGRAPH_NO_BINDLESS`, where data textures are
/// re-encoded), agree on the procedural scene; and both give the closed-form channels on its
/// constant tiles.
#[test]
fn metallic_roughness_gbuffers_agree_and_follow_gltf_conventions() {
    let mut gpu = gpu();
    let bindless = gpu.texture_binding_arrays();
    let (scene, probes) = metallic_roughness_scene();
    let size = (128, 96);
    // Smooth textures: the mip-level choice moves filtered values little. Normals: the normal
    // map's tilt changes by under a degree between neighbouring mip levels of this map.
    let limits = vec![
        Tolerance { name: "position / depth", tolerance: 1e-3, share: 0.0 },
        Tolerance { name: "geo_normal angle (deg)", tolerance: 0.5, share: 0.0 },
        Tolerance { name: "normal angle (deg)", tolerance: 2.0, share: 0.01 },
        Tolerance { name: "albedo", tolerance: 0.03, share: 0.01 },
        // 1.08% measured (1.00% on the texture array): the far ground, where the level choice
        // matters most.
        Tolerance { name: "metallic", tolerance: 0.03, share: 0.02 },
        Tolerance { name: "roughness", tolerance: 0.03, share: 0.01 },
        Tolerance { name: "emissive", tolerance: 0.01, share: 0.0 },
        Tolerance { name: "occlusion", tolerance: 0.03, share: 0.01 },
    ];
    for (backend, arrays) in gpu.backends().to_vec().into_iter().flat_map(|b| [(b, bindless), (b, false)]) {
        gpu.set_texture_binding_arrays(arrays);
        let what = format!("metallic-roughness scene, {}", if arrays { "binding array" } else { "texture array" });
        let (raster, traced) = check_agreement(&gpu, &what, &scene, size, backend, 4000, &limits);
        for (name, centre) in &probes {
            let (x, y) = pixel_of(scene.camera(), size, *centre);
            for (mode, g) in [("hybrid", &raster), ("full RT", &traced)] {
                let (normal, material, emissive) = (v3(g.at(1, x, y)).normalize(), g.at(4, x, y), g.at(5, x, y));
                let tilt = |axis: Vec3, scale: f32| {
                    let (s, c) = (30f32.to_radians().sin() * scale, 30f32.to_radians().cos());
                    (axis * s + Vec3::Y * c).normalize()
                };
                let check = |ok: bool, problem: String| assert!(ok, "{what}, {mode} ({backend:?}), {name} tile at pixel ({x}, {y}): {problem}");
                match *name {
                    "mr" => {
                        // metallic = factor x blue, roughness = factor x green, read linearly.
                        check((material[0] - 0.8 * MR_TEXEL[2] as f32 / 255.0).abs() < 0.01, format!("metallic {}", material[0]));
                        check((material[1] - 0.9 * MR_TEXEL[1] as f32 / 255.0).abs() < 0.01, format!("roughness {}", material[1]));
                        // occlusion = 1 + strength (red - 1)
                        check((emissive[3] - (1.0 + 0.5 * (OCCLUSION_RED as f32 / 255.0 - 1.0))).abs() < 0.01, format!("occlusion {}", emissive[3]));
                    }
                    "emissive" => {
                        let want = [2.0f32, 1.0, 0.5];
                        for k in 0..3 {
                            let w = want[k] * raygraph::util::srgb_to_linear(EMISSIVE_TEXEL[k]);
                            check((emissive[k] - w).abs() < 0.01 * w.max(0.1), format!("emissive {:?}", emissive));
                        }
                        check(emissive[3] == 1.0, format!("occlusion without a texture {}", emissive[3]));
                    }
                    // The plane's u runs along +x, its v along +z: the texture's +x tilts the
                    // normal towards +x, its +y towards -z (decreasing v), by normal_scale.
                    "normal +u" => check(normal.angle_between(tilt(Vec3::X, 1.0)).to_degrees() < 1.0, format!("normal {normal}")),
                    "normal +y" => check(normal.angle_between(tilt(-Vec3::Z, 0.5)).to_degrees() < 1.0, format!("normal {normal}")),
                    _ => unreachable!(),
                }
            }
        }
    }
}
