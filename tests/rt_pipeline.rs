//! The rt-pipeline back-end's interop with wgpu (src/accel/rt_pipeline.rs): its traces are
//! recorded through wgpu-hal into command buffers wgpu does not see into, between wgpu's own.
//! Every texture a trace reads is written by wgpu in the same submission (the G-buffer), every
//! texture it writes is read by wgpu after it (resolve), and in full RT one trace reads what
//! another wrote. Checked against the `compute` back-end, which wgpu tracks itself: the first
//! frame (where wgpu would zero-fill textures it never saw written), every trace channel, later
//! frames, and a moved instance (the TLAS rebuilt and bound again). Runs under the validation
//! layer in CI (README's test command), which also reports objects left undestroyed.

mod common;

use raygraph::accel::rt_pipeline::live_hal_objects;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::default_scene;
use raygraph::scene::Scene;

const SIZE: (u32, u32) = (96, 64);

/// The tests of this file run one at a time: `live_hal_objects` counts the whole process.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    assert!(gpu.backends().contains(&Backend::RtPipeline), "lavapipe >= 24.1 has ray-tracing pipelines; CI must test the rt-pipeline back-end");
    gpu
}

fn executor(gpu: &Gpu, graph: &str, backend: Backend, scene: &Scene) -> Executor {
    let graph = common::repo().join(graph);
    let plan = compile_with(&graph, &Project::beside_graph(&graph), SIZE, &gpu.compile_options_for(backend)).unwrap();
    Executor::new(gpu, plan, scene).unwrap()
}

/// Every texture of the frame the graph keeps, by resource name, as f32 texels.
fn channels(gpu: &Gpu, exec: &Executor, names: &[&str]) -> Vec<(String, Vec<[f32; 4]>)> {
    names
        .iter()
        .map(|name| {
            let r = exec.plan().resources().iter().position(|r| r.name == *name).unwrap_or_else(|| panic!("no resource {name}"));
            (name.to_string(), exec.read_texture_f32(gpu, r).unwrap().2)
        })
        .collect()
}

/// Largest absolute difference between two channels.
fn max_diff(a: &[[f32; 4]], b: &[[f32; 4]]) -> f32 {
    a.iter().zip(b).flat_map(|(x, y)| (0..4).map(move |k| (x[k] - y[k]).abs())).fold(0.0, f32::max)
}

/// RMSE over RGB in 8-bit units and the number of pixels off by more than 24 in a channel.
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (f64, usize) {
    let mut sum = 0.0;
    let mut outliers = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d: Vec<f64> = (0..3).map(|k| p.0[k] as f64 - q.0[k] as f64).collect();
        sum += d.iter().map(|x| x * x).sum::<f64>();
        outliers += d.iter().any(|x| x.abs() > 24.0) as usize;
    }
    ((sum / (3 * a.pixels().len()) as f64).sqrt(), outliers)
}

/// Metric, on the first frame and the next two: shadow and AO equal to compute's texel for
/// texel (the same any-hit answers: tests/reference_channels.rs shows both exact per pixel);
/// G-buffer and reflection channels within CHANNEL_TOLERANCES (the driver's t and barycentrics
/// differ from compute's in the last bits); the 8-bit output within RMSE 0.02 and no pixel
/// off by more than 24; every channel non-zero somewhere (nothing zero-filled). Measured on
/// lavapipe (Mesa 25.0.7), 2026-11-29: positions 1.24e-5, normals and reflections 2.44e-4 (one
/// half-float step at 1), output RMSE 0.007 (full RT) and 0 (hybrid), no outlier; every bound
/// is 3x its measured value.
/// The largest |rt-pipeline - compute| of each channel compared (see the test below).
const CHANNEL_TOLERANCES: [(&str, f32); 5] =
    [("shadow.shadow", 0.0), ("ao.ao", 0.0), ("gbuffer.position", 4e-5), ("gbuffer.normal", 7.5e-4), ("reflection.reflection", 7.5e-4)];

#[test]
fn the_first_and_later_frames_match_compute_in_hybrid_and_full_rt() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = gpu();
    let scene = default_scene();
    for (graph, names) in [
        ("graph/hybrid.ron", &["shadow.shadow", "ao.ao", "reflection.reflection"][..]),
        ("graph/full_rt.ron", &["gbuffer.position", "gbuffer.normal", "shadow.shadow", "ao.ao", "reflection.reflection"][..]),
    ] {
        let mut compute = executor(&gpu, graph, Backend::Compute, &scene);
        let mut rt = executor(&gpu, graph, Backend::RtPipeline, &scene);
        for frame in 0..3 {
            let tc = compute.render(&gpu, scene.camera(), &scene).unwrap();
            let tr = rt.render(&gpu, scene.camera(), &scene).unwrap();
            assert_eq!(tc.rays.unwrap().traced(), tr.rays.unwrap().traced(), "{graph} frame {frame}: the same rays");
            assert_eq!(tc.rays.unwrap().hits, tr.rays.unwrap().hits, "{graph} frame {frame}: the same hits");
            for ((name, a), (_, b)) in channels(&gpu, &compute, names).iter().zip(channels(&gpu, &rt, names)) {
                let d = max_diff(a, &b);
                let lit = b.iter().filter(|t| t.iter().any(|c| *c != 0.0)).count();
                println!("{graph} frame {frame} {name}: max |rt-pipeline - compute| {d:e}, {lit} non-zero texels");
                let tolerance = CHANNEL_TOLERANCES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t).unwrap();
                assert!(d <= tolerance, "{graph} frame {frame}: {name} differs by {d}");
                assert!(lit > 0, "{graph} frame {frame}: {name} is all zero on rt-pipeline");
            }
            let (rmse, outliers) = difference(&compute.read_output(&gpu).unwrap(), &rt.read_output(&gpu).unwrap());
            println!("{graph} frame {frame} output: RMSE {rmse:.3}, {outliers} outlier pixels");
            assert!(rmse <= 0.02 && outliers == 0, "{graph} frame {frame}: RMSE {rmse}, {outliers} outliers");
        }
    }
}

/// Moved instances: the acceleration structure is built again and bound again, and the
/// picture follows the scene as compute's does, frame after frame, in one executor. Two levels
/// (`Accel()`: a new TLAS, no BLAS) and the merged layout (`Accel(merge: true)`, the hybrid
/// graph's: one BLAS over the world-space triangles, rebuilt).
#[test]
fn a_moving_instance_is_followed_frame_by_frame() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = gpu();
    let p = common::TempProject::with_repo_files();
    let hybrid = std::fs::read_to_string(common::repo().join("graph/hybrid.ron")).unwrap();
    assert!(hybrid.contains("Accel(merge: true)"), "graph/hybrid.ron changed: update the test");
    p.write("graph/two_level.ron", &hybrid.replace("Accel(merge: true)", "Accel()"));
    for (graph, merged) in [(p.root.join("graph/two_level.ron"), false), (common::repo().join("graph/hybrid.ron"), true)] {
        let mut scene = default_scene();
        let open = |backend| {
            let plan = compile_with(&graph, &Project::beside_graph(&graph), SIZE, &gpu.compile_options_for(backend)).unwrap();
            Executor::new(&gpu, plan, &scene).unwrap()
        };
        let (mut compute, mut rt) = (open(Backend::Compute), open(Backend::RtPipeline));
        let first = rt.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        assert_eq!(first.blas_built, if merged { 1 } else { scene.meshes().len() }, "the first frame builds every BLAS");
        let accel_pass = rt.plan().passes().iter().position(|p| p.kind == raygraph::graph::desc::PassKind::AccelBuild).unwrap();
        let mut outputs = Vec::new();
        let mut build_ms = Vec::new();
        for step in 0..3 {
            scene.instances_mut()[0].transform = glam::Mat4::from_translation(glam::vec3(0.3 * (step + 1) as f32, 0.0, 0.0)) * scene.instances()[0].transform;
            compute.render(&gpu, scene.camera(), &scene).unwrap();
            let t = rt.render(&gpu, scene.camera(), &scene).unwrap();
            build_ms.push(t.gpu_ms.as_ref().map(|ms| ms[accel_pass]).unwrap());
            let accel = t.accel.unwrap();
            let expected = if merged { 1 } else { 0 };
            assert_eq!(accel.blas_built, expected, "{} step {step}: an instance moved", graph.display());
            let (a, b) = (compute.read_output(&gpu).unwrap(), rt.read_output(&gpu).unwrap());
            let (rmse, outliers) = difference(&a, &b);
            println!("{} step {step}: RMSE {rmse:.3}, {outliers} outliers against compute", graph.display());
            assert!(rmse <= 1.0 && outliers * 1000 <= (SIZE.0 * SIZE.1) as usize, "{} step {step}: RMSE {rmse}, {outliers} outliers", graph.display());
            outputs.push(b);
        }
        assert!(outputs.windows(2).all(|w| w[0] != w[1]), "the picture changes as the instance moves");
        // The build runs between the `Accel` node's timestamps: a frame that builds takes
        // longer there than one that does not (asserted where a BLAS of 4,430 triangles is
        // built, 7x the empty pass on lavapipe; two levels rebuild only a 3-instance TLAS).
        let still_ms = (0..3).map(|_| rt.render(&gpu, scene.camera(), &scene).unwrap().gpu_ms.unwrap()[accel_pass]).fold(f64::INFINITY, f64::min);
        println!("{}: accel GPU ms with a build {build_ms:?}, without {still_ms}", graph.display());
        build_ms.sort_by(f64::total_cmp);
        assert!(!merged || build_ms[1] > still_ms, "{}: the build is not inside the Accel node's timestamps", graph.display());
    }
}

/// Executors made, changed and dropped leave no object made through wgpu-hal behind
/// (`rt_pipeline::live_hal_objects` back where it was; in CI the validation layer also reports
/// any Vulkan object left when the device goes): two levels with a mesh and its instances
/// removed between frames (fewer BLAS), the merged layout, a graph compiled again, and a batch
/// tracer; and a new executor draws what the first drew.
#[test]
fn executors_come_and_go_without_leaks() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = gpu();
    let before = live_hal_objects();
    let p = common::TempProject::with_repo_files();
    let ao = std::fs::read_to_string(common::repo().join("graph/ao.ron")).unwrap();
    p.write("graph/ao_two_level.ron", &ao.replace("Accel(merge: true)", "Accel()"));
    let two_level = p.root.join("graph/ao_two_level.ron");
    let mut first = None;
    for round in 0..3 {
        let mut scene = default_scene();
        let graph = if round == 1 { common::repo().join("graph/ao.ron") } else { two_level.clone() };
        let plan = compile_with(&graph, &Project::beside_graph(&graph), SIZE, &gpu.compile_options_for(Backend::RtPipeline)).unwrap();
        let mut rt = Executor::new(&gpu, plan, &scene).unwrap();
        rt.render(&gpu, scene.camera(), &scene).unwrap();
        let image = rt.read_output(&gpu).unwrap();
        assert!(first.get_or_insert_with(|| image.clone()) == &image, "a new executor draws another picture");
        // The last mesh and its instances go: one BLAS fewer.
        let last = scene.meshes().len() - 1;
        scene.instances_mut().retain(|i| i.mesh != last);
        scene.pop_mesh();
        let t = rt.render(&gpu, scene.camera(), &scene).unwrap();
        assert!(t.rays.unwrap().traced() > 0);
        assert!(live_hal_objects() > before, "the executor holds hal objects");
    }
    let tracer = raygraph::runtime::batch::BatchTracer::new(&gpu, Backend::RtPipeline, &default_scene(), &common::repo().join("shaders")).unwrap();
    let (hits, _) =
        tracer.closest(&gpu, &[raygraph::runtime::batch::GpuRay { origin: [0.0, 50.0, 0.0], t_min: 0.0, dir: [0.0, -1.0, 0.0], t_max: 1e30 }]).unwrap();
    assert_eq!(hits.len(), 1);
    drop(tracer);
    assert_eq!(live_hal_objects(), before, "objects made through wgpu-hal were left behind");
}
