//! The scene's lights (`scene_lights`, `shaders/common/lighting.wgsl`) against closed forms on
//! small procedural scenes, in the three modes and on every back-end: a plane under a point
//! light at height h (irradiance I cos^3(theta) / h^2), its range window, a spot light's cone
//! (full inside the inner angle, 0 outside the outer), a directional light (I cos(theta)), two
//! lights adding up, each light's own shadow (ray-traced for every light; shadow maps for
//! directional and spot lights in raster, cube maps for point lights), a scene without
//! lights of its own lit as before, a glTF file's own lights, emission with every light off, and
//! the occlusion texture scaling the ambient term.
//!
//! The expected radiance is the shading model of `lighting.wgsl` evaluated on the CPU: Lambert +
//! GGX per unit irradiance times the closed-form irradiance, plus (raster) the sky's Fresnel
//! reflection. The ambient term is 0 in these scenes.

mod common;

use common::{channel, gpu};

use glam::{Mat4, Quat, Vec3};
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::{plane, sphere};
use raygraph::scene::{Camera, Light, LightKind, Material, Mesh, PunctualLight, Scene};

const SIZE: (u32, u32) = (48, 40);
const ALBEDO: f32 = 0.7;
const ROUGHNESS: f32 = 0.8;

fn grey() -> Material {
    Material { roughness: ROUGHNESS, ..Material::diffuse("grey", [ALBEDO, ALBEDO, ALBEDO, 1.0], None) }
}

fn camera() -> Camera {
    Camera::look(Vec3::new(0.0, 5.0, 4.0), Vec3::new(0.0, 0.0, 0.3), 60.0, 0.05, 100.0)
}

/// A floor (y = 0, 16 units wide) and optional extra parts, lit by `lights`, no ambient light.
fn scene(lights: Vec<PunctualLight>, extra: Vec<(Mesh, Material, Mat4)>) -> Scene {
    let mut s = Scene::new("lights", camera());
    s.presets_mut().push(("test".into(), camera()));
    *s.light_mut() = Light { ambient: 0.0, ..Light::default() };
    *s.lights_mut() = lights;
    common::add_parts(&mut s, std::iter::once((plane("floor", 16.0, 1.0), grey(), Mat4::IDENTITY)).chain(extra));
    s
}

fn light(kind: LightKind, position: Vec3, direction: Vec3, intensity: f32) -> PunctualLight {
    PunctualLight { name: "test".into(), kind, position, direction: direction.normalize(), color: Vec3::ONE, intensity }
}

fn point(position: Vec3, intensity: f32, range: Option<f32>) -> PunctualLight {
    light(LightKind::Point { range }, position, Vec3::NEG_Y, intensity)
}

fn spot(position: Vec3, target: Vec3, intensity: f32, inner: f32, outer: f32) -> PunctualLight {
    light(LightKind::Spot { range: None, inner_cone: inner.to_radians(), outer_cone: outer.to_radians() }, position, target - position, intensity)
}

fn directional(direction: Vec3, intensity: f32) -> PunctualLight {
    light(LightKind::Directional, Vec3::ZERO, direction, intensity)
}

// ---- the CPU mirror of common/lighting.wgsl ----

fn sky(d: Vec3) -> Vec3 {
    Vec3::new(0.35, 0.3, 0.25).lerp(Vec3::new(0.6, 0.75, 1.0), 0.5 + 0.5 * d.y)
}

fn fresnel(cos: f32, f0: f32) -> f32 {
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// Radiance towards v per unit irradiance arriving from l (dielectric, ALBEDO, ROUGHNESS).
fn brdf(n: Vec3, v: Vec3, l: Vec3) -> f32 {
    let n_l = n.dot(l);
    if n_l <= 0.0 {
        return 0.0;
    }
    let n_v = n.dot(v).max(1e-4);
    let h = (l + v).normalize();
    let n_h = n.dot(h).max(0.0);
    let a2 = (ROUGHNESS * ROUGHNESS).powi(2);
    let d = a2 / (std::f32::consts::PI * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
    let k = (ROUGHNESS + 1.0).powi(2) / 8.0;
    let g = (n_l / (n_l * (1.0 - k) + k)) * (n_v / (n_v * (1.0 - k) + k));
    let f = fresnel(h.dot(v).max(0.0), 0.04);
    (d * g * f / (4.0 * n_l * n_v) + (1.0 - f) * ALBEDO / std::f32::consts::PI) * std::f32::consts::PI
}

/// Closed-form irradiance on the floor (normal +y) at p from `light`, with the direction
/// towards it; also where the floor faces away.
fn irradiance(light: &PunctualLight, p: Vec3) -> (f32, Vec3) {
    let smoothstep_window = |d: f32, range: Option<f32>| range.map_or(1.0, |r| (1.0 - (d / r).powi(4)).clamp(0.0, 1.0).powi(2));
    match light.kind {
        LightKind::Directional => (light.intensity * (-light.direction.y).max(0.0), -light.direction),
        LightKind::Point { range } => {
            // I cos^3(theta) / h^2 for a light at height h; cos(theta) = h / d.
            let (h, d) = (light.position.y - p.y, (light.position - p).length());
            let cos = h / d;
            (light.intensity * cos.max(0.0).powi(3) / (h * h) * smoothstep_window(d, range), (light.position - p) / d)
        }
        LightKind::Spot { range, inner_cone, outer_cone } => {
            let (h, d) = (light.position.y - p.y, (light.position - p).length());
            let to = (light.position - p) / d;
            let cone = ((light.direction.dot(-to) - outer_cone.cos()) / (inner_cone.cos() - outer_cone.cos()).max(0.001)).clamp(0.0, 1.0);
            (light.intensity * (h / d).max(0.0).powi(3) / (h * h) * smoothstep_window(d, range) * cone * cone, to)
        }
    }
}

/// Direct radiance at floor point p seen from the camera, each light times its visibility.
fn direct(lights: &[PunctualLight], visible: &[bool], p: Vec3) -> f32 {
    let v = (camera().position - p).normalize();
    lights
        .iter()
        .zip(visible)
        .filter(|(_, vis)| **vis)
        .map(|(l, _)| {
            let (e, dir) = irradiance(l, p);
            e * brdf(Vec3::Y, v, dir)
        })
        .sum()
}

/// The sky's Fresnel-weighted reflection at floor point p (the raster mode adds it; the resolve
/// too, where no reflection ray was traced).
fn sky_reflection(p: Vec3) -> Vec3 {
    let v = (camera().position - p).normalize();
    let r = Vec3::new(-v.x, v.y, -v.z);
    sky(r) * fresnel(v.y, 0.04)
}

/// World points of the floor seen through each pixel's centre (None: the ray misses it).
fn floor_points() -> Vec<Option<Vec3>> {
    let c = camera();
    c.ray_dirs(SIZE, 1)
        .into_iter()
        .map(|d| {
            let t = -c.position.y / d.y;
            let p = c.position + d * t;
            (t > 0.0 && p.x.abs() < 7.9 && p.z.abs() < 7.9).then_some(p)
        })
        .collect()
}

// ---- rendering ----

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Raster,
    Hybrid,
    FullRt,
}

/// The mode's graph in a temporary project, AO and reflections switched off.
fn graph(mode: Mode) -> (common::TempProject, std::path::PathBuf) {
    let file = match mode {
        Mode::Raster => "graph/raster.ron",
        Mode::Hybrid => "graph/hybrid.ron",
        Mode::FullRt => "graph/full_rt.ron",
    };
    let text = std::fs::read_to_string(common::repo().join(file))
        .unwrap()
        .replace("\"ao\": Layer(", "\"ao\": Layer(enabled: false, ")
        .replace("\"reflection\": Layer(", "\"reflection\": Layer(enabled: false, ");
    let p = common::TempProject::with_repo_files();
    let path = p.write("graph/test.ron", &text);
    (p, path)
}

/// Every (mode, back-end) pair: raster once, the ray-traced modes on every back-end.
fn configurations(gpu: &Gpu) -> Vec<(Mode, Backend)> {
    let mut out = vec![(Mode::Raster, Backend::Compute)];
    for mode in [Mode::Hybrid, Mode::FullRt] {
        out.extend(Backend::ALL.into_iter().filter(|b| gpu.backends().contains(b)).map(|b| (mode, b)));
    }
    out
}

fn executor(gpu: &Gpu, graph: &std::path::Path, backend: Backend, scene: &Scene) -> Executor {
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    let plan = compile_with(graph, &Project::beside_graph(graph), SIZE, &options).unwrap();
    Executor::new(gpu, plan, scene).unwrap()
}

/// What a mode computed at each pixel: the direct light alone (ray-traced modes: rt_shadow's
/// `direct`, with rt_shadow's per-light mask) or, in raster, the forward colour less the sky's
/// reflection.
struct Frame {
    direct: Vec<Vec3>,
    mask: Option<Vec<[f32; 4]>>,
}

fn render(gpu: &Gpu, exec: &mut Executor, mode: Mode, scene: &Scene) -> Frame {
    exec.render(gpu, scene.camera(), scene).unwrap();
    let points = floor_points();
    if mode == Mode::Raster {
        let color = channel(gpu, exec, "forward.color");
        let direct = color.iter().zip(&points).map(|(c, p)| Vec3::new(c[0], c[1], c[2]) - p.map_or(Vec3::ZERO, sky_reflection)).collect();
        Frame { direct, mask: None }
    } else {
        let direct = channel(gpu, exec, "shadow.direct").iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        Frame { direct, mask: Some(channel(gpu, exec, "shadow.shadow")) }
    }
}

/// Relative tolerance of a radiance: f16 storage (1e-3), the 8-bit albedo of the G-buffer
/// (0.7 stored as 179/255: 0.3%), and the position of a pixel's centre against the
/// rasterizer's interpolation (measured below 0.5% on these planes); plus an absolute 2e-3.
fn close(got: f32, want: f32) -> bool {
    (got - want).abs() <= 0.01 * want.abs() + 2e-3
}

/// Checks every floor pixel's direct light against the closed form, with each light's
/// visibility there (None: a pixel too near a shadow's outline or not showing the floor, left
/// out); returns the largest error and the number of pixels checked.
fn check_direct(frame: &Frame, lights: &[PunctualLight], visible: impl Fn(Vec3) -> Option<Vec<bool>>, what: &str) -> (f32, usize) {
    let mut worst = 0.0f32;
    let mut checked = 0;
    for (i, p) in floor_points().into_iter().enumerate() {
        let Some((p, vis)) = p.and_then(|p| Some((p, visible(p)?))) else { continue };
        let want = direct(lights, &vis, p);
        let got = frame.direct[i];
        for c in 0..3 {
            assert!(close(got[c], want), "{what}: pixel {i} at {p:?} (visible {vis:?}): {got:?} against the closed form {want}");
        }
        worst = worst.max((got.x - want).abs());
        checked += 1;
    }
    (worst, checked)
}

/// Renders `s` and checks the final HDR colour of every floor pixel (raster: the forward pass's,
/// else the resolve's) against `want`.
fn check_floor_color(gpu: &Gpu, mode: Mode, backend: Backend, s: &Scene, want: impl Fn(Vec3) -> Vec3, what: &str) {
    let (_p, graph_file) = graph(mode);
    let mut exec = executor(gpu, &graph_file, backend, s);
    exec.render(gpu, s.camera(), s).unwrap();
    let color = channel(gpu, &exec, if mode == Mode::Raster { "forward.color" } else { "resolve.hdr" });
    let mut checked = 0;
    for (i, p) in floor_points().into_iter().enumerate() {
        let Some(p) = p else { continue };
        let want = want(p);
        for c in 0..3 {
            assert!(close(color[i][c], want[c]), "{mode:?}/{backend}: {what}: pixel {i}: {:?} against {want:?}", color[i]);
        }
        checked += 1;
    }
    println!("{mode:?}/{backend}: {what}: {checked} floor pixels match");
    assert!(checked > 900, "{mode:?}/{backend}: the floor fills the view");
}

/// The unshadowed closed forms: point light (with and without range), spot cone, directional,
/// and two lights adding up, in every mode and on every back-end.
#[test]
fn a_plane_under_each_kind_of_light_matches_the_closed_forms() {
    let gpu = gpu();
    let h = 2.0;
    let cases: Vec<(&str, Vec<PunctualLight>)> = vec![
        ("point at height 2", vec![point(Vec3::new(0.0, h, 0.0), 8.0, None)]),
        ("point with range 3", vec![point(Vec3::new(0.0, h, 0.0), 8.0, Some(3.0))]),
        ("spot, cones 15 and 25 degrees", vec![spot(Vec3::new(0.5, 3.0, 0.5), Vec3::new(0.5, 0.0, 0.5), 30.0, 15.0, 25.0)]),
        ("directional", vec![directional(Vec3::new(0.3, -1.0, 0.2), 2.0)]),
        ("point and directional", vec![point(Vec3::new(0.0, h, 0.0), 8.0, None), directional(Vec3::new(0.3, -1.0, 0.2), 2.0)]),
    ];
    for (mode, backend) in configurations(&gpu) {
        let (_p, graph) = graph(mode);
        let mut exec = executor(&gpu, &graph, backend, &scene(cases[0].1.clone(), vec![]));
        let mut frames = Vec::new();
        for (name, lights) in &cases {
            let frame = render(&gpu, &mut exec, mode, &scene(lights.clone(), vec![]));
            let (worst, checked) = check_direct(&frame, lights, |_| Some(vec![true; lights.len()]), &format!("{mode:?}/{backend}/{name}"));
            assert!(checked > (SIZE.0 * SIZE.1) as usize / 2, "the floor fills the view ({checked} pixels)");
            println!("{mode:?} {backend:11} {name:30}: largest error {worst:.2e}");
            frames.push(frame);
        }
        let points = floor_points();
        let on_floor = |i: &usize| points[*i].is_some();
        // The range window ends the light: pixels beyond 3 units get none, nearer ones some.
        let beyond = (0..points.len()).filter(on_floor).filter(|i| (Vec3::new(0.0, h, 0.0) - points[*i].unwrap()).length() > 3.0).collect::<Vec<_>>();
        assert!(beyond.len() > 100, "the view reaches beyond the range");
        assert!(beyond.iter().all(|i| frames[1].direct[*i].max_element() <= 2e-3), "{mode:?}/{backend}: light beyond the range");
        // The spot: full intensity inside the inner cone, none outside the outer one.
        let angle = |i: usize| (points[i].unwrap() - Vec3::new(0.5, 3.0, 0.5)).normalize().dot(Vec3::NEG_Y).acos().to_degrees();
        let (inside, outside): (Vec<usize>, Vec<usize>) =
            (0..points.len()).filter(on_floor).filter(|i| angle(*i) < 15.0 || angle(*i) > 25.0).partition(|i| angle(*i) < 15.0);
        assert!(inside.len() > 10 && outside.len() > 100, "the view holds both sides of the cone");
        assert!(outside.iter().all(|i| frames[2].direct[*i].max_element() <= 2e-3), "{mode:?}/{backend}: light outside the spot's outer cone");
        assert!(inside.iter().all(|i| frames[2].direct[*i].x > 0.1), "{mode:?}/{backend}: no light inside the spot's inner cone");
        // Two lights add up.
        for i in (0..points.len()).filter(on_floor) {
            let sum = frames[0].direct[i] + frames[3].direct[i];
            assert!(close(frames[4].direct[i].x, sum.x), "{mode:?}/{backend}: two lights at pixel {i}: {:?} against {sum:?}", frames[4].direct[i]);
        }
    }
}

/// A sphere of radius `R` at `C` over the floor, and three lights: a directional, a spot and a
/// point light, whose shadows fall apart from each other.
const C: Vec3 = Vec3::new(0.0, 1.2, 0.0);
const R: f32 = 0.7;

fn occluded_scene() -> Scene {
    let lights = vec![
        directional(Vec3::new(0.6, -1.0, 0.1), 1.5),
        spot(Vec3::new(-2.5, 4.0, 0.5), Vec3::new(0.0, 0.0, 0.0), 30.0, 50.0, 60.0),
        point(Vec3::new(0.3, 3.5, -1.5), 12.0, None),
    ];
    let ball = Mat4::from_scale_rotation_translation(Vec3::splat(R), Quat::IDENTITY, C);
    scene(lights, vec![(sphere("ball", 32, 64), grey(), ball)])
}

/// Distance from the sphere's centre to the segment from p towards `light` (to its position, or
/// without end for a directional light).
fn miss_distance(light: &PunctualLight, p: Vec3) -> f32 {
    let (dir, length) = match light.kind {
        LightKind::Directional => (-light.direction, f32::INFINITY),
        _ => ((light.position - p).normalize(), (light.position - p).length()),
    };
    let along = (C - p).dot(dir).clamp(0.0, length);
    (C - p - dir * along).length()
}

/// Every light casts its own shadow: per light, a floor point is shadowed exactly when the
/// segment to the light passes through the sphere (outside a margin around the outline: 3% of
/// R for the 32x64 tessellation plus one pixel's footprint at ~6 units). Ray-traced modes on
/// every back-end: rt_shadow's mask of each light and the direct light with each light's
/// visibility. Raster: the directional and the spot light shadowed by their shadow maps, the
/// point light by its cube map.
#[test]
fn every_light_casts_its_own_shadow() {
    let gpu = gpu();
    let s = occluded_scene();
    let margin = 0.03 * R + 2.0 * 6.0 * 30f32.to_radians().tan() / SIZE.1 as f32;
    let cam = camera();
    // Pixels whose camera ray passes near the sphere show it (or its outline), not the floor.
    let shows_floor = |p: Vec3| {
        let d = (p - cam.position).normalize();
        let along = (C - cam.position).dot(d).max(0.0);
        (C - cam.position - d * along).length() > R + margin
    };
    let classify = || {
        let lights = s.lights().to_vec();
        move |p: Vec3| -> Option<Vec<bool>> {
            if !shows_floor(p) {
                return None;
            }
            lights
                .iter()
                .map(|l| {
                    let d = miss_distance(l, p);
                    if d < R - margin {
                        Some(false)
                    } else if d > R + margin {
                        Some(true)
                    } else {
                        None
                    }
                })
                .collect()
        }
    };
    let points = floor_points();
    for (mode, backend) in configurations(&gpu) {
        let (_p, graph) = graph(mode);
        let mut exec = executor(&gpu, &graph, backend, &s);
        let frame = render(&gpu, &mut exec, mode, &s);
        let what = format!("{mode:?}/{backend}");
        let (worst, checked) = check_direct(&frame, s.lights(), classify(), &what);
        println!("{what}: direct light of {checked} floor pixels within {worst:.2e} of the closed form");
        assert!(checked > 800, "{what}: {checked} pixels checked");
        let Some(mask) = &frame.mask else { continue };
        for (l, light) in s.lights().iter().enumerate() {
            let (mut shadowed, mut lit) = (0, 0);
            for (i, p) in points.iter().enumerate() {
                let Some(p) = p.filter(|p| shows_floor(*p)) else { continue };
                let d = miss_distance(light, p);
                let reaches = irradiance(light, p).0 > 0.0;
                if d < R - margin {
                    shadowed += 1;
                    assert_eq!(mask[i][l], 0.0, "{what}: light {l} at pixel {i} ({p:?}) inside its shadow");
                } else if d > R + margin && reaches {
                    lit += 1;
                    assert_eq!(mask[i][l], 1.0, "{what}: light {l} at pixel {i} ({p:?}) outside its shadow");
                }
            }
            println!("{what}: light {l}: {shadowed} pixels in its shadow, {lit} lit");
            assert!(shadowed > 15 && lit > 300, "{what}: light {l}'s shadow and light are in view");
        }
    }
}

/// A scene without lights of its own is lit by the default sun (and the optional point light)
/// exactly as when those lights are given as the file's own: the same image in every mode.
#[test]
fn a_scene_without_lights_is_lit_by_the_default_sun() {
    let gpu = gpu();
    let (mut s, _) = raygraph::scene::open("default", &raygraph::scene::LoadOptions::default()).unwrap();
    s.set_point_light(Some(raygraph::scene::PointLight { position: Vec3::new(1.0, 2.5, 1.0), color: Vec3::new(1.0, 0.8, 0.6), intensity: 4.0 }));
    assert!(s.lights().is_empty());
    let mut explicit = s.clone();
    *explicit.lights_mut() = s.effective_lights();
    assert_eq!(explicit.lights().len(), 2);
    assert_eq!(explicit.lights()[0].kind, LightKind::Directional);
    for (mode, backend) in configurations(&gpu).into_iter().filter(|(_, b)| *b == Backend::Compute) {
        let (_p, graph) = graph(mode);
        let image = |scene: &Scene| {
            let mut exec = executor(&gpu, &graph, backend, scene);
            exec.render(&gpu, scene.camera(), scene).unwrap();
            exec.read_output(&gpu).unwrap()
        };
        let (default, given) = (image(&s), image(&explicit));
        assert!(default.pixels().any(|p| p.0 != default.get_pixel(0, 0).0), "{mode:?}: the image shows something");
        assert_eq!(default.as_raw(), given.as_raw(), "{mode:?}: the default lights differ from the same lights given");
    }
}

/// Emission with every light off (one directional light of intensity 0, no ambient light): the
/// floor's radiance is its emissive factor plus the sky's Fresnel reflection, in every mode and
/// on every back-end; and a mirror floor's reflection rays (hybrid, every back-end) return an
/// emissive wall's emission.
#[test]
fn emissive_surfaces_glow_with_every_light_off() {
    let gpu = gpu();
    let emissive = [2.0, 1.0, 0.5];
    let dark = vec![directional(Vec3::NEG_Y, 0.0)];
    let mut glowing = grey();
    glowing.emissive = emissive;
    let mut s = scene(dark.clone(), vec![]);
    s.materials_mut()[0] = glowing.clone();
    for (mode, backend) in configurations(&gpu) {
        check_floor_color(&gpu, mode, backend, &s, |p| Vec3::from(emissive) + sky_reflection(p), "emission");
    }

    // A mirror floor in front of an emissive wall standing in z = -3, facing +z.
    let mirror = Material { metallic: 1.0, roughness: 0.0, ..Material::diffuse("mirror", [1.0; 4], None) };
    let wall = Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0)) * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let mut s = scene(dark, vec![(plane("wall", 16.0, 1.0), glowing, wall)]);
    s.materials_mut()[0] = mirror;
    let text = std::fs::read_to_string(common::repo().join("graph/hybrid.ron")).unwrap().replace("\"ao\": Layer(", "\"ao\": Layer(enabled: false, ");
    let project = common::TempProject::with_repo_files();
    let graph_file = project.write("graph/test.ron", &text);
    let cam = camera();
    for backend in Backend::ALL.into_iter().filter(|b| gpu.backends().contains(b)) {
        let mut exec = executor(&gpu, &graph_file, backend, &s);
        exec.render(&gpu, s.camera(), &s).unwrap();
        let reflection = channel(&gpu, &exec, "reflection.reflection");
        let mut seen = 0;
        for (i, p) in floor_points().into_iter().enumerate() {
            // The mirror ray's point on the wall's plane, well inside the wall.
            let Some(p) = p.filter(|p| p.z > -2.9) else { continue };
            let v = (cam.position - p).normalize();
            let r = Vec3::new(-v.x, v.y, -v.z);
            let t = (-3.0 - p.z) / r.z;
            let q = p + r * t;
            if !(t > 0.0 && q.x.abs() < 7.5 && q.y > 0.1 && q.y < 7.5) {
                continue;
            }
            for c in 0..3 {
                assert!(close(reflection[i][c], emissive[c]), "{backend}: pixel {i}: reflection {:?} against the emission {emissive:?}", reflection[i]);
            }
            seen += 1;
        }
        println!("{backend}: {seen} mirror pixels reflect the emissive wall");
        assert!(seen > 100, "{backend}: the mirror shows the wall");
    }
}

/// A glTF file's own `KHR_lights_punctual` lights light the scene: a floor (two triangles, the
/// material of `grey()`) under a point light at (0, 2, 0) and a spot light at (0.5, 3, 0.5)
/// turned to shine straight down, in a GLB written here; the direct light in raster and hybrid
/// matches the closed forms of the lights as written into the file.
#[test]
fn a_gltf_files_punctual_lights_match_the_closed_forms() {
    use common::gltf_doc::{temp_dir, Doc};
    use serde_json::json;
    let gpu = gpu();
    let mut d = Doc::new();
    let p = d.positions(&[[-8.0, 0.0, -8.0], [-8.0, 0.0, 8.0], [8.0, 0.0, 8.0], [8.0, 0.0, -8.0]]);
    let n = d.floats(&[0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0], "VEC3", 4);
    let i = d.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let mesh = d.mesh(&[("POSITION", p), ("NORMAL", n)], Some(i), Some(0), None);
    d.material(json!({"pbrMetallicRoughness": {"baseColorFactor": [ALBEDO, ALBEDO, ALBEDO, 1.0], "metallicFactor": 0.0, "roughnessFactor": ROUGHNESS}}));
    d.node(json!({"mesh": mesh}), true);
    d.json["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    d.json["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "intensity": 8.0},
        {"type": "spot", "intensity": 30.0, "spot": {"innerConeAngle": 15f32.to_radians(), "outerConeAngle": 25f32.to_radians()}}
    ]}});
    let s = std::f32::consts::FRAC_1_SQRT_2;
    d.node(json!({"translation": [0.0, 2.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}), true);
    // -90 degrees about +x: the light's -z becomes -y.
    d.node(json!({"translation": [0.5, 3.0, 0.5], "rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 1}}}), true);
    let dir = temp_dir("lights");
    let path = d.write_glb(&dir, "lights");
    let (mut scene, _) = raygraph::scene::open(path.to_str().unwrap(), &raygraph::scene::LoadOptions::default()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(scene.lights().len(), 2, "the file's two lights");
    *scene.camera_mut() = camera();
    scene.light_mut().ambient = 0.0;
    let written = [point(Vec3::new(0.0, 2.0, 0.0), 8.0, None), spot(Vec3::new(0.5, 3.0, 0.5), Vec3::new(0.5, 0.0, 0.5), 30.0, 15.0, 25.0)];
    for (mode, backend) in [(Mode::Raster, Backend::Compute), (Mode::Hybrid, Backend::Compute)] {
        let (_p, graph) = graph(mode);
        let mut exec = executor(&gpu, &graph, backend, &scene);
        let frame = render(&gpu, &mut exec, mode, &scene);
        let (worst, checked) = check_direct(&frame, &written, |_| Some(vec![true; 2]), &format!("{mode:?}/{backend}/glTF"));
        println!("{mode:?} {backend}: the file's lights within {worst:.2e} of the closed form at {checked} pixels");
        assert!(checked > 900);
    }
}

/// The material's occlusion scales the ambient term in every mode: with every light off and
/// AO off, a floor's radiance is ambient x sky(up) x albedo x occlusion plus the sky's Fresnel
/// reflection, where occlusion = 1 + strength x (texel red - 1): 1 without a texture, 0.5 with a
/// black texture at strength 0.5.
#[test]
fn the_occlusion_texture_scales_the_ambient_term_in_every_mode() {
    let gpu = gpu();
    let ambient = 0.35;
    for (occlusion, with_texture) in [(1.0f32, false), (0.5, true)] {
        let mut s = scene(vec![directional(Vec3::NEG_Y, 0.0)], vec![]);
        s.light_mut().ambient = ambient;
        if with_texture {
            s.textures_mut().push(raygraph::scene::TextureImage { name: "black".into(), width: 1, height: 1, rgba: vec![0, 0, 0, 255].into() });
            s.materials_mut()[0].occlusion_texture = Some(0);
            s.materials_mut()[0].occlusion_strength = 0.5;
        }
        for (mode, backend) in configurations(&gpu).into_iter().filter(|(_, b)| *b == Backend::Compute) {
            let want = |p: Vec3| ambient * sky(Vec3::Y) * ALBEDO * occlusion + sky_reflection(p);
            check_floor_color(&gpu, mode, backend, &s, want, &format!("occlusion {occlusion}"));
        }
    }
}
