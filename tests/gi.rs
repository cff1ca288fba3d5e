//! One-bounce diffuse global illumination (`rt_gi`) in a furnace: inside a closed box whose
//! walls all emit radiance E (and the default sun outside, which the walls hide), every GI ray
//! hits a wall, and the cosine-weighted mean radiance arriving from surfaces is E at every
//! pixel, whatever the directions; the resolve adds exactly albedo x E to the image, the
//! difference between the graph with the `gi` node and with it switched off.

mod common;

use common::{gpu, TempProject};
use glam::{Mat4, Vec3};
use raygraph::runtime::Executor;
use raygraph::scene::builtin::{cube, default_scene};
use raygraph::scene::{Camera, Instance, Material, Scene};

const W: u32 = 64;
const H: u32 = 48;
const E: f32 = 0.2;
const ALBEDO: f32 = 0.5;

fn furnace() -> Scene {
    let mut s = default_scene();
    s.name = "furnace".into();
    s.meshes = vec![cube("room")].into_iter().map(Into::into).collect();
    s.textures = Vec::new();
    let mut m = Material::diffuse("wall", [ALBEDO, ALBEDO, ALBEDO, 1.0], None);
    m.emissive = [E; 3];
    m.double_sided = true;
    m.roughness = 1.0;
    *s.materials_mut() = vec![m];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::from_scale(Vec3::splat(4.0)) }];
    s.light.ambient = 0.0;
    s.camera = Camera::look(Vec3::new(0.3, 0.2, 1.2), Vec3::new(-0.5, -0.4, -1.0), 70.0, 0.01, 100.0);
    s
}

fn graph(gi_enabled: bool) -> String {
    format!(
        r#"Graph(output: "tonemap.color", nodes: {{
    "accel": Accel(),
    "gbuffer": Layer(layer: "deferred"),
    "shadow": Layer(
        layer: "rt_shadow",
        inputs: {{"position": "gbuffer.position", "geo_normal": "gbuffer.geo_normal", "normal": "gbuffer.normal", "albedo": "gbuffer.albedo", "material": "gbuffer.material", "lobes": "gbuffer.lobes", "tlas": "accel.tlas"}},
    ),
    "gi": Layer(
        layer: "rt_gi",
        enabled: {gi_enabled},
        inputs: {{"position": "gbuffer.position", "geo_normal": "gbuffer.geo_normal", "normal": "gbuffer.normal", "tlas": "accel.tlas"}},
        params: {{"rays": 4, "per_frame": true}},
    ),
    "resolve": Layer(
        layer: "resolve",
        inputs: {{
            "position": "gbuffer.position", "normal": "gbuffer.normal", "albedo": "gbuffer.albedo", "material": "gbuffer.material", "lobes": "gbuffer.lobes",
            "emissive": "gbuffer.emissive", "direct": "shadow.direct", "gi": "gi.gi",
        }},
    ),
    "tonemap": Layer(layer: "tonemap", inputs: {{"hdr": "resolve.hdr"}}),
}})"#
    )
}

/// A texture's texels, read back.
type Texels = Vec<[f32; 4]>;

/// The `resolve.hdr` texels, the G-buffer's positions and, with GI, the `gi.gi` texels after
/// two frames.
fn render(gi_enabled: bool) -> (Texels, Texels, Option<Texels>) {
    let gpu = gpu();
    let p = TempProject::with_repo_files();
    let path = p.write("graph/furnace.ron", &graph(gi_enabled));
    let plan = raygraph::graph::compile::compile(&path, &p.project(), (W, H)).unwrap_or_else(|e| panic!("{e}"));
    let scene = furnace();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    for _ in 0..2 {
        exec.render(&gpu, &scene.camera, &scene).unwrap();
    }
    (common::channel(&gpu, &exec, "resolve.hdr"), common::channel(&gpu, &exec, "gbuffer.position"), gi_enabled.then(|| common::channel(&gpu, &exec, "gi.gi")))
}

#[test]
fn in_a_furnace_every_pixel_receives_the_walls_emission_and_the_resolve_adds_albedo_times_it() {
    let (with_gi, position, gi) = render(true);
    let (without_gi, _, _) = render(false);
    let gi = gi.expect("gi channel");
    // Pixels on a wall's edge (within 1% of the box's half-width of two walls) are left out:
    // a ray that leaves the very edge starts on the other wall's plane and may pass it.
    let on_edge = |p: &[f32; 4]| p[..3].iter().filter(|c| c.abs() > 2.0 * 0.99).count() >= 2;
    let edge = position.iter().filter(|p| on_edge(p)).count();
    let gi: Vec<[f32; 4]> = gi.iter().zip(&position).filter(|(_, p)| !on_edge(p)).map(|(g, _)| *g).collect();
    // Half-float storage of E = 0.2: 0.19995117.
    let stored = |v: f32| v - 0.2 * 2f32.powi(-11);
    let worst_gi = gi.iter().flat_map(|v| v[..3].to_vec()).map(|v| (v - E).abs()).fold(0.0f32, f32::max);
    let added: Vec<f32> =
        with_gi.iter().zip(&without_gi).zip(&position).filter(|(_, p)| !on_edge(p)).flat_map(|((a, b), _)| (0..3).map(move |c| a[c] - b[c])).collect();
    // The G-buffer keeps the albedo in 8 bits (0.5 is 128/255) and E in half floats.
    let expected_added = (ALBEDO * 255.0).round() / 255.0 * stored(E);
    let worst_added = added.iter().map(|d| (d - expected_added).abs()).fold(0.0f32, f32::max);
    let brightest = with_gi.iter().flat_map(|v| v[..3].to_vec()).fold(0.0f32, f32::max);
    println!("{} pixels judged, {edge} on an edge left out", gi.len());
    println!("GI: largest deviation from E = {E}: {worst_gi:e}; the resolve's addition: largest deviation from albedo x E = {expected_added}: {worst_added:e} (brightest HDR value {brightest})");
    assert!(gi.iter().all(|v| v[3] == 1.0), "every pixel is a wall");
    // E comes back through half floats (the emissive G-buffer channel and the GI target).
    assert!(worst_gi <= (E - stored(E)).abs() * 2.0 + 1e-6, "GI differs from E by {worst_gi}");
    // The HDR target is half floats: each of the two images carries up to one unit in the last
    // place at its brightest value (a store may round towards zero).
    let ulp = 2f32.powi(brightest.log2().floor() as i32 - 10);
    assert!(worst_added <= 2.0 * ulp, "the resolve added albedo x GI with an error of {worst_added} (2 units: {})", 2.0 * ulp);
}
