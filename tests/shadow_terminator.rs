//! The shadow terminator of smooth-shaded low-poly meshes: a 6 x 8 sphere alone under a grazing
//! sun. Nothing else is in the scene, so every pixel whose shading normal faces the sun is lit;
//! ray-traced shadows used to leave a jagged dark fringe there (facets whose flat face turns
//! away, or whose shadow rays hit the next facet). Measured in hybrid and full RT against the
//! f64 reference (the same rays, traced in f64, from the G-buffer's surfaces with and without
//! the offset) and against raster's shadow maps (the final colour in the terminator band).

mod common;

use common::{channel, gpu, repo};
use glam::{Mat4, Vec3};
use raygraph::accel::reference_render::{ReferenceRenderer, SurfacePoint};
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{Camera, Instance, Light, Material, Scene};

const SIZE: (u32, u32) = (96, 96);

/// The low-poly sphere, the sun grazing it from +x (slightly from above and behind the camera's
/// side so the terminator crosses the visible half), the camera on +z.
fn sphere_scene() -> Scene {
    let mut scene = raygraph::scene::builtin::default_scene();
    scene.set_meshes(vec![raygraph::scene::builtin::sphere("low-poly sphere", 6, 8)]);
    *scene.materials_mut() = vec![Material::diffuse("white", [0.8, 0.8, 0.8, 1.0], None)];
    *scene.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::from_rotation_y(0.3) }];
    scene.textures_mut().clear();
    scene.lights_mut().clear();
    scene.set_point_light(None);
    *scene.light_mut() = Light { direction: Vec3::new(1.0, 0.15, -0.1).normalize(), ..*scene.light() };
    *scene.camera_mut() = Camera::look(Vec3::new(0.0, 0.0, 3.2), Vec3::ZERO, 45.0, 0.1, 10.0);
    scene
}

fn run(gpu: &Gpu, scene: &Scene, graph: &str, off: &[&str]) -> Executor {
    let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    for node in off {
        options.enabled.insert(node.to_string(), false);
    }
    let path = repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    exec
}

/// The G-buffer's surfaces, as the shadow pass reads them.
fn surfaces(gpu: &Gpu, exec: &Executor) -> Vec<Option<SurfacePoint>> {
    let (pos, normal, geo) = (channel(gpu, exec, "gbuffer.position"), channel(gpu, exec, "gbuffer.normal"), channel(gpu, exec, "gbuffer.geo_normal"));
    let xyz = |v: [f32; 4]| Vec3::new(v[0], v[1], v[2]);
    (0..pos.len())
        .map(|i| {
            (pos[i][3] != 0.0).then(|| SurfacePoint {
                position: xyz(pos[i]),
                geo_normal: xyz(geo[i]),
                normal: xyz(normal[i]).normalize(),
                shadow_offset: geo[i][3],
            })
        })
        .collect()
}

/// Among pixels whose shading normal faces the sun by more than 0.05, the share `shadowed`
/// calls shadowed.
fn fringe(surfaces: &[Option<SurfacePoint>], sun: Vec3, shadowed: impl Fn(usize) -> bool) -> (usize, f64) {
    let facing: Vec<usize> = (0..surfaces.len()).filter(|&i| surfaces[i].is_some_and(|s| s.normal.dot(sun) > 0.05)).collect();
    let dark = facing.iter().filter(|&&i| shadowed(i)).count();
    (facing.len(), dark as f64 / facing.len().max(1) as f64)
}

#[test]
fn smooth_low_poly_surfaces_have_no_shadow_terminator_fringe() {
    let gpu = gpu();
    let scene = sphere_scene();
    let sun = scene.light().direction;
    let reference = ReferenceRenderer::new(&scene);
    for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
        let exec = run(&gpu, &scene, graph, &["ao", "reflection"]);
        let surfaces = surfaces(&gpu, &exec);
        let mask = channel(&gpu, &exec, "shadow.shadow");
        let (facing, gpu_share) = fringe(&surfaces, sun, |i| mask[i][0] < 0.5);
        // The same rays in f64 from the same surfaces, and from the surfaces without the offset
        // (what the shadow pass traced before it).
        let with = reference.shadow(&surfaces, scene.light(), None);
        let flat: Vec<Option<SurfacePoint>> = surfaces.iter().map(|s| s.map(|s| SurfacePoint { shadow_offset: 0.0, ..s })).collect();
        let without = reference.shadow(&flat, scene.light(), None);
        let (_, with_share) = fringe(&surfaces, sun, |i| with[i].is_some_and(|p| !p.sun.value));
        let (_, without_share) = fringe(&surfaces, sun, |i| without[i].is_some_and(|p| !p.sun.value));
        println!(
            "{graph}: {facing} pixels face the sun by their shading normal; shadowed: GPU {:.2}%, f64 reference with the offset {:.2}%, without it {:.2}%",
            100.0 * gpu_share,
            100.0 * with_share,
            100.0 * without_share
        );
        assert!(facing > 1000, "{graph}: the lit side is in view");
        assert!(without_share > 0.05, "{graph}: without the offset the fringe is there ({without_share})");
        assert!(gpu_share <= 0.002 && with_share <= 0.002, "{graph}: the fringe is gone: GPU {gpu_share}, reference {with_share}");
        // The GPU agrees with the f64 reference wherever the reference's answer is robust.
        let disagree = (0..mask.len()).filter(|&i| with[i].is_some_and(|p| p.sun.margin > 1e-4 && p.sun.value != (mask[i][0] >= 0.5))).count();
        assert_eq!(disagree, 0, "{graph}: shadow mask against the f64 reference");
    }
}

#[test]
fn a_lone_convex_mesh_shades_as_if_unshadowed_and_raster_is_measured_beside_it() {
    // Nothing can shadow a lone convex mesh but itself, and a convex smooth surface does not
    // shadow itself: with the shadow pass on, every pixel must match the frame without it
    // (the resolve then lights every light unshadowed). Raster's shadow maps are measured in the
    // terminator band beside it (ACCURACY.md, "Shadow terminator").
    let gpu = gpu();
    let scene = sphere_scene();
    let sun = scene.light().direction;
    let exec = run(&gpu, &scene, "graph/hybrid.ron", &["ao", "reflection"]);
    let shadowed = channel(&gpu, &exec, "resolve.hdr");
    let unshadowed = channel(&gpu, &run(&gpu, &scene, "graph/hybrid.ron", &["ao", "reflection", "shadow"]), "resolve.hdr");
    let raster = channel(&gpu, &run(&gpu, &scene, "graph/raster.ron", &[]), "forward.color");
    let surfaces = surfaces(&gpu, &exec);
    let luminance = |c: [f32; 4]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let worst = (0..shadowed.len()).map(|i| (luminance(shadowed[i]) - luminance(unshadowed[i])).abs()).fold(0.0f32, f32::max);
    // The band where the smooth normal turns from the sun: shading normal . sun in (0, 0.3).
    let band: Vec<usize> = (0..surfaces.len()).filter(|&i| surfaces[i].is_some_and(|s| (0.0..0.3).contains(&s.normal.dot(sun)))).collect();
    let mean = |img: &[[f32; 4]]| band.iter().map(|&i| luminance(img[i]) as f64).sum::<f64>() / band.len() as f64;
    println!(
        "terminator band, {} pixels, mean luminance: hybrid {:.4}, unshadowed {:.4}, raster {:.4}; worst pixel, shadowed against unshadowed: {worst:.5}",
        band.len(),
        mean(&shadowed),
        mean(&unshadowed),
        mean(&raster)
    );
    assert!(band.len() > 200, "the band is in view");
    // The shadowed frame's direct light is rounded to rgba16float twice (the shadow pass's
    // `direct`, then the resolve's output) against once: one f16 step near 1.5 is 0.00098, and
    // the measured worst is 0.00195 (two steps); a shadowed pixel would lose its whole direct
    // light (0.1 and more).
    assert!(worst < 4e-3, "a pixel of the lone sphere is shadowed: {worst}");
}
