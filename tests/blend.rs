//! glTF BLEND surfaces against closed-form answers.
//!
//! A 40%-covering red panel (base colour alpha 0.4, BLEND, double-sided) 1 unit in front of a
//! blue wall, both unlit (KHR_materials_unlit: each shows its base colour, whatever the
//! lights), seen straight on:
//! - hybrid and full RT composite the panel over the wall: where the panel covers the pixel its
//!   HDR colour is 0.4 red + 0.6 blue, elsewhere blue, on every back-end; the G-buffer holds the
//!   wall behind the panel (primary rays and the raster G-buffer pass BLEND surfaces);
//! - raster blends it over the wall after the opaque surfaces (the translucent pass of both
//!   forward layers, the visibility-buffer one and the fragment-stage one): the same colours.
//!
//! A second, green 40% panel half a unit behind the red one: every mode composites red over
//! green over blue (0.4 red + 0.6 x (0.4 green + 0.6 blue)); the other order would give 0.24
//! red and 0.4 green.
//!
//! A sun straight above a lit floor, the same panel between them: the ray-traced shadow mask
//! under the panel is 1 - 0.4 (the light through it), 1 beside it, on every back-end; two
//! stacked panels let 0.6 x 0.6 through, ten 0.6^10 (every surface on the ray counts).
//!
//! The same panel with its 0.4 in its vertex colours' alpha (COLOR_0) instead: the same answers.
//!
//! A transmissive panel (KHR_materials_transmission 0.75, alpha mode OPAQUE, unlit base colour
//! (0.5, 1, 0.25)) in the same place covers 1 - 0.75 of the pixel and tints what it lets through
//! by its base colour: 0.25 x base + 0.75 x base x blue, in every mode; its shadow lets 0.75
//! through.
//!
//! The same red transmissive panel with transmission 1 and a transmission texture of 0.6 covers
//! 0.4 (1 - 0.6) in every mode: 0.4 red over the wall (the blue it lets through tinted away by
//! its red).
//!
//! A scene without BLEND materials runs its shadow rays as any-hit rays (SCENE_BLEND off).
//!
//! The G-buffer's primary rays pass both stacked panels within their one traversal
//! (TRACE_PASS_BLEND): one closest-hit ray a pixel on every back-end.

mod common;

use common::{channel, gpu, repo};
use glam::{Mat4, Vec3};
use raygraph::accel::cache::RayStats;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{builtin, AlphaMode, Camera, Instance, LightKind, Material, Mesh, PunctualLight, Scene, Vertex, VertexExtra};
use std::path::Path;

const SIZE: (u32, u32) = (64, 64);
const COVERAGE: f32 = 0.4;

/// A quad over [-h, h]² in the xy plane at height z, facing +z, uvs over [0, 1]².
fn quad(name: &str, h: f32, z: f32) -> Mesh {
    let v = |x: f32, y: f32| Vertex { position: [x, y, z], normal: [0.0, 0.0, 1.0], uv: [(x + h) / (2.0 * h), (h - y) / (2.0 * h)] };
    Mesh { name: name.into(), vertices: vec![v(-h, -h), v(h, -h), v(h, h), v(-h, h)], indices: vec![0, 1, 2, 0, 2, 3], tangents: None, extras: None }
}

fn panel_material(lit: bool) -> Material {
    Material { alpha_mode: AlphaMode::Blend, double_sided: true, unlit: !lit, ..Material::diffuse("panel", [1.0, 0.0, 0.0, COVERAGE], None) }
}

/// The transmissive panel: what it covers (1 - transmission) and its colour.
const TRANSMISSION: f32 = 0.75;
const GLASS: [f32; 3] = [0.5, 1.0, 0.25];

fn glass_material(lit: bool) -> Material {
    let mut m = Material { double_sided: true, unlit: !lit, ..Material::diffuse("glass", [GLASS[0], GLASS[1], GLASS[2], 1.0], None) };
    m.lobes.transmission = TRANSMISSION;
    m
}

/// The panel scene with the panel's 0.4 in its vertex colours' alpha (COLOR_0) instead of its
/// base colour's.
fn vertex_alpha_scene() -> Scene {
    let mut s = panel_scene();
    s.materials_mut()[1].base_color[3] = 1.0;
    let corners = s.meshes()[1].vertices.len();
    s.mesh_mut(1).extras = Some(vec![VertexExtra { color: [1.0, 1.0, 1.0, COVERAGE], ..Default::default() }; corners]);
    s
}

/// The panel scene with the transmissive panel instead of the BLEND one.
fn glass_scene() -> Scene {
    let mut s = panel_scene();
    s.materials_mut()[1] = glass_material(false);
    s
}

/// The panel scene with a red transmissive panel (transmission 1) whose transmission texture's
/// red is 153/255 = 0.6 everywhere: it covers 1 - 0.6 = 0.4 of the pixel (without the texture
/// it would cover nothing) and lets through what its red base colour lets through of the blue
/// wall: nothing.
fn transmission_texture_scene() -> Scene {
    let mut s = panel_scene();
    let mut m = Material { double_sided: true, unlit: true, ..Material::diffuse("textured glass", [1.0, 0.0, 0.0, 1.0], None) };
    m.lobes.transmission = 1.0;
    m.lobes.textures[raygraph::scene::LOBE_TRANSMISSION] = Some(0);
    *s.textures_mut() =
        vec![raygraph::scene::TextureImage { name: "transmission".into(), width: 2, height: 2, rgba: std::sync::Arc::new([153, 0, 0, 255].repeat(4)) }];
    s.materials_mut()[1] = m;
    s
}

/// The panel scene with a green 40% panel half a unit behind the red one, the same size.
fn stacked_scene() -> Scene {
    let mut s = panel_scene();
    s.push_mesh(quad("green panel", 1.0, 0.5));
    s.materials_mut().push(Material {
        alpha_mode: AlphaMode::Blend,
        double_sided: true,
        unlit: true,
        ..Material::diffuse("green", [0.0, 1.0, 0.0, COVERAGE], None)
    });
    s.instances_mut().push(Instance { mesh: 2, material: 2, transform: Mat4::IDENTITY });
    s
}

/// Every panel scene with the HDR colour composited where the panel covers a pixel.
fn composite_cases() -> Vec<(&'static str, Scene, Vec3)> {
    let glass = Vec3::from(GLASS);
    let over_wall = Vec3::new(COVERAGE, 0.0, 1.0 - COVERAGE);
    vec![
        ("blend", panel_scene(), over_wall),
        ("vertex alpha", vertex_alpha_scene(), over_wall),
        ("transmission", glass_scene(), (1.0 - TRANSMISSION) * glass + TRANSMISSION * glass * Vec3::Z),
        ("transmission texture", transmission_texture_scene(), Vec3::new(COVERAGE, 0.0, 0.0)),
        ("stacked", stacked_scene(), Vec3::new(COVERAGE, 0.0, 0.0) + (1.0 - COVERAGE) * Vec3::new(0.0, COVERAGE, 1.0 - COVERAGE)),
    ]
}

/// The largest error of `hdr` against `over` where the panel covers the pixel wholly, the
/// number of those pixels, and the largest error against the bare wall where it covers none.
fn panel_errors(hdr: &[[f32; 4]], over: Vec3) -> (f32, usize, f32) {
    let (mut worst_in, mut worst_out, mut n_in) = (0.0f32, 0.0f32, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let p = hdr[(y * SIZE.0 + x) as usize];
            let c = Vec3::new(p[0], p[1], p[2]);
            if inside_panel(x, y) {
                worst_in = worst_in.max((c - over).abs().max_element());
                n_in += 1;
            } else if outside_panel(x, y) {
                worst_out = worst_out.max((c - Vec3::Z).abs().max_element());
            }
        }
    }
    (worst_in, n_in, worst_out)
}

/// The panel over the wall, seen from +z: the panel covers the middle half of the image.
fn panel_scene() -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("blend panel");
    s.set_meshes(vec![quad("wall", 4.0, 0.0), quad("panel", 1.0, 1.0)]);
    *s.materials_mut() = vec![Material { unlit: true, ..Material::diffuse("wall", [0.0, 0.0, 1.0, 1.0], None) }, panel_material(false)];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 1, material: 1, transform: Mat4::IDENTITY }];
    s.textures_mut().clear();
    // 5 units from the panel, whose half-width 1 then spans half the image's height.
    *s.camera_mut() = Camera {
        position: Vec3::new(0.0, 0.0, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 2.0 * (2.0f32 / 5.0).atan(),
        near: 0.05,
        far: 100.0,
        orthographic: None,
        aspect_ratio: None,
    };
    s
}

fn render(gpu: &Gpu, graph: &str, backend: Backend, scene: &Scene) -> Executor {
    common::modes::render_graph(gpu, graph, backend, scene, SIZE)
}

/// One frame of `graph` on `backend`, and the rays each trace pass counted, by pass name.
fn render_counting_rays(gpu: &Gpu, graph: &Path, backend: Backend, scene: &Scene) -> (Executor, impl Fn(&str) -> RayStats) {
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    let plan = compile_with(graph, &Project::beside_graph(graph), SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    let frame = exec.render(gpu, scene.camera(), scene).unwrap();
    let names: Vec<String> = exec.plan().passes().iter().map(|p| p.name.clone()).collect();
    let rays_of =
        move |pass: &str| frame.pass_rays[names.iter().position(|n| n == pass).expect("the pass is in the plan")].expect("a trace pass counts its rays");
    (exec, rays_of)
}

/// Whether pixel (x, y) is wholly inside the panel's image (its middle half, a pixel's margin).
fn inside_panel(x: u32, y: u32) -> bool {
    let (lo, hi) = (SIZE.0 / 4 + 1, 3 * SIZE.0 / 4 - 1);
    (lo..hi).contains(&x) && (lo..hi).contains(&y)
}

/// Whether pixel (x, y) is wholly outside it.
fn outside_panel(x: u32, y: u32) -> bool {
    let (lo, hi) = (SIZE.0 / 4 - 1, 3 * SIZE.0 / 4 + 1);
    !(lo..hi).contains(&x) || !(lo..hi).contains(&y)
}

fn backends(gpu: &Gpu) -> Vec<Backend> {
    gpu.backends().to_vec()
}

#[test]
fn the_ray_traced_modes_composite_the_panel_over_the_wall_on_every_back_end() {
    let gpu = gpu();
    let cases = composite_cases();
    for (backend, (what, scene, over)) in backends(&gpu).into_iter().flat_map(|b| cases.iter().map(move |c| (b, c))) {
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let exec = render(&gpu, graph, backend, scene);
            let hdr = channel(&gpu, &exec, "blend.color");
            let position = channel(&gpu, &exec, "gbuffer.position");
            for (i, p) in position.iter().enumerate() {
                let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
                if inside_panel(x, y) {
                    // The G-buffer shows the wall (instance 0, w = 1) behind the panel.
                    assert_eq!(p[3], 1.0, "{graph} {backend:?}: the G-buffer at ({x}, {y}) holds the wall");
                    assert!(p[2].abs() < 1e-3, "{graph} {backend:?}: G-buffer depth at ({x}, {y}): z = {}", p[2]);
                }
            }
            let (worst_in, n_in, worst_out) = panel_errors(&hdr, *over);
            println!("{what}, {graph} {backend:?}: {n_in} pixels behind the panel, largest error {worst_in:.5}; beside it {worst_out:.5}");
            assert!(n_in > 600, "{graph}: the panel is in view");
            // 8-bit albedo of the G-buffer (wall) and the f16 output: 1/510 + 1e-3.
            assert!(worst_in < 3e-3, "{what}, {graph} {backend:?}: the panel over the wall, largest error {worst_in}");
            assert!(worst_out < 3e-3, "{graph} {backend:?}: the bare wall, largest error {worst_out}");
        }
    }
}

#[test]
fn primary_rays_pass_the_stacked_panels_in_one_traversal_on_every_back_end() {
    let gpu = gpu();
    let scene = stacked_scene();
    let path = repo().join("graph/full_rt.ron");
    let pixels = u64::from(SIZE.0 * SIZE.1);
    for backend in backends(&gpu) {
        let (exec, rays_of) = render_counting_rays(&gpu, &path, backend, &scene);
        let rays = rays_of("gbuffer/primary");
        let position = channel(&gpu, &exec, "gbuffer.position");
        let inside: Vec<&[f32; 4]> =
            position.iter().enumerate().filter(|(i, _)| inside_panel(*i as u32 % SIZE.0, *i as u32 / SIZE.0)).map(|(_, p)| p).collect();
        let on_wall = inside.iter().filter(|p| p[3] == 1.0 && p[2].abs() < 1e-3).count();
        println!(
            "{backend:?}: G-buffer pass {} closest-hit rays for {pixels} pixels; {on_wall} of {} pixels behind both panels on the wall",
            rays.closest,
            inside.len()
        );
        // TRACE_PASS_BLEND: the two panels are passed inside the ray's one traversal, not by a
        // new traversal past each.
        assert_eq!(rays.closest, pixels, "{backend:?}: one closest-hit ray a pixel");
        assert!(inside.len() > 600 && on_wall == inside.len(), "{backend:?}: the G-buffer holds the wall behind both panels");
    }
}

#[test]
fn raster_blends_the_panels_over_the_wall_after_the_opaque_surfaces_in_both_forward_layers() {
    let gpu = gpu();
    let path = repo().join("graph/raster.ron");
    for layer in ["forward", "forward_fragment"] {
        let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
        options.layers.insert("forward".into(), layer.into());
        for (what, scene, over) in composite_cases() {
            let plan = compile_with(&path, &Project::beside_graph(&path), SIZE, &options).unwrap();
            assert!(plan.passes().iter().any(|p| p.name == "forward/translucent" && p.translucent), "{layer}: a translucent pass");
            let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
            exec.render(&gpu, scene.camera(), &scene).unwrap();
            let hdr = channel(&gpu, &exec, "forward.color");
            let (worst_in, n_in, worst_out) = panel_errors(&hdr, over);
            println!("raster ({layer}), {what}: {n_in} pixels behind the panel, largest error {worst_in:.5}; beside it {worst_out:.5}");
            assert!(n_in > 600, "the panel is in view");
            // The f16 layers and output: 1e-3 a rounding, three of them.
            assert!(worst_in < 3e-3, "raster ({layer}), {what}: the panel over the wall, largest error {worst_in}");
            assert!(worst_out < 3e-3, "raster ({layer}), {what}: the bare wall, largest error {worst_out}");
        }
    }
}

#[test]
fn the_cpu_reads_the_transmission_texture_into_the_coverage_as_the_gpu_does() {
    let scene = transmission_texture_scene();
    assert!(scene.materials()[1].transmission_texture_drawn());
    let coverage = raygraph::accel::alpha::blend_coverage(&scene, 1, 0, [0.25, 0.25]).expect("a translucent panel");
    assert!((coverage - 0.4).abs() < 1e-6, "1 - 1 x 0.6: {coverage}");
    let mut other_uv = scene.clone();
    other_uv.materials_mut()[1].sampling[5 + raygraph::scene::LOBE_TRANSMISSION].tex_coord = 1;
    assert!(!other_uv.materials()[1].transmission_texture_drawn(), "a texture on another uv set is not drawn");
}

/// A lit floor (y = 0) under a sun straight above, `panels` BLEND panels over all of x < 0, the
/// first 1 above it, the others 0.5 apart above that; seen from above (image right is +x).
fn shadow_scene(panels: usize, transmissive: bool) -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("blend shadow");
    let flat = Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let over_left = |y: f32| Mat4::from_translation(Vec3::new(-4.0, y, 0.0)) * flat;
    s.set_meshes(vec![quad("floor", 4.0, 0.0), quad("panel", 4.0, 0.0)]);
    *s.materials_mut() = vec![Material::diffuse("floor", [0.8, 0.8, 0.8, 1.0], None), if transmissive { glass_material(true) } else { panel_material(true) }];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: flat }, Instance { mesh: 1, material: 1, transform: over_left(1.0) }];
    for i in 1..panels {
        s.instances_mut().push(Instance { mesh: 1, material: 1, transform: over_left(1.0 + 0.5 * i as f32) });
    }
    s.textures_mut().clear();
    *s.lights_mut() = vec![PunctualLight {
        name: "sun".into(),
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 3.0,
    }];
    *s.camera_mut() = Camera {
        position: Vec3::new(0.0, 10.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        fov_y: 2.0 * (3.0f32 / 10.0).atan(),
        near: 0.05,
        far: 100.0,
        orthographic: None,
        aspect_ratio: None,
    };
    s
}

#[test]
fn shadows_through_blend_panels_let_one_minus_their_coverage_through_on_every_back_end() {
    let gpu = gpu();
    // Ten stacked panels let 0.6^10 = 0.006 through (above the 1/256 below which a ray counts
    // as stopped): every surface on the ray counts, not only the first eight (0.6^8 = 0.017).
    let cases = [(1, false, 1.0 - COVERAGE), (2, false, (1.0 - COVERAGE).powi(2)), (10, false, (1.0 - COVERAGE).powi(10)), (1, true, TRANSMISSION)];
    for (panels, transmissive, through) in cases {
        let scene = shadow_scene(panels, transmissive);
        for backend in backends(&gpu) {
            let exec = render(&gpu, "graph/hybrid.ron", backend, &scene);
            let mask = channel(&gpu, &exec, "shadow.shadow");
            // Floor pixels: x in [-3, 3] spans the image; the panels cover x < 0 (left half),
            // the floor's right half is in the open. A pixel's margin around x = 0.
            let (mut under, mut open) = (Vec::new(), Vec::new());
            for y in 4..SIZE.1 - 4 {
                for x in 4..SIZE.0 - 4 {
                    let m = mask[(y * SIZE.0 + x) as usize][0];
                    if x < SIZE.0 / 2 - 1 {
                        under.push(m);
                    } else if x > SIZE.0 / 2 {
                        open.push(m);
                    }
                }
            }
            let worst_under = under.iter().map(|m| (m - through).abs()).fold(0.0f32, f32::max);
            let worst_open = open.iter().map(|m| (m - 1.0).abs()).fold(0.0f32, f32::max);
            println!("{backend:?}, {panels} panels, transmissive {transmissive}: light under the panels {through:.3} within {worst_under:.4}, in the open within {worst_open:.4}");
            // The mask is 8-bit: half a step.
            assert!(worst_under <= 0.5 / 255.0 + 1e-4, "{backend:?} {panels} panels: under the panels {worst_under}");
            assert!(worst_open <= 0.5 / 255.0 + 1e-4, "{backend:?} {panels} panels: in the open {worst_open}");
        }
    }
}

#[test]
fn a_scene_without_blend_materials_traces_its_shadow_rays_as_any_hit_rays() {
    let gpu = gpu();
    let scene = builtin::default_scene();
    assert!(scene.materials().iter().all(|m| m.alpha_mode != AlphaMode::Blend));
    let (_, rays_of) = render_counting_rays(&gpu, &repo().join("graph/hybrid.ron"), Backend::Compute, &scene);
    let (shadow, blend) = (rays_of("shadow/shadow"), rays_of("blend/blend"));
    println!("default scene: shadow pass {} any-hit, {} closest-hit rays; blend pass {} rays", shadow.any, shadow.closest, blend.traced());
    assert!(shadow.any > 0 && shadow.closest == 0, "shadow rays are any-hit rays without BLEND materials");
    assert_eq!(blend.traced(), 0, "the blend layer traces nothing without BLEND materials");
}
