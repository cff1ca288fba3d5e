//! Alpha-tested geometry against the analytic answer. Four unit quads ([-1, 1]² at z = 0, one
//! mesh) side by side, 3 apart, each over a plane at z = -1 that covers only the left half of
//! its view, x in [-1.5, 0], y in [-1.5, 1.5] (so holes show either the plane or nothing). The
//! quads share an 8x8 checkerboard texture of alpha 0 and 1 (uv [0, 1]² over the quad): MASK
//! 0.5, MASK 0.375 with base-colour alpha 0.75, MASK 0.25 with base-colour alpha 0.5 (the factor
//! times the texture), and an opaque material, which ignores the texture's alpha. The level-0 bilinear
//! read of a 0/1 checker crosses 0.5 exactly on the cell edges (also across the repeat wrap,
//! the checker being periodic), so an alpha-tested quad is its opaque cells.
//!
//! Rays per quad: a 48x48 grid over [-1.5, 1.5]² (16 rays per unit, centres at odd multiples
//! of 1/32: never on a cell edge, a quad edge or the plane's edge). Per alpha-tested quad, 512
//! hit the quad, 896 the plane and 896 nothing; the opaque quad takes 1024, 640 and 640. Shadow
//! rays straight up from the plane's grid points: 256 of 1152 shadowed (opaque: 512). AO rays
//! (range 2, straight up and tilted 4 degrees four ways) from the plane under the centres of the
//! 32 cells over it: every ray under an opaque cell is occluded, none under a hole. Two quads
//! stacked with complementary checkers stop every ray (an any-hit ray goes on past a hole).
//!
//! Every back-end lavapipe has and both layouts, with both texture paths (binding array and
//! the 256x256 texture array of `RAYGRAPH_NO_BINDLESS`); the f64 reference and the CPU
//! traversal give the same counts; the raster G-buffer and the forward pass cover exactly the
//! pixels the primary rays hit, all equal to the analytic classification of each camera ray.
//!
//! Also what the graphs specialise: one executor whose scene gains alpha-tested materials
//! compiles the test into its traversal and raster pipelines; and the raster pipelines' culling
//! (single-sided, double-sided, mirroring transforms) shows the sides the primary rays see.

mod common;

use glam::{Mat4, Vec3};
use raygraph::accel::alpha;
use raygraph::accel::bvh::AccelOptions;
use raygraph::accel::cache::AccelSettings;
use raygraph::accel::cpu_traverse::{CpuTraverser, Ray};
use raygraph::accel::layout::{merge, merge_instances, GpuAccel, TRI_ALPHA};
use raygraph::accel::reference::Reference;
use raygraph::accel::reference_render::ReferenceRenderer;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::graph::Project;
use raygraph::runtime::batch::{BatchTracer, GpuRay};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{builtin, AlphaMode, Camera, Instance, Material, Mesh, Scene, TextureImage, Vertex};

/// Quads, each over its plane, `SPACING` apart along x.
const QUADS: usize = 4;
const SPACING: f32 = 3.0;
/// Index of the opaque quad.
const OPAQUE: usize = 3;
const GRID: usize = 48;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Surface {
    Quad(usize),
    Plane(usize),
    Miss,
}

fn checker_alpha() -> TextureImage {
    let rgba = (0..64).flat_map(|i| [255, 255, 255, if (i % 8 + i / 8) % 2 == 0 { 255 } else { 0 }]).collect::<Vec<u8>>().into();
    TextureImage { name: "alpha checker".into(), width: 8, height: 8, rgba }
}

fn quad_mesh(name: &str, x: [f32; 2], y: [f32; 2], z: f32) -> Mesh {
    let v = |px: f32, py: f32| Vertex { position: [px, py, z], normal: [0.0, 0.0, 1.0], uv: [(px - x[0]) / (x[1] - x[0]), (y[1] - py) / (y[1] - y[0])] };
    Mesh {
        name: name.into(),
        vertices: vec![v(x[0], y[0]), v(x[1], y[0]), v(x[1], y[1]), v(x[0], y[1])],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    }
}

fn scene() -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("alpha checker");
    s.set_meshes(vec![quad_mesh("quad", [-1.0, 1.0], [-1.0, 1.0], 0.0), quad_mesh("plane", [-1.5, 0.0], [-1.5, 1.5], -1.0)]);
    *s.textures_mut() = vec![checker_alpha()];
    let textured = |name: &str, a: f32, mode| Material { alpha_mode: mode, ..Material::diffuse(name, [1.0, 1.0, 1.0, a], Some(0)) };
    *s.materials_mut() = vec![
        textured("mask", 1.0, AlphaMode::Mask(0.5)),
        textured("mask with factor 0.75", 0.75, AlphaMode::Mask(0.375)),
        textured("mask with factor", 0.5, AlphaMode::Mask(0.25)),
        textured("opaque", 1.0, AlphaMode::Opaque),
        Material::diffuse("plane", [0.6, 0.6, 0.6, 1.0], None),
    ];
    *s.instances_mut() = (0..QUADS)
        .flat_map(|i| {
            let at = Mat4::from_translation(Vec3::new(SPACING * i as f32, 0.0, 0.0));
            [Instance { mesh: 0, material: i, transform: at }, Instance { mesh: 1, material: 4, transform: at }]
        })
        .collect();
    s.lights_mut().clear();
    s
}

/// Whether the quad's texel at local (x, y) is opaque (cell of the 8x8 checker).
fn opaque_cell(x: f64, y: f64) -> bool {
    let (cx, cy) = (((x + 1.0) * 4.0).floor() as i64, ((1.0 - y) * 4.0).floor() as i64);
    (cx + cy) % 2 == 0
}

/// Distance of a local point to the nearest line of the 1/4 grid (cell and quad edges).
fn edge_distance(v: f64) -> f64 {
    let f = (v * 4.0).rem_euclid(1.0);
    f.min(1.0 - f) / 4.0
}

/// The analytic answer for a ray (f64 intersection with the planes z = 0 and z = -1).
fn classify(origin: Vec3, dir: Vec3) -> Surface {
    let (o, d) = (origin.as_dvec3(), dir.as_dvec3());
    let at = |z: f64| {
        let t = (z - o.z) / d.z;
        (t > 0.0).then(|| o + t * d)
    };
    let local = |p: glam::DVec3| {
        let i = ((p.x / SPACING as f64) + 0.5).floor().clamp(0.0, QUADS as f64 - 1.0) as usize;
        (i, p.x - SPACING as f64 * i as f64, p.y)
    };
    if let Some(p) = at(0.0) {
        let (i, x, y) = local(p);
        assert!(edge_distance(x) > 1e-3 && edge_distance(y) > 1e-3, "a ray passes within 1e-3 of a cell edge at ({x}, {y}): move the rays");
        if x.abs() < 1.0 && y.abs() < 1.0 && (i == OPAQUE || opaque_cell(x, y)) {
            return Surface::Quad(i);
        }
    }
    if let Some(p) = at(-1.0) {
        let (i, x, y) = local(p);
        assert!(x.abs() > 1e-3 && (x + 1.5).abs() > 1e-3 && (y.abs() - 1.5).abs() > 1e-3, "a ray passes within 1e-3 of the plane's edge");
        if (-1.5..0.0).contains(&x) && y.abs() < 1.5 {
            return Surface::Plane(i);
        }
    }
    Surface::Miss
}

/// Grid offsets of one quad's rays: odd multiples of 1/32 in [-1.5, 1.5].
fn grid() -> impl Iterator<Item = (f32, f32)> {
    (0..GRID * GRID).map(|k| (-1.5 + ((k % GRID) as f32 + 0.5) / 16.0, 1.5 - ((k / GRID) as f32 + 0.5) / 16.0))
}

fn primary_rays() -> Vec<Ray> {
    (0..QUADS).flat_map(|i| grid().map(move |(x, y)| Ray::with_interval(Vec3::new(x + SPACING * i as f32, y, 5.0), Vec3::NEG_Z, 0.0, 3.0e38))).collect()
}

/// Shadow rays straight up from the plane's grid points (just above it), unbounded.
fn shadow_rays() -> Vec<Ray> {
    (0..QUADS)
        .flat_map(|i| {
            grid().filter(|&(x, _)| x < 0.0).map(move |(x, y)| Ray::with_interval(Vec3::new(x + SPACING * i as f32, y, -0.999), Vec3::Z, 0.0, 3.0e38))
        })
        .collect()
}

/// AO rays of range 2 from the plane under the centre of every cell over it: straight up and
/// tilted 4 degrees towards +-x and +-y.
fn ao_rays() -> Vec<Ray> {
    let (s, c) = 4f32.to_radians().sin_cos();
    let dirs = [Vec3::Z, Vec3::new(s, 0.0, c), Vec3::new(-s, 0.0, c), Vec3::new(0.0, s, c), Vec3::new(0.0, -s, c)];
    let mut rays = Vec::new();
    for i in 0..QUADS {
        for cell in 0..32 {
            let (x, y) = (-1.0 + 0.125 + 0.25 * (cell % 4) as f32, 1.0 - 0.125 - 0.25 * (cell / 4) as f32);
            rays.extend(dirs.iter().map(|&d| Ray::with_interval(Vec3::new(x + SPACING * i as f32, y, -0.999), d, 0.0, 2.0)));
        }
    }
    rays
}

/// Per quad, the number of rays whose answer is `Quad`, `Plane`, `Miss`.
fn tally(surfaces: &[Surface]) -> Vec<[usize; 3]> {
    let mut out = vec![[0; 3]; QUADS];
    for (k, s) in surfaces.iter().enumerate() {
        let i = k / (GRID * GRID);
        out[i][match s {
            Surface::Quad(_) => 0,
            Surface::Plane(_) => 1,
            Surface::Miss => 2,
        }] += 1;
    }
    out
}

/// The analytic answers, with their counts checked against the module docs.
fn expected() -> (Vec<Surface>, Vec<bool>, Vec<bool>) {
    let primary: Vec<Surface> = primary_rays().iter().map(|r| classify(r.origin, r.dir)).collect();
    let counts = tally(&primary);
    for (i, c) in counts.iter().enumerate() {
        assert_eq!(*c, if i == OPAQUE { [1024, 640, 640] } else { [512, 896, 896] }, "analytic counts of quad {i}");
    }
    let shadow: Vec<bool> = shadow_rays().iter().map(|r| matches!(classify(r.origin + 2.0 * r.dir, -r.dir), Surface::Quad(_))).collect();
    let per_quad = shadow.len() / QUADS;
    for i in 0..QUADS {
        let shadowed = shadow[i * per_quad..(i + 1) * per_quad].iter().filter(|&&s| s).count();
        assert_eq!((shadowed, per_quad), (if i == OPAQUE { 512 } else { 256 }, 1152), "analytic shadow count of quad {i}");
    }
    // Under a cell: all five rays through it, or none.
    let ao: Vec<bool> = ao_rays()
        .iter()
        .map(|r| {
            let i = (r.origin.x / SPACING).round() as usize;
            let (x, y) = (r.origin.x as f64 - (SPACING * i as f32) as f64, r.origin.y as f64);
            i == OPAQUE || opaque_cell(x, y)
        })
        .collect();
    (primary, shadow, ao)
}

/// The surface a hit names: instance 2i is quad i, 2i + 1 its plane.
fn surface_of(instance: Option<u32>) -> Surface {
    match instance {
        Some(k) if k % 2 == 0 => Surface::Quad(k as usize / 2),
        Some(k) => Surface::Plane(k as usize / 2),
        None => Surface::Miss,
    }
}

fn gpu_rays(rays: &[Ray]) -> Vec<GpuRay> {
    rays.iter().map(|r| GpuRay { origin: r.origin.to_array(), t_min: r.t_min, dir: r.dir.to_array(), t_max: r.t_max }).collect()
}

fn assert_same<T: PartialEq + std::fmt::Debug>(what: &str, got: &[T], want: &[T]) {
    let wrong: Vec<usize> = (0..want.len()).filter(|&k| got[k] != want[k]).collect();
    assert!(
        wrong.is_empty(),
        "{what}: {} of {} rays differ from the analytic answer, first {:?}: {:?} instead of {:?}",
        wrong.len(),
        want.len(),
        wrong.first(),
        wrong.first().map(|&k| &got[k]),
        wrong.first().map(|&k| &want[k])
    );
}

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    assert!(gpu.texture_binding_arrays(), "lavapipe has texture binding arrays; CI must exercise both texture paths");
    gpu
}

/// Two alpha-tested quads 0.5 apart with complementary checkers (the upper one's texture
/// inverted): every ray through [-1, 1]² hits exactly one of them, so an any-hit ray whose
/// first candidate is a hole must go on to the other quad.
fn stacked_scene() -> Scene {
    let mut s = scene();
    let mut inverted = checker_alpha();
    for a in std::sync::Arc::make_mut(&mut inverted.rgba).iter_mut().skip(3).step_by(4) {
        *a = 255 - *a;
    }
    s.textures_mut().push(inverted);
    s.materials_mut().push(Material { alpha_mode: AlphaMode::Mask(0.5), ..Material::diffuse("inverted", [1.0; 4], Some(1)) });
    *s.instances_mut() = vec![
        Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY },
        Instance { mesh: 0, material: s.materials().len() - 1, transform: Mat4::from_translation(Vec3::new(0.0, 0.0, 0.5)) },
    ];
    s
}

/// For [`stacked_scene`]: rays down through the quads and up from below, and the instance each
/// downward ray hits (the upper quad 1 where the lower one has a hole).
fn stacked_rays() -> (Vec<Ray>, Vec<Ray>, Vec<Option<u32>>) {
    let inside: Vec<(f32, f32)> = grid().filter(|(x, y)| x.abs() < 1.0 && y.abs() < 1.0).collect();
    let down = inside.iter().map(|&(x, y)| Ray::with_interval(Vec3::new(x, y, 5.0), Vec3::NEG_Z, 0.0, 3.0e38)).collect();
    let up = inside.iter().map(|&(x, y)| Ray::with_interval(Vec3::new(x, y, -1.0), Vec3::Z, 0.0, 3.0e38)).collect();
    let hit = inside.iter().map(|&(x, y)| Some(if opaque_cell(x as f64, y as f64) { 0 } else { 1 })).collect();
    (down, up, hit)
}

/// Primary, shadow and AO rays through `backend` (both layouts where it has two, both texture
/// paths) against the analytic answer.
fn batch_matches_the_analytic_answer(backend: Backend) {
    let mut gpu = gpu();
    assert!(gpu.backends().contains(&backend), "lavapipe has back-end {backend}; CI must test it");
    let scene = scene();
    let (primary, shadow, ao) = expected();
    let stacked = stacked_scene();
    let (down, up, stacked_hits) = stacked_rays();
    let layouts: &[bool] = if backend == Backend::RayQuery { &[false] } else { &[false, true] };
    for bindless in [true, false] {
        gpu.set_texture_binding_arrays(bindless);
        for &merge in layouts {
            let what = format!("{backend}{}, {}", if merge { " merged" } else { "" }, if bindless { "binding array" } else { "texture array" });
            let t = BatchTracer::with_settings(&gpu, backend, &scene, &common::repo().join("shaders"), AccelSettings { dedup: true, merge }).unwrap();
            let hits = t.closest(&gpu, &gpu_rays(&primary_rays())).unwrap().0;
            let got: Vec<Surface> = hits.iter().map(|h| surface_of(h.map(|h| h.instance))).collect();
            println!("{what}: primary (quad, plane, miss) per quad {:?}", tally(&got));
            assert_same(&format!("{what}, primary rays"), &got, &primary);
            assert_same(&format!("{what}, shadow rays"), &t.any(&gpu, &gpu_rays(&shadow_rays())).unwrap().0, &shadow);
            assert_same(&format!("{what}, AO rays"), &t.any(&gpu, &gpu_rays(&ao_rays())).unwrap().0, &ao);

            let t = BatchTracer::with_settings(&gpu, backend, &stacked, &common::repo().join("shaders"), AccelSettings { dedup: true, merge }).unwrap();
            let got: Vec<Option<u32>> = t.closest(&gpu, &gpu_rays(&down)).unwrap().0.iter().map(|h| h.map(|h| h.instance)).collect();
            assert_same(&format!("{what}, stacked quads, closest"), &got, &stacked_hits);
            assert_same(&format!("{what}, stacked quads, any from below"), &t.any(&gpu, &gpu_rays(&up)).unwrap().0, &vec![true; up.len()]);
        }
    }
}

#[test]
fn compute_cuts_out_the_checker() {
    batch_matches_the_analytic_answer(Backend::Compute);
}

#[test]
fn ray_query_cuts_out_the_checker() {
    batch_matches_the_analytic_answer(Backend::RayQuery);
}

#[test]
fn rt_pipeline_cuts_out_the_checker() {
    batch_matches_the_analytic_answer(Backend::RtPipeline);
}

#[test]
fn cpu_references_cut_out_the_checker() {
    let scene = scene();
    let (primary, shadow, ao) = expected();
    let reference = Reference::new(&scene);
    let got: Vec<Surface> = reference.closest_many(&primary_rays()).iter().map(|h| surface_of(h.map(|h| h.instance_id))).collect();
    assert_same("f64 reference, primary rays", &got, &primary);
    assert_same("f64 reference, shadow rays", &reference.any_many(&shadow_rays()), &shadow);
    assert_same("f64 reference, AO rays", &reference.any_many(&ao_rays()), &ao);
    let (down, up, stacked_hits) = stacked_rays();
    assert_eq!(stacked_hits.iter().filter(|h| **h == Some(1)).count(), 512, "analytic: half the rays pass the lower quad's holes");
    let stacked = Reference::new(&stacked_scene());
    let got: Vec<Option<u32>> = stacked.closest_many(&down).iter().map(|h| h.map(|h| h.instance_id)).collect();
    assert_same("f64 reference, stacked quads", &got, &stacked_hits);
    assert!(stacked.any_many(&up).iter().all(|&h| h), "f64 reference: every ray from below is stopped");
    // Every ray crosses the quads' plane clear of an alpha edge: the bilinear alpha there is
    // well away from 0.5 (the smallest distance is 0.03, at cell corners).
    let texture = checker_alpha();
    let closest_to_edge = grid()
        .filter(|(x, y)| x.abs() < 1.0 && y.abs() < 1.0)
        .map(|(x, y)| (alpha::bilinear_alpha(&texture, [(x as f64 + 1.0) / 2.0, (1.0 - y as f64) / 2.0], &Default::default()) - 0.5).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(closest_to_edge > 0.03, "alpha within {closest_to_edge} of the cutoff");

    let (merged_mesh, origin) = merge_instances(&scene);
    let layouts = [
        ("two-level", GpuAccel::build(&scene, &AccelOptions::default())),
        ("merged", merge(&merged_mesh, &origin, raygraph::accel::bvh::Blas::build(&merged_mesh, &Default::default()))),
    ];
    for (name, accel) in &layouts {
        let cpu = CpuTraverser::with_scene(accel, &scene);
        let got: Vec<Surface> = cpu.closest_many(&primary_rays()).iter().map(|h| surface_of(h.map(|h| h.instance_id))).collect();
        assert_same(&format!("CPU traversal {name}, primary rays"), &got, &primary);
        assert_same(&format!("CPU traversal {name}, shadow rays"), &cpu.any_many(&shadow_rays()), &shadow);
        assert_same(&format!("CPU traversal {name}, AO rays"), &cpu.any_many(&ao_rays()), &ao);
    }
}

#[test]
fn only_alpha_tested_instances_are_flagged() {
    // The alpha scene: quads 0..3 are alpha-tested, the opaque quad and the planes are not.
    let scene = scene();
    let accel = GpuAccel::build(&scene, &AccelOptions::default());
    let flagged: Vec<u32> =
        accel.instances.iter().filter(|i| i.flags != 0).map(|i| i.instance_id).collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    assert_eq!(flagged, [0, 2, 4]);
    assert_eq!(alpha::tested_meshes(&scene), [true, false], "the quad mesh is alpha-tested through its alpha instances");
    let (mesh, origin) = merge_instances(&scene);
    let merged = merge(&mesh, &origin, raygraph::accel::bvh::Blas::build(&mesh, &Default::default()));
    assert!(merged.triangles.iter().all(|t| (t.flags & TRI_ALPHA != 0) == [0, 2, 4].contains(&t.instance) || t.prim == u32::MAX));

    // Opaque scenes: no flag anywhere, one opaque record for the trace module, no uvs.
    for scene in [builtin::default_scene(), raygraph::scene::procedural::atrium(1)] {
        let accel = GpuAccel::build(&scene, &AccelOptions::default());
        assert!(accel.instances.iter().all(|i| i.flags == 0) && accel.triangles.iter().all(|t| t.flags == 0), "{}", scene.name());
        let (mesh, origin) = merge_instances(&scene);
        let merged = merge(&mesh, &origin, raygraph::accel::bvh::Blas::build(&mesh, &Default::default()));
        assert!(merged.triangles.iter().all(|t| t.flags & TRI_ALPHA == 0), "{}", scene.name());
        assert_eq!(alpha::gpu_words(&scene, &raygraph::scene::texture_pool::texture_refs(&scene, true)), [[alpha::ALPHA_OPAQUE; 4]], "{}", scene.name());
        assert!(alpha::tested_meshes(&scene).iter().all(|&t| !t), "{}", scene.name());
    }
}

/// The camera of the graph test: quads 0 and 1 (both MASK) fill a 96x48 image, its pixel
/// centres on the quads' plane at the batch rays' grid.
fn camera() -> Camera {
    Camera {
        position: Vec3::new(1.5, 0.0, 4.0),
        target: Vec3::new(1.5, 0.0, 0.0),
        up: Vec3::Y,
        fov_y: 2.0 * (1.5f32 / 4.0).atan(),
        near: 0.05,
        far: 100.0,
        orthographic: None,
        aspect_ratio: None,
    }
}

const IMAGE: (u32, u32) = (96, 48);

/// Per pixel, the surface the G-buffer's position shows.
fn gbuffer_surfaces(gpu: &Gpu, path: &std::path::Path, options: CompileOptions, scene: &Scene) -> Vec<Surface> {
    let mut exec = gbuffer_executor(gpu, path, options, scene);
    rendered_surfaces(gpu, &mut exec, scene)
}

fn gbuffer_executor(gpu: &Gpu, path: &std::path::Path, options: CompileOptions, scene: &Scene) -> Executor {
    let plan = compile_with(path, &Project::beside_graph(path), IMAGE, &CompileOptions { reuse: false, ..options }).unwrap();
    Executor::new(gpu, plan, scene).unwrap()
}

/// Renders `scene` with `exec` and classifies the G-buffer's position per pixel.
fn rendered_surfaces(gpu: &Gpu, exec: &mut Executor, scene: &Scene) -> Vec<Surface> {
    exec.render(gpu, scene.camera(), scene).unwrap();
    let r = exec.plan().resource_by_name("gbuffer.position").unwrap();
    let pos = exec.read_texture_f32(gpu, r).unwrap().2;
    pos.iter()
        .map(|p| {
            let i = ((p[0] / SPACING) + 0.5).floor().clamp(0.0, QUADS as f32 - 1.0) as usize;
            match (p[3] != 0.0, p[2] > -0.5) {
                (false, _) => Surface::Miss,
                (true, true) => Surface::Quad(i),
                (true, false) => Surface::Plane(i),
            }
        })
        .collect()
}

/// The scene with the camera of the graph tests, the analytic answer per pixel, and a project
/// with the shipped graphs plus full_rt with a two-level `Accel` (it ships merged).
fn graph_setup() -> (Scene, Vec<Surface>, common::TempProject) {
    let mut scene = scene();
    *scene.camera_mut() = camera();
    let want: Vec<Surface> = ReferenceRenderer::camera_rays(scene.camera(), IMAGE).iter().map(|r| classify(r.origin, r.dir)).collect();
    let count = |f: fn(&Surface) -> bool| want.iter().filter(|x| f(x)).count();
    let counts = (count(|s| matches!(s, Surface::Quad(_))), count(|s| matches!(s, Surface::Plane(_))), count(|s| *s == Surface::Miss));
    assert_eq!(counts, (1024, 1312, 2272), "analytic (quad, plane, miss) pixels");
    let p = common::TempProject::with_repo_files();
    let full_rt = std::fs::read_to_string(common::repo().join("graph/full_rt.ron")).unwrap();
    let two_level = full_rt.replace("Accel(merge: true)", "Accel()");
    assert_ne!(two_level, full_rt, "graph/full_rt.ron no longer merges: update the test");
    p.write("graph/full_rt.ron", &full_rt);
    p.write("graph/full_rt_two_level.ron", &two_level);
    for g in ["hybrid", "raster"] {
        p.write(&format!("graph/{g}.ron"), &std::fs::read_to_string(common::repo().join(format!("graph/{g}.ron"))).unwrap());
    }
    (scene, want, p)
}

/// The raster G-buffer (deferred pass of the hybrid graph) shows, pixel for pixel, the
/// analytic answer for each camera ray, with both texture paths.
#[test]
fn raster_gbuffer_cuts_out_the_checker() {
    let mut gpu = gpu();
    let (scene, want, p) = graph_setup();
    for bindless in [true, false] {
        gpu.set_texture_binding_arrays(bindless);
        let raster = gbuffer_surfaces(&gpu, &p.root.join("graph/hybrid.ron"), gpu.compile_options_for(Backend::Compute), &scene);
        assert_same(&format!("raster G-buffer, binding array {bindless}"), &raster, &want);
        // The forward pass (raster graph), from its depth buffer: the cleared value where
        // nothing was drawn; the quads' and the planes' depths are two values (both are
        // perpendicular to the view axis), the quads' the one farther from the cleared value.
        let path = p.root.join("graph/raster.ron");
        let options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
        let mut exec = Executor::new(&gpu, compile_with(&path, &Project::beside_graph(&path), IMAGE, &options).unwrap(), &scene).unwrap();
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        let depth: Vec<f32> = exec.read_texture_f32(&gpu, exec.plan().resource_by_name("forward/depth").unwrap()).unwrap().2.iter().map(|d| d[0]).collect();
        let kind = |s: &Surface| match s {
            Surface::Quad(_) => 0,
            Surface::Plane(_) => 1,
            Surface::Miss => 2,
        };
        let cleared = depth[want.iter().position(|s| *s == Surface::Miss).unwrap()];
        let (quad, plane) = (depth[want.iter().position(|s| kind(s) == 0).unwrap()], depth[want.iter().position(|s| kind(s) == 1).unwrap()]);
        assert!((quad - cleared).abs() > (plane - cleared).abs(), "the quads are in front of the planes");
        let forward: Vec<u8> = depth
            .iter()
            .map(|&d| {
                if d == cleared {
                    2
                } else if (d - quad).abs() < (d - plane).abs() {
                    0
                } else {
                    1
                }
            })
            .collect();
        assert_same(&format!("forward pass, binding array {bindless}"), &forward, &want.iter().map(kind).collect::<Vec<u8>>());
    }
}

/// The primary rays' G-buffer (full ray-tracing graph) on `backend`, both layouts where it has
/// two, both texture paths: the analytic answer per pixel, so the raster G-buffer's coverage
/// ([`raster_gbuffer_cuts_out_the_checker`]) pixel for pixel.
fn gbuffers_match(backend: Backend) {
    let mut gpu = gpu();
    assert!(gpu.backends().contains(&backend), "lavapipe has back-end {backend}; CI must test it");
    let (scene, want, p) = graph_setup();
    let graphs: &[&str] = if backend == Backend::RayQuery { &["full_rt_two_level"] } else { &["full_rt", "full_rt_two_level"] };
    for bindless in [true, false] {
        gpu.set_texture_binding_arrays(bindless);
        for graph in graphs {
            let traced = gbuffer_surfaces(&gpu, &p.root.join(format!("graph/{graph}.ron")), gpu.compile_options_for(backend), &scene);
            assert_same(&format!("primary-ray G-buffer {backend} ({graph}), binding array {bindless}"), &traced, &want);
        }
    }
}

#[test]
fn compute_gbuffers_agree_with_the_raster_gbuffer() {
    gbuffers_match(Backend::Compute);
}

#[test]
fn ray_query_gbuffers_agree_with_the_raster_gbuffer() {
    gbuffers_match(Backend::RayQuery);
}

#[test]
fn rt_pipeline_gbuffers_agree_with_the_raster_gbuffer() {
    gbuffers_match(Backend::RtPipeline);
}

/// A trace pass that reads no texture itself (the shadow pass) binds the alpha test's data
/// through the back-end's module on every back-end and texture path: `scene_textures` in group
/// 1 (so the plan loads the scene's textures) and `accel_alpha` in group 2.
#[test]
fn every_trace_module_binds_the_alpha_data() {
    use raygraph::graph::reflect::{reflect_with, BindingKind};
    use raygraph::scene::usage::SceneUsage;
    let shaders = common::repo().join("shaders");
    let shadow = shaders.join("rt/shadow.wgsl");
    for backend in Backend::ALL {
        for bindless in [false, true] {
            let options = CompileOptions { includes: raygraph::runtime::gpu::include_aliases(bindless), backend, ..Default::default() };
            let info = reflect_with(&shadow, &shaders, &raygraph::error::Location::file_start(&shadow), &options.all_includes()).unwrap();
            let find = |name: &str| info.bindings.iter().find(|b| b.name == name);
            let textures = find("scene_textures").unwrap_or_else(|| panic!("{backend}: no scene_textures"));
            assert_eq!((textures.group, textures.kind == BindingKind::TextureBindingArray), (1, bindless), "{backend}");
            assert_eq!(find("accel_alpha").map(|b| b.group), Some(2), "{backend}: accel_alpha");
            let mut usage = SceneUsage::default();
            info.bindings.iter().for_each(|b| usage.add_binding(b));
            assert!(usage.textures && usage.texture_binding_array == bindless, "{backend}");
        }
    }
}

/// One executor per graph, first given the scene with every material opaque (no alpha-tested
/// instance: the traversal is compiled without the test and every draw takes the raster
/// pipeline without it), then the checker scene: the next frame must cut the checker out, on
/// the raster G-buffer and on `compute`'s primary rays, both layouts. The opaque frame shows
/// every quad in view whole: more pixels than its checker, and the raster and the traced
/// G-buffers agree pixel for pixel. On the two-level layout only the quads' BLAS is rebuilt
/// (its mesh became alpha-tested), and the planes' must be kept: the frame after the change
/// still shows every plane pixel.
#[test]
fn an_executor_compiles_the_alpha_test_in_when_its_scene_gains_alpha() {
    let gpu = gpu();
    let (scene, want, p) = graph_setup();
    let mut opaque = scene.clone();
    for m in opaque.materials_mut().iter_mut() {
        m.alpha_mode = AlphaMode::Opaque;
    }
    let quad_pixels = |s: &[Surface]| (0..QUADS).map(|i| s.iter().filter(|x| **x == Surface::Quad(i)).count()).collect::<Vec<_>>();
    let want_quads = quad_pixels(&want);
    let mut opaque_frames = Vec::new();
    for graph in ["hybrid", "full_rt", "full_rt_two_level"] {
        let path = p.root.join(format!("graph/{graph}.ron"));
        let mut exec = gbuffer_executor(&gpu, &path, gpu.compile_options_for(Backend::Compute), &opaque);
        let first = rendered_surfaces(&gpu, &mut exec, &opaque);
        let quads = quad_pixels(&first);
        // Quads 0 and 1 (both MASK) are the ones in view.
        for i in 0..QUADS {
            let more = if want_quads[i] > 0 { quads[i] > want_quads[i] } else { quads[i] == 0 };
            assert!(more, "{graph}, opaque frame: quad {i} covers {} pixels, its checker {}", quads[i], want_quads[i]);
        }
        assert!(want_quads[0] > 0 && want_quads[1] > 0, "the camera sees quads 0 and 1");
        opaque_frames.push(first);
        let second = rendered_surfaces(&gpu, &mut exec, &scene);
        assert_same(&format!("{graph}, frame after the materials became alpha-tested"), &second, &want);
    }
    assert_same("traced against raster G-buffer, opaque frame", &opaque_frames[1], &opaque_frames[0]);
    assert_same("two-level against raster G-buffer, opaque frame", &opaque_frames[2], &opaque_frames[0]);
}

/// Two unit quads ([-1, 1]² at z = 0, facing +z), at x = 0 and x = 3, the second mirrored by
/// its transform (x -> -x about its centre: same place, reversed winding, same front side).
fn facing_scene(double_sided: bool) -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("facing");
    s.set_meshes(vec![quad_mesh("quad", [-1.0, 1.0], [-1.0, 1.0], 0.0)]);
    s.textures_mut().clear();
    *s.materials_mut() = vec![Material { double_sided, ..Material::diffuse("quad", [0.8, 0.8, 0.8, 1.0], None) }];
    let mirrored = Mat4::from_translation(Vec3::new(SPACING, 0.0, 0.0)) * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 0, material: 0, transform: mirrored }];
    s.lights_mut().clear();
    s
}

/// The raster G-buffer culls the back faces of single-sided materials in the rasterizer (for
/// a mirroring transform, the faces whose winding it reverses), and draws double-sided ones on
/// both sides: from in front, both quads; from behind, none when single-sided, both when
/// double-sided. The same pixels as the primary rays (`compute`, full RT graph) and as the
/// analytic answer: a pixel shows quad i where its camera ray crosses z = 0 within quad i
/// (the camera's pixel centres fall on odd multiples of 1/32 there, never on an edge).
#[test]
fn raster_culling_shows_the_sides_the_rays_see() {
    let gpu = gpu();
    let (_, _, p) = graph_setup();
    for double_sided in [false, true] {
        for behind in [false, true] {
            let mut scene = facing_scene(double_sided);
            *scene.camera_mut() = camera();
            if behind {
                scene.camera_mut().position.z = -scene.camera_mut().position.z;
            }
            let want: Vec<Surface> = ReferenceRenderer::camera_rays(scene.camera(), IMAGE)
                .iter()
                .map(|r| {
                    let (o, d) = (r.origin.as_dvec3(), r.dir.as_dvec3());
                    let q = o + d * (-o.z / d.z);
                    let i = ((q.x / SPACING as f64) + 0.5).floor().clamp(0.0, 1.0) as usize;
                    let visible = double_sided || !behind;
                    if visible && (q.x - SPACING as f64 * i as f64).abs() < 1.0 && q.y.abs() < 1.0 {
                        Surface::Quad(i)
                    } else {
                        Surface::Miss
                    }
                })
                .collect();
            let shown = want.iter().filter(|s| **s != Surface::Miss).count();
            assert_eq!(shown, if double_sided || !behind { 2 * 32 * 32 } else { 0 }, "analytic pixels of the two quads");
            let what = format!("{} quads seen from {}", if double_sided { "double-sided" } else { "single-sided" }, if behind { "behind" } else { "in front" });
            for graph in ["hybrid", "full_rt"] {
                let got = gbuffer_surfaces(&gpu, &p.root.join(format!("graph/{graph}.ron")), gpu.compile_options_for(Backend::Compute), &scene);
                assert_same(&format!("{what}, {graph} G-buffer"), &got, &want);
            }
        }
    }
}
