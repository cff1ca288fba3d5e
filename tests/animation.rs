//! Animated glTF (assets/gltf/animated/, written by its make.py; the statically posed twins
//! and bad inputs in tests/fixtures/anim/): a node that turns and moves (with a child whose
//! scale is a cubic spline), a morph target, and a skinned cylinder.
//!
//! - At given times each renders the same image as its twin, the same scene posed statically
//!   in closed form (hybrid and raster graphs; ray-traced shadows follow the motion). Metric:
//!   the largest per-channel difference of the 8-bit images and the number of pixels that
//!   differ, bounded where the twin's f32 vertices round differently from the posed ones.
//! - One executor after N frames of animation gives the image of a fresh executor at that time.
//! - Every back-end and layout after 100 frames of a skinned animation (the merged layout
//!   refitted each frame) agrees with the f64 reference caster on primary visibility and sun
//!   shadows, except within the reference's margin (as in `raygraph selftest`).
//! - The cache refits a deforming mesh while the tree's SAH cost stays within the policy's
//!   growth, and rebuilds past it; a still scene is never refitted.
//! - Bad input: a missing sampler, an out-of-range joint, a NaN keyframe and an output count
//!   that does not match fail with errors naming the file and what is wrong; weights that do
//!   not sum to one are repaired and counted.

mod common;

use common::{gpu, repo};
use glam::Vec3;
use raygraph::accel::cache::BuildReport;
use raygraph::accel::deform::RefitPolicy;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{Camera, LoadOptions, Scene};
use std::path::Path;

const SIZE: (u32, u32) = (160, 120);

fn load(path: &Path) -> Scene {
    raygraph::scene::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}")).0
}

fn animated(name: &str) -> Scene {
    load(&repo().join(format!("assets/gltf/animated/{name}.gltf")))
}

fn twin(name: &str, time: f32) -> Scene {
    load(&repo().join(format!("tests/fixtures/anim/{name}_static_{time}.gltf")))
}

fn camera() -> Camera {
    Camera { position: Vec3::new(2.0, 4.0, 7.5), target: Vec3::new(0.5, 0.8, 0.0), fov_y: 45f32.to_radians(), ..Camera::default() }
}

fn executor(gpu: &Gpu, graph: &str, backend: Option<Backend>, scene: &Scene) -> Executor {
    let graph = repo().join(graph);
    let options = CompileOptions { reuse: false, ..backend.map_or_else(|| gpu.compile_options(), |b| gpu.compile_options_for(b)) };
    let plan = compile_with(&graph, &Project::beside_graph(&graph), SIZE, &options).unwrap_or_else(|e| panic!("{e}"));
    Executor::new(gpu, plan, scene).unwrap()
}

fn image(gpu: &Gpu, exec: &mut Executor, scene: &Scene) -> Vec<u8> {
    exec.render(gpu, &camera(), scene).unwrap();
    exec.read_output(gpu).unwrap().into_raw()
}

/// The largest channel difference and the pixels that differ at all.
fn difference(a: &[u8], b: &[u8]) -> (u8, usize) {
    let largest = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
    let pixels = a.chunks(4).zip(b.chunks(4)).filter(|(x, y)| x != y).count();
    (largest, pixels)
}

#[test]
fn posed_scenes_render_as_their_static_twins() {
    let gpu = gpu();
    let cases = [("spinner", [0.7, 2.6]), ("morph", [0.3, 1.6]), ("skinned_cylinder", [0.5, 1.25])];
    for (name, times) in cases {
        let mut images = Vec::new();
        for time in times {
            let mut scene = animated(name);
            let clip = scene.rig().unwrap().clip(&Default::default()).unwrap();
            scene.pose(clip, time);
            let still = twin(name, time);
            for graph in ["graph/hybrid.ron", "graph/raster.ron"] {
                let a = image(&gpu, &mut executor(&gpu, graph, None, &scene), &scene);
                let b = image(&gpu, &mut executor(&gpu, graph, None, &still), &still);
                let (largest, pixels) = difference(&a, &b);
                println!("{name} at {time} s, {graph}: largest difference {largest}, {pixels} of {} pixels differ", a.len() / 4);
                // Measured on lavapipe: identical. (The twins' vertices are the closed-form poses
                // rounded to f32 once, the posed scene's come from f32 joint matrices and slerps;
                // at these poses they round to the same pixels.)
                assert_eq!(pixels, 0, "{name} at {time} s, {graph}: largest difference {largest}");
                images.push(a);
            }
        }
        // Not vacuous: the two times differ (hybrid: the object and its ray-traced shadow).
        let (_, moved) = difference(&images[0], &images[2]);
        println!("{name}: {moved} pixels differ between {} s and {} s", times[0], times[1]);
        assert!(moved > 200, "{name}: the animation moves something in view");
    }
}

#[test]
fn an_executor_after_frames_of_animation_renders_as_a_fresh_one() {
    let gpu = gpu();
    for (name, on_gpu) in [("spinner", false), ("skinned_cylinder", false), ("skinned_cylinder", true), ("morph", true)] {
        let mut scene = animated(name);
        let clip = Some(0);
        let mut exec = executor(&gpu, "graph/hybrid.ron", None, &scene);
        let mut last = Vec::new();
        for frame in 0..12 {
            if on_gpu {
                scene.pose_for_gpu(clip, 0.13 * frame as f32);
            } else {
                scene.pose(clip, 0.13 * frame as f32);
            }
            last = image(&gpu, &mut exec, &scene);
        }
        let report = exec.accel().map(|a| a.refit_policy());
        println!("{name}: policy {report:?}");
        let fresh = image(&gpu, &mut executor(&gpu, "graph/hybrid.ron", None, &scene), &scene);
        let (largest, pixels) = difference(&last, &fresh);
        println!(
            "{name} (deformed on the {}): after 12 frames, {pixels} pixels differ from a fresh executor (largest {largest})",
            if on_gpu { "GPU" } else { "CPU" }
        );
        // A refitted tree holds the same triangles as a built one: every hit and shadow ray
        // finds the same answer, so the images are identical.
        assert_eq!(pixels, 0, "{name}: largest difference {largest}");
    }
}

#[test]
fn bad_animation_data_fails_with_errors_naming_the_file() {
    let cases = [
        ("bad_missing_sampler", "animations[0].channels[0].sampler"),
        ("bad_joint_index", "vertex 5: JOINTS_0 names joint 9, but the skin has 2 joints"),
        ("bad_nan_keyframe", "animation `spin` channel 1: keyframe value 4 (key 1) is NaN"),
        ("bad_output_count", "animation `breathe` channel 0: the sampler's output accessor 9 has 5 elements, but 3 key times need 6"),
    ];
    for (file, expected) in cases {
        let path = repo().join(format!("tests/fixtures/anim/{file}.gltf"));
        let err = raygraph::scene::open(path.to_str().unwrap(), &LoadOptions::default()).err().unwrap_or_else(|| panic!("{file} loads")).to_string();
        println!("{file}: {err}");
        assert!(err.contains(path.to_str().unwrap()) && err.contains(expected), "{file}: {err}");
    }
    let path = repo().join("tests/fixtures/anim/repair_weights.gltf");
    let (scene, report) = raygraph::scene::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap();
    assert_eq!(report.rig_repairs.renormalised_weights, 1);
    assert!(report.warnings.iter().any(|w| w.contains("1 vertices' skin weights did not sum to one")), "{:?}", report.warnings);
    let skin = scene.rig().unwrap().deformers[0].skin.as_ref().unwrap();
    assert_eq!(&skin.weights[..4], &[0.5, 0.5, 0.0, 0.0], "vertex 0's weights (2, 2) normalised");
}

#[test]
fn clips_are_chosen_by_name_or_index_and_loop() {
    use raygraph::scene::animation::{ClipChoice, ClipSet};
    let scene = animated("spinner");
    let rig = scene.rig().unwrap();
    assert_eq!(rig.clip(&"hop".parse::<ClipChoice>().unwrap()), Ok(ClipSet::One(1)));
    assert_eq!(rig.clip(&"0".parse::<ClipChoice>().unwrap()), Ok(ClipSet::One(0)));
    let err = rig.clip(&"walk".parse::<ClipChoice>().unwrap()).unwrap_err();
    assert!(err.contains("no animation named `walk`") && err.contains("`spin` (2.00 s)") && err.contains("`hop`"), "{err}");
    let spinner_node = rig.nodes.iter().position(|n| n.name == "spinner").unwrap();
    // STEP: the box is at y 2 from 0.5 s to 1 s; the clip loops every second.
    assert_eq!(rig.pose(Some(1), 0.7).world[spinner_node].w_axis.y, 2.0);
    assert_eq!(rig.pose(Some(1), 1.7).world[spinner_node].w_axis.y, 2.0);
    assert_eq!(rig.pose(Some(1), 0.2).world[spinner_node].w_axis.y, 1.0);
    assert_eq!(rig.clip(&"all".parse::<ClipChoice>().unwrap()), Ok(ClipSet::All));
    assert_eq!(rig.duration(ClipSet::All), 2.0, "the longest clip's length");
}

/// The build reports of `frames` frames of `scene`'s first clip (`step` seconds apart) on the
/// merged compute layout under `policy`.
fn reports(gpu: &Gpu, scene: &mut Scene, policy: RefitPolicy, frames: usize, step: f32) -> Vec<BuildReport> {
    let mut exec = executor(gpu, "graph/hybrid.ron", Some(Backend::Compute), scene);
    exec.accel_mut().unwrap().set_refit_policy(policy);
    (0..frames)
        .map(|f| {
            scene.pose_for_gpu(Some(0), step * f as f32);
            exec.render(gpu, &camera(), scene).unwrap().accel.unwrap()
        })
        .collect()
}

#[test]
fn the_cache_refits_deforming_meshes_until_the_tree_degrades() {
    let gpu = gpu();
    let mut scene = animated("skinned_cylinder");
    // Always refit: every frame after the first refits; the SAH growth is measured from the
    // second refit on (each refit's cost is read after its frame).
    let always = reports(&gpu, &mut scene, RefitPolicy::AlwaysRefit, 12, 0.08);
    for (f, r) in always.iter().enumerate() {
        println!("always refit, frame {f}: {}", r.describe());
    }
    assert_eq!(always[0].tlas, raygraph::accel::cache::TlasWork::Rebuild);
    assert!(always[1..].iter().all(|r| r.blas_refit && r.deformed_meshes == 1), "every later frame refits the bent cylinder");
    let growth: Vec<f64> = always[2..].iter().map(|r| r.sah_growth.unwrap()).collect();
    assert!(growth.last().unwrap() > &1.05, "bending the cylinder 80 degrees degrades the refitted tree: {growth:?}");
    // A threshold below what the bend reaches: rebuilt for quality, then refitted again.
    let auto = reports(&gpu, &mut scene, RefitPolicy::Auto { max_growth: 1.05 }, 12, 0.08);
    let rebuilt: Vec<usize> = (0..auto.len()).filter(|&f| auto[f].rebuilt_for_quality).collect();
    println!("auto (x1.05): rebuilt for quality at frames {rebuilt:?}");
    assert!(!rebuilt.is_empty() && auto.iter().filter(|r| r.blas_refit).count() > rebuilt.len(), "{rebuilt:?}");
    // Always rebuild: no refit.
    assert!(reports(&gpu, &mut scene, RefitPolicy::AlwaysRebuild, 4, 0.08).iter().all(|r| !r.blas_refit));
    // A still pose: nothing to do after the first frame; a refit right after a build keeps
    // the builder's SAH cost (the probe measures what the builder reported).
    let still = reports(&gpu, &mut scene, RefitPolicy::AlwaysRefit, 3, 0.0);
    assert!(!still[1].built_anything() && !still[2].built_anything());
    let mut exec = executor(&gpu, "graph/hybrid.ron", Some(Backend::Compute), &scene);
    scene.pose(Some(0), 0.0);
    exec.render(&gpu, &camera(), &scene).unwrap();
    let mut moved = scene.clone();
    moved.instances_mut()[0].transform = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 1e-3)) * moved.instances()[0].transform;
    exec.render(&gpu, &camera(), &moved).unwrap();
    exec.render(&gpu, &camera(), &moved).unwrap();
    let g = exec.accel().unwrap().sah_growth().unwrap();
    assert!((g - 1.0).abs() < 1e-3, "the ground moved by 1e-3: SAH x{g}");
}

/// Primary hits and sun shadows of `exec`'s last frame against the f64 reference of `scene`:
/// (compared, disagreements outside the reference's margin, pixels that hit the cylinder).
fn against_reference(gpu: &Gpu, exec: &Executor, scene: &Scene, camera: &Camera, size: (u32, u32)) -> (usize, usize, usize) {
    use raygraph::accel::reference_render::{ReferenceRenderer, SurfacePoint};
    const MARGIN: f64 = 1e-5; // as raygraph selftest's reference channels (src/selftest/channels.rs)
    let renderer = ReferenceRenderer::new(scene);
    let rays = ReferenceRenderer::camera_rays(camera, size);
    let visibility = renderer.visibility(&rays);
    let (pos, geo, normal, shadow) = (
        common::channel(gpu, exec, "gbuffer.position"),
        common::channel(gpu, exec, "gbuffer.geo_normal"),
        common::channel(gpu, exec, "gbuffer.normal"),
        common::channel(gpu, exec, "shadow.shadow"),
    );
    let (mut compared, mut wrong, mut cylinder) = (0, 0, 0);
    for (i, ray) in rays.iter().enumerate() {
        let r = &visibility[i];
        let agree = match (pos[i][3] != 0.0, r.value) {
            (false, None) => true,
            (true, Some(h)) => {
                cylinder += (h.instance_id == 1) as usize;
                let at = ray.origin.as_dvec3() + h.t * ray.dir.as_dvec3();
                (Vec3::new(pos[i][0], pos[i][1], pos[i][2]).as_dvec3() - at).length() <= 1e-4 * h.t
            }
            _ => false,
        };
        compared += 1;
        wrong += (!agree && r.margin >= MARGIN) as usize;
    }
    let xyz = |v: [f32; 4]| Vec3::new(v[0], v[1], v[2]);
    let surfaces: Vec<Option<SurfacePoint>> = (0..pos.len())
        .map(|i| (pos[i][3] != 0.0).then(|| SurfacePoint { position: xyz(pos[i]), geo_normal: xyz(geo[i]), normal: xyz(normal[i]), shadow_offset: geo[i][3] }))
        .collect();
    for (i, s) in renderer.shadow(&surfaces, scene.light(), None).iter().enumerate() {
        let Some(s) = s else { continue };
        compared += 1;
        wrong += ((shadow[i][0] == 1.0) != s.sun.value && s.sun.margin >= MARGIN) as usize;
    }
    (compared, wrong, cylinder)
}

#[test]
fn every_back_end_agrees_with_the_f64_reference_after_100_refit_frames() {
    use raygraph::selftest::VARIANTS;
    let gpu = gpu();
    let size = (64, 48);
    let camera = Camera { position: Vec3::new(1.6, 1.6, 3.2), target: Vec3::new(0.6, 1.0, 0.0), fov_y: 50f32.to_radians(), ..Camera::default() };
    let shipped = std::fs::read_to_string(repo().join("graph/full_rt.ron")).unwrap();
    let p = common::TempProject::with_repo_files();
    let merged = p.write("graph/anim_merged.ron", &shipped);
    let two_level = p.write("graph/anim_two_level.ron", &shipped.replace("Accel(merge: true)", "Accel()"));
    assert_ne!(std::fs::read_to_string(&two_level).unwrap(), shipped, "graph/full_rt.ron merges: the two-level copy must differ");
    for variant in VARIANTS {
        let mut scene = animated("skinned_cylinder");
        scene.pose(Some(0), 0.0);
        let graph = if variant.merge { &merged } else { &two_level };
        let options = CompileOptions { reuse: false, ..gpu.compile_options_for(variant.backend) };
        let plan = compile_with(graph, &p.project(), size, &options).unwrap_or_else(|e| panic!("{e}"));
        let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
        if let Some(cache) = exec.accel_mut() {
            cache.set_refit_policy(RefitPolicy::AlwaysRefit);
        }
        let mut refits = 0;
        for frame in 0..=100 {
            // 100 frames over the clip's bend up and back (2 s) and on into the next loop.
            scene.pose_for_gpu(Some(0), 0.023 * frame as f32);
            let t = exec.render(&gpu, &camera, &scene).unwrap();
            refits += t.accel.as_ref().is_some_and(|r| r.blas_refit || r.blas_refits > 0) as usize;
        }
        let (compared, wrong, cylinder) = against_reference(&gpu, &exec, &scene.with_meshes_posed(), &camera, size);
        println!(
            "{}: {refits} refits; {compared} primary and shadow answers compared, {wrong} outside the margin; {cylinder} pixels see the cylinder",
            variant.name
        );
        assert!(cylinder > 100, "{}: the cylinder is in view", variant.name);
        assert_eq!(wrong, 0, "{}", variant.name);
        if variant.backend == Backend::Compute {
            // The merged layout refits on the GPU, the two-level one the cylinder's BLAS on the
            // CPU; the driver back-ends rebuild (wgpu has no refit).
            assert_eq!(refits, 100, "{}: a refit every frame after the first", variant.name);
        }
    }
}

/// The skinned cylinder with a morph target too (every vertex displaced along x by up to 0.1,
/// weight 0.7 from its node): a mesh whose frame data holds both joint matrices and weights.
fn skinned_and_morphed() -> Scene {
    use raygraph::scene::animation::MorphTarget;
    let mut scene = animated("skinned_cylinder");
    let mut rig = (**scene.rig().unwrap()).clone();
    let deformer = &mut rig.deformers[0];
    let positions = deformer.rest.iter().map(|v| Vec3::new(0.1 * v.position[1] / 2.0, 0.0, 0.0)).collect();
    deformer.targets.push(MorphTarget { positions, normals: None });
    rig.nodes[deformer.node].weights = vec![0.7];
    scene.set_rig(Some(std::sync::Arc::new(rig)));
    scene
}

/// The GPU deformation (`shaders/anim/deform.wgsl`) against the CPU's (`Deformer::deform`):
/// skinned and morphed vertices, positions and normals, at several times. Tolerance: 4 ulps of
/// the largest coordinate for positions, 1e-5 for unit normals (the GPU may fuse the
/// joint-matrix sums and products); measured below.
#[test]
fn gpu_deformation_matches_the_cpu_reference() {
    use raygraph::accel::gpu_build::read_bytes;
    let gpu = gpu();
    for name in ["skinned_cylinder", "morph", "skinned and morphed"] {
        let mut scene = if name == "skinned and morphed" { skinned_and_morphed() } else { animated(name) };
        let mut exec = executor(&gpu, "graph/hybrid.ron", None, &scene);
        let (mut worst_p, mut worst_n) = (0.0f32, 0.0f32);
        for time in [0.2f32, 0.7, 1.45] {
            scene.pose_for_gpu(Some(0), time);
            exec.render(&gpu, &camera(), &scene).unwrap();
            let cpu = scene.with_meshes_posed();
            let uploaded = exec.uploaded_scene().unwrap();
            let bytes = read_bytes(gpu.device(), gpu.queue(), uploaded.vertices().unwrap(), 0, uploaded.vertices().unwrap().size()).unwrap();
            let gpu_vertices: &[raygraph::scene::Vertex] = bytemuck::cast_slice(&bytes);
            let mut base = 0;
            for (m, mesh) in cpu.meshes().iter().enumerate() {
                let deforming = scene.deforming_meshes().contains(&m);
                for (k, v) in mesh.vertices.iter().enumerate() {
                    let g = gpu_vertices[base + k];
                    let scale = v.position.iter().fold(1.0f32, |a, c| a.max(c.abs()));
                    let dp = (0..3).map(|c| (g.position[c] - v.position[c]).abs()).fold(0.0, f32::max) / scale;
                    let dn = (0..3).map(|c| (g.normal[c] - v.normal[c]).abs()).fold(0.0, f32::max);
                    if deforming {
                        worst_p = worst_p.max(dp);
                        worst_n = worst_n.max(dn);
                    } else {
                        assert_eq!(g, *v, "{name}: mesh {m} does not deform and keeps its vertices");
                    }
                }
                base += mesh.vertices.len();
            }
            let rest = &scene.rig().unwrap().deformers[0].rest;
            let moved = cpu.meshes()[scene.deforming_meshes()[0]].vertices.iter().zip(rest).filter(|(a, b)| a.position != b.position).count();
            assert!(moved > 10, "{name} at {time} s: the pose moves vertices ({moved})");
        }
        println!("{name}: GPU against CPU deformation: positions within {worst_p:.2e} of the largest coordinate, normals within {worst_n:.2e}");
        assert!(worst_p <= 4.0 * f32::EPSILON && worst_n <= 1e-5, "{name}: {worst_p} {worst_n}");
    }
}

/// A scene that does not move pays for none of this: no deformation pass, a vertex buffer
/// neither rewritable nor writable by shaders beyond what the plan asks for, and after the
/// first frame no acceleration-structure work at all; an animated file with only node motion
/// makes no deformation either.
#[test]
fn a_static_scene_pays_nothing() {
    let gpu = gpu();
    for (name, mut scene) in [("default", raygraph::scene::builtin::default_scene()), ("spinner (nodes only)", animated("spinner"))] {
        let mut exec = executor(&gpu, "graph/hybrid.ron", Some(Backend::Compute), &scene);
        let vertices = exec.uploaded_scene().unwrap().vertices().unwrap().usage();
        assert!(!vertices.contains(wgpu::BufferUsages::COPY_DST), "{name}: {vertices:?}");
        let reports: Vec<BuildReport> = (0..3)
            .map(|_| {
                scene.pose_for_gpu(Some(0), 0.5);
                exec.render(&gpu, &camera(), &scene).unwrap().accel.unwrap()
            })
            .collect();
        assert!(reports[1..].iter().all(|r| !r.built_anything() && r.deformed_meshes == 0), "{name}: {reports:?}");
    }
}
