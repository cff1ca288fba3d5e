//! The `Accel` node's cache through the executor, on both back-ends: no build work for an
//! unchanged scene, one BLAS for one edited mesh, the TLAS alone for a moved instance (refit in
//! `compute`), BLAS counts with and without de-duplication, nothing built for graphs that do
//! not trace; and `graph/ao.ron` drawing the same picture on both back-ends.

mod common;

use glam::{Mat4, Vec3};
use raygraph::accel::cache::TlasWork;
use raygraph::backend::Backend;
use raygraph::graph::compile::compile_with;
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::default_scene;

fn gpu() -> Gpu {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    println!("adapter: {}", gpu.describe());
    gpu
}

fn executor(gpu: &Gpu, graph: &std::path::Path, backend: Backend, size: (u32, u32)) -> Executor {
    let plan = compile_with(graph, &Project::beside_graph(graph), size, &gpu.compile_options_for(backend)).unwrap();
    Executor::new(gpu, plan, &default_scene()).unwrap()
}

#[test]
fn the_cache_builds_only_what_changed() {
    let gpu = gpu();
    let graph = common::repo().join("graph/ao.ron");
    for backend in Backend::ALL {
        let mut scene = default_scene();
        let mut exec = executor(&gpu, &graph, backend, (32, 24));
        let first = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        assert_eq!((first.blas_built, first.tlas), (scene.meshes().len(), TlasWork::Rebuild), "{backend}: the first frame builds everything");
        for _ in 0..4 {
            let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
            assert!(!r.built_anything(), "{backend}: an unchanged scene builds nothing: {r:?}");
        }
        // Edit one mesh (the sphere, used by two instances): one BLAS.
        scene.mesh_mut(2).vertices[5].position[1] += 0.05;
        let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        assert_eq!((r.blas_built, r.blas_reused, r.tlas), (1, scene.meshes().len() - 1, TlasWork::Rebuild), "{backend}: {r:?}");
        // Move one instance: the TLAS only.
        scene.instances_mut()[1].transform = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)) * scene.instances()[1].transform;
        let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        let expected = if backend == Backend::Compute { TlasWork::Refit } else { TlasWork::Rebuild };
        assert_eq!((r.blas_built, r.tlas), (0, expected), "{backend}: {r:?}");
        let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        assert!(!r.built_anything(), "{backend}: {r:?}");
        assert_eq!(exec.accel().unwrap().total_blas_builds(), scene.meshes().len() + 1);
        // The moved instance is where the rays now find it: the picture changed.
        println!("{backend}: {}", r.describe());
    }
}

#[test]
fn deduplication_shares_one_blas_per_mesh() {
    let gpu = gpu();
    let p = common::TempProject::with_repo_files();
    let text = std::fs::read_to_string(common::repo().join("graph/ao.ron")).unwrap();
    let scene = default_scene();
    for (dedup, expected) in [(true, scene.meshes().len()), (false, scene.instances().len())] {
        let graph = p.write("graph/ao.ron", &text.replace("Accel()", &format!("Accel(dedup: {dedup})")));
        for backend in Backend::ALL {
            let mut exec = executor(&gpu, &graph, backend, (16, 16));
            let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
            assert_eq!(r.blas_count, expected, "{backend}, dedup {dedup}: {r:?}");
            assert_eq!(r.blas_built, expected);
        }
    }
}

#[test]
fn graphs_that_do_not_trace_build_nothing() {
    let gpu = gpu();
    let exec = executor(&gpu, &common::repo().join("graph/raster.ron"), Backend::Compute, (16, 16));
    assert!(exec.accel().is_none(), "no Accel node, no cache");
    // An Accel node whose only reader is culled is culled with it.
    let p = common::TempProject::with_repo_files();
    // The output shows the G-buffer's normals; the ray-traced node feeds nothing that reaches it.
    let text = r#"Graph(
        output: "tonemap.color",
        nodes: {
            "gb": Layer(layer: "deferred"),
            "accel": Accel(),
            "rt": Layer(layer: "rt_ao", inputs: {"position": "gb.position", "geo_normal": "gb.geo_normal", "tlas": "accel.tlas"}),
            "tonemap": Layer(layer: "tonemap", inputs: {"hdr": "gb.normal"}),
        },
    )"#;
    let graph = p.write("graph/unused_rt.ron", text);
    let plan = compile_with(&graph, &Project::beside_graph(&graph), (16, 16), &gpu.compile_options()).unwrap();
    assert!(plan.culled().iter().any(|c| c == "accel/build") && plan.culled().iter().any(|c| c == "rt/ao"), "culled: {:?}", plan.culled());
    let scene = default_scene();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    assert!(exec.accel().is_none());
    assert!(exec.render(&gpu, scene.camera(), &scene).unwrap().rays.is_none());
}

/// Metric: the images are identical, byte for byte, between the back-ends (the same rays from
/// the same G-buffer), and in the tests below between layouts, builders and refit against
/// rebuild (as tests/animation.rs demands for the same claim). Measured on lavapipe (Mesa
/// 25.0.7), 2026-11-29: RMSE 0.000 and no outlier in every comparison of this file; a
/// driver whose hits at exact edges differ between back-ends would show it here first.
#[test]
fn the_ao_graph_draws_the_same_picture_on_every_back_end() {
    let gpu = gpu();
    let graph = common::repo().join("graph/ao.ron");
    let scene = default_scene();
    let mut images = Vec::new();
    let mut rays = Vec::new();
    for backend in Backend::ALL {
        let mut exec = executor(&gpu, &graph, backend, (96, 64));
        let t = exec.render(&gpu, scene.camera(), &scene).unwrap();
        rays.push(t.rays.unwrap());
        images.push(exec.read_output(&gpu).unwrap());
    }
    // Every back-end against `compute` (Backend::ALL[1]).
    let (a, b) = (&images[0], &images[1]);
    for (k, backend) in Backend::ALL.iter().enumerate().filter(|(_, b)| **b != Backend::Compute) {
        let (rmse, outliers) = difference(&images[k], b);
        println!("{backend} vs compute: RMSE {rmse:.3}, {outliers} outlier pixels; rays {:?} / {:?}", rays[k], rays[1]);
        assert!(rmse == 0.0 && outliers == 0, "{backend}: RMSE {rmse}, {outliers} outliers");
        assert_eq!(rays[k].traced(), rays[1].traced(), "{backend}: the same rays as on compute");
        assert!(rays[k].any > 0 && rays[k].hits > 0 && rays[k].invalid == 0);
    }
    // The effects are there: shadowed and occluded pixels exist.
    let distinct: std::collections::HashSet<[u8; 4]> = a.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 100);
}

/// RMSE over RGB in 8-bit units, and the pixels with a channel off by more than 24.
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (f64, usize) {
    let mut sq = 0.0;
    let mut outliers = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d: Vec<i32> = (0..3).map(|c| p[c] as i32 - q[c] as i32).collect();
        sq += d.iter().map(|x| (x * x) as f64).sum::<f64>();
        outliers += d.iter().any(|x| x.abs() > 24) as usize;
    }
    ((sq / (3.0 * a.width() as f64 * a.height() as f64)).sqrt(), outliers)
}

/// The merged layout (`Accel(merge: true)`, compute back-end): one BVH over every instance,
/// nothing built while the scene is unchanged, refitted on the GPU when instances move (the
/// picture of a fresh build of the moved scene), rebuilt when an instance is removed, and the
/// AO graph's picture as the two-level layout draws it (the metric above).
#[test]
fn the_merged_layout_rebuilds_on_change_and_draws_the_same_picture() {
    let gpu = gpu();
    let p = common::TempProject::with_repo_files();
    let text = std::fs::read_to_string(common::repo().join("graph/ao.ron")).unwrap();
    let merged_graph = p.write("graph/ao_merged.ron", &text.replace("Accel()", "Accel(merge: true)"));
    let mut scene = default_scene();
    let mut images = Vec::new();
    for graph in [common::repo().join("graph/ao.ron"), merged_graph.clone()] {
        let mut exec = executor(&gpu, &graph, Backend::Compute, (96, 64));
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        images.push(exec.read_output(&gpu).unwrap());
    }
    let (rmse, outliers) = difference(&images[0], &images[1]);
    println!("two levels vs merged: RMSE {rmse:.3}, {outliers} outlier pixels");
    assert!(rmse == 0.0 && outliers == 0, "RMSE {rmse}, {outliers} outliers");

    let mut exec = executor(&gpu, &merged_graph, Backend::Compute, (32, 24));
    let first = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
    assert_eq!((first.blas_count, first.blas_built, first.tlas), (1, 1, TlasWork::Rebuild), "{first:?}");
    let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
    assert!(!r.built_anything(), "an unchanged scene builds nothing: {r:?}");
    // Moved instances: refitted on the GPU, nothing built; the picture is the one a fresh
    // build of the moved scene draws (same metric), after one move and after several.
    let mut exec = executor(&gpu, &merged_graph, Backend::Compute, (96, 64));
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    for step in 1..=3 {
        for (k, inst) in scene.instances_mut().iter_mut().enumerate() {
            inst.transform = Mat4::from_translation(Vec3::new(0.05 * k as f32, 0.15, -0.1 * step as f32)) * inst.transform;
        }
        let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
        assert!(r.blas_refit && r.blas_built == 0 && r.tlas == TlasWork::Refit, "moved instances refit the merged BVH: {r:?}");
        let refitted = exec.read_output(&gpu).unwrap();
        let mut fresh = executor(&gpu, &merged_graph, Backend::Compute, (96, 64));
        fresh.render(&gpu, scene.camera(), &scene).unwrap();
        let (rmse, outliers) = difference(&refitted, &fresh.read_output(&gpu).unwrap());
        println!("after {step} moves, refitted vs rebuilt: RMSE {rmse:.3}, {outliers} outlier pixels");
        assert!(rmse == 0.0 && outliers == 0, "after {step} moves: RMSE {rmse}, {outliers} outliers");
    }
    // A structural change (an instance removed) rebuilds.
    scene.instances_mut().pop();
    let r = exec.render(&gpu, scene.camera(), &scene).unwrap().accel.unwrap();
    assert_eq!((r.blas_built, r.tlas, r.blas_refit), (1, TlasWork::Rebuild, false), "a removed instance rebuilds the merged BVH: {r:?}");

    // `organic` is larger than one treelet (refit::TREELET_NODES), so its refit has both
    // dispatches (subtree treelets, then the top): turned and moved, refitted, it draws what a
    // fresh build draws.
    let mut organic = raygraph::scene::load::builtin("organic", 0).unwrap();
    let mut exec = executor(&gpu, &merged_graph, Backend::Compute, (96, 64));
    exec.render(&gpu, organic.camera(), &organic).unwrap();
    let (levels, dispatches) = exec.accel().unwrap().refit_shape().unwrap();
    assert_eq!(dispatches, 2, "organic: subtree treelets, then the top one ({levels} levels)");
    organic.instances_mut()[0].transform = Mat4::from_rotation_y(0.3) * Mat4::from_translation(Vec3::new(0.1, -0.05, 0.0)) * organic.instances()[0].transform;
    let r = exec.render(&gpu, organic.camera(), &organic).unwrap().accel.unwrap();
    assert!(r.blas_refit, "{r:?}");
    let mut fresh = executor(&gpu, &merged_graph, Backend::Compute, (96, 64));
    fresh.render(&gpu, organic.camera(), &organic).unwrap();
    let (rmse, outliers) = difference(&exec.read_output(&gpu).unwrap(), &fresh.read_output(&gpu).unwrap());
    println!("organic turned and moved, refitted vs rebuilt: RMSE {rmse:.3}, {outliers} outlier pixels ({levels} levels, {dispatches} dispatches)");
    assert!(rmse == 0.0 && outliers == 0, "organic: RMSE {rmse}, {outliers} outliers");
}

/// The merged layout built by the GPU builder (PLOC, the executor's choice for rebuilds on a
/// real GPU; chosen here explicitly, lavapipe being a CPU adapter) draws the picture the
/// CPU-built one draws (the metric above), is refitted on the GPU when its instance moves, and
/// rebuilt on the GPU when a mesh changes.
#[test]
fn the_merged_layout_built_on_the_gpu_draws_what_the_cpu_built_one_draws() {
    use raygraph::accel::cache::MergedBuilder;
    let gpu = gpu();
    let p = common::TempProject::with_repo_files();
    let text = std::fs::read_to_string(common::repo().join("graph/ao.ron")).unwrap();
    let merged_graph = p.write("graph/ao_merged.ron", &text.replace("Accel()", "Accel(merge: true)"));
    let mut organic = raygraph::scene::load::builtin("organic", 0).unwrap();
    let render = |scene: &raygraph::scene::Scene, builder: MergedBuilder| {
        let mut exec = executor(&gpu, &merged_graph, Backend::Compute, (96, 64));
        exec.accel_mut().unwrap().set_merged_builder(builder);
        let r = exec.render(&gpu, scene.camera(), scene).unwrap().accel.unwrap();
        (exec, r)
    };
    let (cpu_exec, cpu) = render(&organic, MergedBuilder::Cpu);
    let (mut gpu_exec, built) = render(&organic, MergedBuilder::Gpu);
    assert!(!cpu.blas_gpu_built && built.blas_gpu_built, "{cpu:?} / {built:?}");
    let (cpu_sah, gpu_sah) = (cpu.blas_sah.unwrap(), built.blas_sah.unwrap());
    println!("organic: SAH cost CPU build {cpu_sah:.2}, GPU build {gpu_sah:.2}; {}", built.describe());
    assert!(gpu_sah <= 1.1 * cpu_sah, "SAH {gpu_sah} against {cpu_sah}");
    let (rmse, outliers) = difference(&cpu_exec.read_output(&gpu).unwrap(), &gpu_exec.read_output(&gpu).unwrap());
    println!("CPU-built vs GPU-built: RMSE {rmse:.3}, {outliers} outlier pixels");
    assert!(rmse == 0.0 && outliers == 0, "RMSE {rmse}, {outliers} outliers");

    // Moved: refitted (from the builder's parents: the tree never comes back to the CPU).
    organic.instances_mut()[0].transform = Mat4::from_rotation_y(0.3) * Mat4::from_translation(Vec3::new(0.1, -0.05, 0.0)) * organic.instances()[0].transform;
    let r = gpu_exec.render(&gpu, organic.camera(), &organic).unwrap().accel.unwrap();
    assert!(r.blas_refit && !r.blas_gpu_built, "{r:?}");
    let (fresh, _) = render(&organic, MergedBuilder::Cpu);
    let (rmse, outliers) = difference(&gpu_exec.read_output(&gpu).unwrap(), &fresh.read_output(&gpu).unwrap());
    println!("GPU-built and refitted vs CPU-built: RMSE {rmse:.3}, {outliers} outlier pixels");
    assert!(rmse == 0.0 && outliers == 0, "refitted: RMSE {rmse}, {outliers} outliers");

    // An edited mesh: rebuilt, on the GPU again.
    let (mut rebuilds, first) = render(&organic, MergedBuilder::GpuRebuilds);
    for v in organic.mesh_mut(0).vertices.iter_mut() {
        v.position[1] *= 1.1;
    }
    let r = gpu_exec.render(&gpu, organic.camera(), &organic).unwrap().accel.unwrap();
    assert!(r.blas_gpu_built && r.tlas == TlasWork::Rebuild, "{r:?}");
    // Moved after that rebuild: refitted, it draws what a CPU build of the moved scene draws.
    organic.instances_mut()[0].transform = Mat4::from_rotation_x(-0.2) * Mat4::from_translation(Vec3::new(-0.1, 0.05, 0.05)) * organic.instances()[0].transform;
    let r = gpu_exec.render(&gpu, organic.camera(), &organic).unwrap().accel.unwrap();
    assert!(r.blas_refit && !r.blas_gpu_built, "{r:?}");
    let (fresh, _) = render(&organic, MergedBuilder::Cpu);
    let (rmse, outliers) = difference(&gpu_exec.read_output(&gpu).unwrap(), &fresh.read_output(&gpu).unwrap());
    println!("rebuilt on the GPU, refitted vs CPU-built: RMSE {rmse:.3}, {outliers} outlier pixels");
    assert!(rmse == 0.0 && outliers == 0, "rebuilt and refitted: RMSE {rmse}, {outliers} outliers");
    // GpuRebuilds (the executor's choice on a real GPU): the first build on the CPU, the
    // rebuild after the edit on the GPU.
    let r = rebuilds.render(&gpu, organic.camera(), &organic).unwrap().accel.unwrap();
    assert!(!first.blas_gpu_built && r.blas_gpu_built, "{first:?} / {r:?}");
}

/// Reads `len` elements of the cache's array `name` (an `accel_*` binding) back from the GPU.
fn cache_array<T: bytemuck::Pod>(gpu: &Gpu, cache: &raygraph::accel::cache::AccelCache, name: &str, len: usize) -> Vec<T> {
    let Some(wgpu::BindingResource::Buffer(b)) = cache.binding(name, 0) else { panic!("the cache binds no buffer `{name}`") };
    let bytes = raygraph::accel::gpu_build::read_bytes(gpu.device(), gpu.queue(), b.buffer, 0, (len * std::mem::size_of::<T>()) as u64).unwrap();
    bytemuck::cast_slice(&bytes).to_vec()
}

/// The tree's nodes from the root in depth-first order: boxes, and the first triangle and count
/// of each leaf (where the nodes lie varies from build to build with the order the GPU's
/// workgroups merge in; this does not).
fn preorder(nodes: &[raygraph::accel::layout::GpuBvhNode]) -> Vec<([f32; 3], [f32; 3], u32, u32)> {
    let mut out = Vec::new();
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let n = nodes[i];
        out.push((n.min, n.max, if n.count > 0 { n.left_or_first } else { 0 }, n.count));
        if n.count == 0 {
            stack.extend([n.left_or_first as usize + 1, n.left_or_first as usize]);
        }
    }
    out
}

/// Checks a refitted tree from its root: every leaf's box is exactly its triangles' box widened
/// as `accel::layout` widens, every interior box exactly the union of its children's.
fn check_refitted_boxes(nodes: &[raygraph::accel::layout::GpuBvhNode], tris: &[raygraph::accel::layout::GpuTriangle]) {
    use raygraph::accel::layout::{widen_down, widen_up};
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let n = nodes[i];
        let (mut lo, mut hi) = ([f32::MAX; 3], [-f32::MAX; 3]);
        if n.count > 0 {
            for t in &tris[n.left_or_first as usize..(n.left_or_first + n.count) as usize] {
                for v in [t.v0, t.v1, t.v2] {
                    for a in 0..3 {
                        (lo[a], hi[a]) = (lo[a].min(v[a]), hi[a].max(v[a]));
                    }
                }
            }
            (lo, hi) = (lo.map(widen_down), hi.map(widen_up));
        } else {
            let (l, r) = (nodes[n.left_or_first as usize], nodes[n.left_or_first as usize + 1]);
            (lo, hi) = ([0, 1, 2].map(|a| l.min[a].min(r.min[a])), [0, 1, 2].map(|a| l.max[a].max(r.max[a])));
            stack.extend([n.left_or_first as usize, n.left_or_first as usize + 1]);
        }
        assert_eq!((n.min, n.max), (lo, hi), "node {i} (count {}): box not refitted", n.count);
    }
}

/// A rebuild on the GPU leaves the tree where the builder wrote it: the traversal binds the very
/// tree a build of the same input reads back (the same boxes and triangles, bit for bit, in the
/// same depth-first order), and the TLAS node holds its root's box. Moved instances are then refitted from the builder's parents, with no CPU copy of the
/// tree: every box is exactly refitted, and rays through the refitted tree hit what the f64
/// reference hits in the moved scene, as rays through a CPU-built tree of the moved scene do.
#[test]
fn a_gpu_rebuild_stays_on_the_gpu_and_refits_to_what_the_moved_scene_traces() {
    use raygraph::accel::bvh::{Blas, BuildConfig};
    use raygraph::accel::cache::{AccelCache, AccelSettings, MergedBuilder};
    use raygraph::accel::gpu_build::{layout_sah_cost, GpuBlasBuilder};
    use raygraph::accel::layout::{merge, merge_instances, merged_accel, GpuBvhNode, GpuTriangle};
    let gpu = gpu();
    let mut scene = raygraph::scene::load::builtin("organic", 0).unwrap();
    // Three instances of the mesh, each moved by its own transform below.
    for k in 1..3 {
        let mut inst = scene.instances()[0].clone();
        inst.transform = Mat4::from_translation(Vec3::new(1.5 * k as f32, 0.2, 0.0)) * inst.transform;
        scene.instances_mut().push(inst);
    }
    let mut cache = AccelCache::new(gpu.device(), Backend::Compute, AccelSettings { dedup: true, merge: true }, 1);
    cache.set_merged_builder(MergedBuilder::GpuRebuilds);
    let update = |cache: &mut AccelCache, scene: &raygraph::scene::Scene| {
        let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let r = cache.update(gpu.device(), gpu.queue(), &mut encoder, scene).unwrap();
        gpu.queue().submit([encoder.finish()]);
        r
    };
    let first = update(&mut cache, &scene);
    assert!(!first.blas_gpu_built, "the first build is the CPU's: {first:?}");
    scene.mesh_mut(0).vertices[0].position[1] += 0.01;
    let r = update(&mut cache, &scene);
    assert!(r.blas_gpu_built && r.tlas == TlasWork::Rebuild && !r.blas_refit, "an edited mesh rebuilds on the GPU: {r:?}");

    // The builder over the records made on the GPU (tests/gpu_build.rs checks them against
    // `merged_triangles`, to a few ulps of the transform's terms on lavapipe).
    let hashes: Vec<u64> = scene.meshes().iter().map(|m| raygraph::accel::cache::mesh_hash(m)).collect();
    let mut maker = raygraph::accel::gpu_records::GpuRecordMaker::new(gpu.device());
    let records = maker.make(gpu.device(), gpu.queue(), &scene, (&hashes, None), u32::MAX).unwrap().unwrap();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    let built = builder.build_records(gpu.device(), gpu.queue(), &records.records, records.count as usize).unwrap();
    let (nodes, tris) = built.read_back(gpu.device(), gpu.queue()).unwrap();
    let bound_nodes: Vec<GpuBvhNode> = cache_array(&gpu, &cache, "accel_blas_nodes", nodes.len());
    let bound_tris: Vec<GpuTriangle> = cache_array(&gpu, &cache, "accel_triangles", tris.len());
    assert!(bound_tris == tris, "the traversal binds the triangles the builder writes");
    assert_eq!(preorder(&bound_nodes), preorder(&nodes), "the traversal binds the tree the builder writes");
    let tlas: Vec<GpuBvhNode> = cache_array(&gpu, &cache, "accel_tlas_nodes", 1);
    assert_eq!((tlas[0].min, tlas[0].max, tlas[0].count), (nodes[0].min, nodes[0].max, 1), "the TLAS node holds the root's box");
    let (sah, read_back_sah) = (r.blas_sah.unwrap(), layout_sah_cost(&nodes));
    println!("organic x3: SAH cost {sah:.4} from the GPU, {read_back_sah:.4} from the read-back tree");
    assert!((sah - read_back_sah).abs() <= 1e-4 * read_back_sah, "SAH cost {sah} against {read_back_sah}");

    for step in 1..=2 {
        for (k, inst) in scene.instances_mut().iter_mut().enumerate() {
            let turn = Mat4::from_rotation_y(0.2 * step as f32 * (k as f32 - 1.0));
            inst.transform = Mat4::from_translation(Vec3::new(0.1 * k as f32, -0.05 * step as f32, 0.1)) * turn * inst.transform;
        }
        let r = update(&mut cache, &scene);
        assert!(r.blas_refit && r.blas_built == 0 && r.tlas == TlasWork::Refit, "step {step}: moved instances refit: {r:?}");
        let nodes: Vec<GpuBvhNode> = cache_array(&gpu, &cache, "accel_blas_nodes", nodes.len());
        let tris: Vec<GpuTriangle> = cache_array(&gpu, &cache, "accel_triangles", tris.len());
        check_refitted_boxes(&nodes, &tris);
        let tlas: Vec<GpuBvhNode> = cache_array(&gpu, &cache, "accel_tlas_nodes", 1);
        assert_eq!((tlas[0].min, tlas[0].max), (nodes[0].min, nodes[0].max), "step {step}: the TLAS node holds the refitted root's box");

        let refitted = merged_accel(nodes, tris);
        let (merged, origin) = merge_instances(&scene);
        let cpu_built = merge(&merged, &origin, Blas::build(&merged, &BuildConfig::default()));
        rays_hit_what_the_reference_hits(&scene, &refitted, &cpu_built, step);
    }
}

/// 400 random rays through the refitted tree and the CPU-built tree of the moved `scene` hit
/// what the f64 reference hits (rays within 1e-4 of an edge skipped).
fn rays_hit_what_the_reference_hits(
    scene: &raygraph::scene::Scene,
    refitted: &raygraph::accel::layout::GpuAccel,
    cpu_built: &raygraph::accel::layout::GpuAccel,
    step: u64,
) {
    use raygraph::accel::cpu_traverse::{CpuTraverser, Ray};
    use raygraph::accel::reference::Reference;
    let (through_refit, through_cpu) = (CpuTraverser::new(refitted), CpuTraverser::new(cpu_built));
    let reference = Reference::new(scene);
    let b = scene.bounds();
    let mut rng = raygraph::util::SplitMix64(step);
    let (mut robust, mut hits) = (0, 0);
    for k in 0..400 {
        let ray = Ray::new(b.min + (b.max - b.min) * Vec3::new(rng.f(), rng.f(), rng.f()), rng.dir());
        let (want, margin) = reference.closest_with_margin(&ray);
        if margin < 1e-4 {
            continue;
        }
        robust += 1;
        hits += want.is_some() as usize;
        for (what, got) in [("refitted", through_refit.closest(&ray)), ("CPU-built", through_cpu.closest(&ray))] {
            assert_eq!(got.map(|h| (h.instance_id, h.prim)), want.map(|w| (w.instance_id, w.prim)), "step {step} ray {k}: the {what} tree's hit");
            if let (Some(g), Some(w)) = (got, want) {
                assert!((g.t as f64 - w.t).abs() <= 1e-4 * w.t.max(1.0), "step {step} ray {k}: the {what} tree's t {} against {}", g.t, w.t);
            }
        }
    }
    println!("step {step}: {robust} of 400 rays away from edges, {hits} hits; refitted, CPU-built and reference agree");
    assert!(robust >= 360 && hits >= 100, "step {step}: {robust} robust rays, {hits} hits");
}
