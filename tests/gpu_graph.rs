//! Graphs executed on the GPU (lavapipe in CI): culling is visible in the plan and on the
//! GPU, texture reuse saves memory and renders the same image.

mod common;
use common::fixtures;
use raygraph::graph::compile::{compile_with, CompileOptions};
use raygraph::graph::desc::PassKind;
use raygraph::graph::{compile, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::default_scene;

const W: u32 = 37; // not a multiple of the 8x8 workgroup: edge handling is exercised
const H: u32 = 21;

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required for GPU tests");
    println!("adapter: {}", gpu.describe());
    gpu
}

fn chain_project() -> (std::path::PathBuf, Project) {
    let file = fixtures().join("graph/chain.ron");
    let project = Project::beside_graph(&file);
    (file, project)
}

#[test]
fn culled_pass_is_neither_allocated_nor_executed() {
    let (file, project) = chain_project();
    let plan = compile(&file, &project, (W, H)).unwrap();
    assert_eq!(plan.culled(), vec!["unused/fill".to_string()]);
    assert!(plan.passes().iter().all(|p| p.node != "unused"));
    let unused = plan.resource_by_name("unused.color").unwrap();
    assert!(!plan.is_kept(unused), "the culled pass's output must not be allocated");
    assert!(plan.slots().iter().all(|s| !s.members.contains(&unused)));
    assert!(!plan.scene_usage().any(), "a graph that reads no scene data uploads no scene");

    let gpu = gpu();
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    let counters = exec.read_debug_counters(&gpu).unwrap();
    let pixels = W * H;
    assert_eq!(counters[0], pixels, "fill ran once per pixel");
    assert_eq!(counters[1], pixels, "first invert ran once per pixel");
    assert_eq!(counters[2], pixels, "second invert ran once per pixel");
    assert_eq!(counters[5], 0, "the culled pass must not run on the GPU");
}

#[test]
fn texture_reuse_saves_memory_and_renders_the_same_image() {
    let (file, project) = chain_project();
    let reused = compile_with(&file, &project, (W, H), &CompileOptions { reuse: true, ..Default::default() }).unwrap();
    let separate = compile_with(&file, &project, (W, H), &CompileOptions { reuse: false, ..Default::default() }).unwrap();
    assert!(reused.bytes_with_reuse() < separate.bytes_with_reuse(), "reuse must save memory");
    assert_eq!(reused.bytes_without_reuse(), separate.bytes_with_reuse());
    let fill = reused.resource_by_name("fill.color").unwrap();
    let b = reused.resource_by_name("b.dst").unwrap();
    assert_eq!(reused.resources()[fill].slot, reused.resources()[b].slot, "fill.color (passes 0..1) and b.dst (2..3) share a slot");
    let a = reused.resource_by_name("a.dst").unwrap();
    assert_ne!(reused.resources()[a].slot, reused.resources()[fill].slot, "overlapping lifetimes never share");

    let gpu = gpu();
    let scene = default_scene();
    let mut images = Vec::new();
    for plan in [reused, separate] {
        let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        images.push(exec.read_output(&gpu).unwrap());
    }
    assert_eq!(images[0].dimensions(), (W, H));
    // Exact equality: both plans run the same shaders on the same data.
    assert!(images[0].as_raw() == images[1].as_raw(), "reuse changed the image");
    // And the image is what the chain computes: fill then two inversions = fill.
    for (x, y, p) in images[0].enumerate_pixels() {
        let u = (x as f32 + 0.5) / W as f32 * 0.75;
        let v = (y as f32 + 0.5) / H as f32;
        let expect = [u, v, 0.25].map(|c| (c * 255.0).round() as i32);
        for c in 0..3 {
            // f16 storage and two 1-x round trips: within 2/255.
            assert!((p[c] as i32 - expect[c]).abs() <= 2, "pixel ({x},{y}) channel {c}: {} vs {}", p[c], expect[c]);
        }
    }
}

#[test]
fn every_pass_gets_a_gpu_timestamp_when_the_adapter_has_them() {
    let (file, project) = chain_project();
    let plan = compile(&file, &project, (W, H)).unwrap();
    let n = plan.passes().len();
    let gpu = gpu();
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    let t = exec.render(&gpu, scene.camera(), &scene).unwrap();
    assert_eq!(t.cpu_ms.len(), n);
    // lavapipe has timestamp queries; CI runs there, so this must hold.
    let gpu_ms = t.gpu_ms.expect("lavapipe reports timestamp queries");
    assert_eq!(gpu_ms.len(), n);
    assert!(gpu_ms.iter().all(|ms| ms.is_finite() && *ms >= 0.0), "{gpu_ms:?}");
}

/// A `Fullscreen` pass (a fragment per texel, vertex stage from `common/fullscreen.wgsl`)
/// writes exactly what the compute pass of the same conversion writes.
#[test]
fn a_fullscreen_pass_draws_what_the_compute_pass_writes() {
    let (file, _) = chain_project();
    let p = common::TempProject::new();
    let text = std::fs::read_to_string(&file).unwrap();
    let fs_graph = p.write("graph/chain_fs.ron", &text.replace(r#"layer: "to8""#, r#"layer: "to8_fullscreen""#));
    let gpu = gpu();
    let scene = default_scene();
    let mut images = Vec::new();
    for graph in [file, fs_graph] {
        let plan = compile(&graph, &Project::beside_graph(&graph), (W, H)).unwrap();
        let kinds: Vec<_> = plan.passes().iter().filter(|p| p.node == "out").map(|p| p.kind).collect();
        println!("{}: out pass {kinds:?}", graph.display());
        let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        images.push(exec.read_output(&gpu).unwrap());
    }
    assert_eq!(images[0].dimensions(), (W, H));
    assert!(images[0] == images[1], "the fragment and compute conversions differ");
}

/// Consecutive compute nodes recorded into one compute pass, timed by timestamps written
/// inside it (`Gpu::merges_compute_passes`, lavapipe has them), and one pass per node, the
/// fallback of a device without them (`RAYGRAPH_PASS_PER_NODE`): every node gets its GPU time
/// either way, every recorded dispatch a time of its own (a pass its `runs_when` left out, 0),
/// and the frames are the same to the byte.
#[test]
fn compute_nodes_merged_into_one_pass_keep_a_gpu_time_each_and_the_image() {
    let mut gpu = gpu();
    let path = common::repo().join("graph/hybrid_denoised.ron");
    let scene = default_scene();
    let mut images = Vec::new();
    for merged in [true, false] {
        gpu.set_merge_compute_passes(merged);
        assert_eq!(gpu.merges_compute_passes(), merged, "lavapipe writes timestamps inside passes");
        let plan = compile_with(&path, &Project::beside_graph(&path), (W, H), &gpu.compile_options()).unwrap();
        let dispatches: Vec<bool> = plan.passes().iter().map(|p| matches!(p.kind, PassKind::Compute | PassKind::Trace)).collect();
        let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
        for frame in 0..3 {
            let t = exec.render(&gpu, scene.camera(), &scene).unwrap();
            let gpu_ms = t.gpu_ms.expect("lavapipe reports timestamp queries");
            assert_eq!((gpu_ms.len(), t.cpu_ms.len()), (dispatches.len(), dispatches.len()));
            assert!(gpu_ms.iter().all(|ms| ms.is_finite() && *ms >= 0.0), "merged {merged}, frame {frame}: {gpu_ms:?}");
            // An unwritten pair would resolve to zero: each recorded dispatch's pair is its own.
            // The passes a frame leaves out (the AO schedule `runs_when` did not pick) read 0.
            assert!(t.skipped.iter().any(|s| *s), "merged {merged}, frame {frame}: rt_ao runs one of its two schedules");
            for (k, ms) in gpu_ms.iter().enumerate().filter(|(k, _)| dispatches[*k]) {
                match t.skipped[k] {
                    false => assert!(*ms > 0.0, "merged {merged}, frame {frame}: pass {k} has no GPU time: {gpu_ms:?}"),
                    true => assert_eq!(*ms, 0.0, "merged {merged}, frame {frame}: pass {k} was left out: {gpu_ms:?}"),
                }
            }
        }
        images.push(exec.read_output(&gpu).unwrap().into_raw());
    }
    assert!(images[0] == images[1], "merging the compute nodes changed the image");
}
