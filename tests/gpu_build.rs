//! The GPU BLAS builder (PLOC, `shaders/accel/build.wgsl`) against the CPU binned-SAH builder
//! (its split tree, before the reinsertion the CPU build adds):
//! the tree it writes is a valid traversal layout (every triangle in exactly one leaf of at
//! most four, every box around what it holds, within the traversal stack's depth), its SAH cost
//! is within the 1.1x of the CPU build's on the atrium, and rays traced through it hit
//! exactly what they hit through the CPU-built tree; the parents, leaf order and SAH cost it
//! reports beside the tree (what the cache's GPU refit and report use) match the tree.

use glam::Vec3;
use raygraph::accel::bvh::{Blas, BuildConfig, MAX_TREE_DEPTH};
use raygraph::accel::cache::mesh_hash;
use raygraph::accel::cpu_traverse::{CpuTraverser, Ray};
use raygraph::accel::gpu_build::{layout_sah_cost, merged_triangles, read_bytes, GpuBlas, GpuBlasBuilder};
use raygraph::accel::gpu_records::GpuRecordMaker;
use raygraph::accel::layout::{merge, merge_instances, GpuAccel, GpuBvhNode, GpuTriangle};
use raygraph::accel::radix_sort::GpuRadixSort;
use raygraph::runtime::Gpu;
use raygraph::scene::load::builtin;
use raygraph::scene::{Mesh, Scene, Vertex};
use raygraph::util::SplitMix64;

fn gpu() -> Gpu {
    Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required")
}

fn read_back(gpu: &Gpu, b: &GpuBlas) -> (Vec<GpuBvhNode>, Vec<GpuTriangle>) {
    let nodes = read_bytes(gpu.device(), gpu.queue(), &b.nodes, 0, b.node_count as u64 * 32).unwrap();
    let tris = read_bytes(gpu.device(), gpu.queue(), &b.triangles, 0, b.triangle_count as u64 * 48).unwrap();
    (bytemuck::cast_slice(&nodes).to_vec(), bytemuck::cast_slice(&tris).to_vec())
}

fn contains(outer: &GpuBvhNode, lo: [f32; 3], hi: [f32; 3]) -> bool {
    (0..3).all(|a| outer.min[a] <= lo[a] && hi[a] <= outer.max[a])
}

/// Checks the layout from the root: returns the depth of the deepest leaf.
fn check_layout(name: &str, nodes: &[GpuBvhNode], tris: &[GpuTriangle], input: &[GpuTriangle]) -> usize {
    assert_eq!(tris.len(), input.len(), "{name}: triangle count");
    let mut seen = vec![0u32; tris.len()];
    let mut deepest = 0;
    let mut stack = vec![(0usize, 0usize)];
    while let Some((i, depth)) = stack.pop() {
        let n = nodes.get(i).unwrap_or_else(|| panic!("{name}: entry {i} out of range"));
        deepest = deepest.max(depth);
        if n.count > 0 {
            assert!(n.count <= 4, "{name}: leaf of {}", n.count);
            for t in n.left_or_first..n.left_or_first + n.count {
                let tri = tris.get(t as usize).unwrap_or_else(|| panic!("{name}: triangle {t} out of range"));
                seen[t as usize] += 1;
                for v in [tri.v0, tri.v1, tri.v2] {
                    assert!(contains(n, v, v), "{name}: leaf {i} does not contain its triangle {t}");
                }
            }
        } else {
            let l = n.left_or_first as usize;
            assert!(l >= 1 && l + 1 < nodes.len(), "{name}: children {l} of {i} out of range");
            for c in [l, l + 1] {
                assert!(contains(n, nodes[c].min, nodes[c].max), "{name}: node {i} does not contain child {c}");
                stack.push((c, depth + 1));
            }
        }
    }
    assert!(seen.iter().all(|&s| s == 1), "{name}: every triangle must be in exactly one leaf");
    // The output is the input reordered.
    let key = |t: &GpuTriangle| (t.prim, t.instance, t.flags, [t.v0, t.v1, t.v2].map(|v| v.map(f32::to_bits)));
    let mut a: Vec<_> = input.iter().map(key).collect();
    let mut b: Vec<_> = tris.iter().map(key).collect();
    a.sort();
    b.sort();
    assert!(a == b, "{name}: the output triangles are not the input's");
    deepest
}

/// What the GPU refit reads besides the tree: every used node's parent (+ 1; 0 for the root
/// and for the unused slots inside leaves), each triangle's index in the input; and the SAH
/// cost the build reports against the read-back tree's.
fn check_refit_inputs(gpu: &Gpu, name: &str, built: &GpuBlas, nodes: &[GpuBvhNode], tris: &[GpuTriangle], input: &[GpuTriangle]) {
    let parents = read_bytes(gpu.device(), gpu.queue(), &built.parents, 0, nodes.len() as u64 * 4).unwrap();
    let parents: &[u32] = bytemuck::cast_slice(&parents);
    let mut expected = vec![0u32; nodes.len()];
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        if nodes[i].count == 0 {
            let l = nodes[i].left_or_first as usize;
            (expected[l], expected[l + 1]) = (i as u32 + 1, i as u32 + 1);
            stack.extend([l, l + 1]);
        }
    }
    assert!(parents == expected, "{name}: parents");
    let order = read_bytes(gpu.device(), gpu.queue(), &built.leaf_order, 0, tris.len() as u64 * 4).unwrap();
    let order: &[u32] = bytemuck::cast_slice(&order);
    assert!(tris.iter().zip(order).all(|(t, &o)| input.get(o as usize) == Some(t)), "{name}: leaf order");
    let sah = layout_sah_cost(nodes);
    assert!((built.sah_cost - sah).abs() <= 1e-4 * sah, "{name}: reported SAH cost {} against {sah}", built.sah_cost);
}

fn soup(n: usize, seed: u64, spread: f32) -> Vec<GpuTriangle> {
    let mut rng = SplitMix64(seed);
    let mut v = || Vec3::new(rng.f(), rng.f(), rng.f());
    (0..n)
        .map(|i| {
            let c = v() * spread;
            let (a, b, d) = (c + v() * 0.05, c + v() * 0.05, c + v() * 0.05);
            GpuTriangle { v0: a.to_array(), prim: i as u32, v1: b.to_array(), instance: 0, v2: d.to_array(), flags: 0 }
        })
        .collect()
}

/// The two builders: H-PLOC (the default) and the PLOC rounds (`RAYGRAPH_GPU_BUILD=ploc`).
const BUILDERS: [&[(&str, &str)]; 2] = [&[], &[("RAYGRAPH_GPU_BUILD", "ploc")]];

/// Held while a test builds with variables of its own set, or needs the default builder: the
/// environment is the process's, shared by the tests running at once.
static ENV: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `f` with the environment's variables `vars` set (the builder reads them at each build), and
/// no other test's set meanwhile.
fn with_env<T>(vars: &[(&str, &str)], f: impl FnOnce() -> T) -> T {
    let _held = ENV.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    for (k, v) in vars {
        std::env::set_var(k, v);
    }
    let out = f();
    for (k, _) in vars {
        std::env::remove_var(k);
    }
    out
}

#[test]
fn small_and_degenerate_inputs_give_valid_trees() {
    let gpu = gpu();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    let mut cases: Vec<(String, Vec<GpuTriangle>)> =
        [1, 2, 3, 4, 5, 17, 1000, 1025, 5000].iter().map(|&n| (format!("soup of {n}"), soup(n, n as u64, 10.0))).collect();
    // Every centroid in one place: all Morton codes equal.
    let one = soup(1, 7, 1.0)[0];
    cases.push(("600 copies of one triangle".into(), (0..600).map(|i| GpuTriangle { prim: i, ..one }).collect()));
    // Long thin distribution along one axis.
    cases.push((
        "a line".into(),
        soup(3000, 9, 1.0)
            .into_iter()
            .enumerate()
            .map(|(i, mut t)| {
                for v in [&mut t.v0, &mut t.v1, &mut t.v2] {
                    v[0] += i as f32;
                }
                t
            })
            .collect(),
    ));
    for ((name, input), variant) in cases.iter().flat_map(|c| BUILDERS.iter().map(move |v| (c, v))) {
        let name = &format!("{name}, {variant:?}");
        let scopes = gpu.scopes();
        let built = with_env(variant, || builder.build(gpu.device(), gpu.queue(), input)).unwrap_or_else(|e| panic!("{name}: {e}"));
        scopes.finish(&gpu, name).unwrap();
        let (nodes, tris) = read_back(&gpu, &built);
        let depth = check_layout(name, &nodes, &tris, input);
        assert_eq!(depth as u32, built.depth, "{name}: the reported depth");
        check_refit_inputs(&gpu, name, &built, &nodes, &tris, input);
        assert!(depth < MAX_TREE_DEPTH, "{name}: depth {depth}");
    }
}

fn atrium_rays(scene: &Scene, count: usize) -> Vec<Ray> {
    let b = scene.bounds();
    let (lo, hi) = (b.min, b.max);
    let mut rng = SplitMix64(11);
    (0..count)
        .map(|_| {
            let p = Vec3::new(rng.f(), rng.f(), rng.f());
            let o = lo + (hi - lo) * p;
            Ray::new(o, rng.dir())
        })
        .collect()
}

#[test]
fn the_atrium_built_on_the_gpu_is_within_1_1x_of_the_cpu_sah_cost_and_traces_the_same_hits() {
    let gpu = gpu();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    let scene = builtin("atrium", 0).unwrap();
    let (merged, origin) = merge_instances(&scene);
    let input = merged_triangles(&merged, &origin);
    let built = with_env(&[], || builder.build(gpu.device(), gpu.queue(), &input)).unwrap();
    let (nodes, tris) = read_back(&gpu, &built);
    check_layout("atrium", &nodes, &tris, &input);
    check_refit_inputs(&gpu, "atrium", &built, &nodes, &tris, &input);

    // The 1.1x is against the CPU's binned-SAH split (1.067x measured); the CPU build
    // now also optimises its tree by reinsertion (4.6% lower on the atrium, PERF.md step 28),
    // against which the GPU's is 1.124x (lavapipe, 2026-12-01): the reference here is the split
    // tree, reinsertion off.
    let split_only = BuildConfig { reinsertion_passes: 0, ..BuildConfig::default() };
    let cpu = merge(&merged, &origin, Blas::build(&merged, &split_only));
    let (gpu_sah, cpu_sah) = (layout_sah_cost(&nodes), layout_sah_cost(&cpu.blas_nodes));
    println!(
        "atrium (H-PLOC): {} triangles, {} PLOC rounds, depth {}; SAH cost GPU {gpu_sah:.2}, CPU {cpu_sah:.2} ({:.3}x)",
        input.len(),
        built.rounds,
        built.depth,
        gpu_sah / cpu_sah
    );
    assert!(gpu_sah <= 1.1 * cpu_sah, "SAH cost {gpu_sah:.2} against the CPU build's {cpu_sah:.2}");

    let gpu_accel = GpuAccel { blas_nodes: nodes, triangles: tris, ..cpu.clone() };
    let (a, b) = (CpuTraverser::new(&cpu), CpuTraverser::new(&gpu_accel));
    let rays = atrium_rays(&scene, 20_000);
    let mut hits = 0;
    for r in &rays {
        let (x, y) = (a.closest(r), b.closest(r));
        assert_eq!(x.is_some(), y.is_some(), "ray {r:?}: hit through one tree only");
        if let (Some(x), Some(y)) = (x, y) {
            hits += 1;
            assert_eq!(x.t, y.t, "ray {r:?}: different closest t");
        }
        assert_eq!(a.any(r), b.any(r), "ray {r:?}: any-hit differs");
    }
    assert!(hits > rays.len() / 2, "the rays must mostly hit ({hits} of {})", rays.len());
}

#[test]
fn an_organic_mesh_and_a_box_build_on_the_gpu() {
    let gpu = gpu();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    for name in ["box", "organic"] {
        let scene = builtin(name, 0).unwrap();
        let (merged, origin) = merge_instances(&scene);
        let input = merged_triangles(&merged, &origin);
        let built = with_env(&[], || builder.build(gpu.device(), gpu.queue(), &input)).unwrap();
        let (nodes, tris) = read_back(&gpu, &built);
        check_layout(name, &nodes, &tris, &input);
        let cpu = merge(&merged, &origin, Blas::build(&merged, &BuildConfig::default()));
        println!("{name}: SAH cost GPU {:.2}, CPU {:.2}", layout_sah_cost(&nodes), layout_sah_cost(&cpu.blas_nodes));
    }
    // A mesh with unusable triangles: they are left out of the input, as the CPU builder does.
    let mut mesh = Mesh::default();
    for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [f32::NAN, 0.0, 0.0]] {
        mesh.vertices.push(Vertex { position: p, ..Default::default() });
    }
    mesh.indices = vec![0, 1, 2, 0, 1, 3, 0, 0, 1, 0, 1, 9];
    let origin: Vec<_> = (0..4).map(|p| raygraph::accel::layout::TriangleOrigin { instance: 0, prim: p, mirrored: false, alpha: false }).collect();
    let input = merged_triangles(&mesh, &origin);
    assert_eq!(input.len(), 1, "NaN, degenerate and out-of-range triangles are left out");
}

/// The scene the record tests use: the organic mesh under several transforms (mirrored,
/// scaled, rotated, one singular and left out) and a small mesh with a NaN vertex, a
/// degenerate triangle and an out-of-range index.
fn record_test_scene() -> Scene {
    use glam::{Mat4, Quat};
    let mut scene = builtin("organic", 0).unwrap();
    let base = scene.instances()[0].clone();
    let mut odd = Mesh::default();
    for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [f32::NAN, 0.0, 0.0], [0.3, 0.7, 1.1]] {
        odd.vertices.push(Vertex { position: p, ..Default::default() });
    }
    odd.indices = vec![0, 1, 2, 0, 1, 3, 0, 0, 1, 0, 1, 9, 1, 2, 4, 2, 2, 2];
    scene.push_mesh(odd);
    let odd_mesh = scene.meshes().len() - 1;
    let transforms = [
        Mat4::from_scale_rotation_translation(Vec3::new(-1.0, 1.0, 1.0), Quat::from_rotation_y(0.7), Vec3::new(123.456, -7.25, 0.1)),
        Mat4::from_scale_rotation_translation(Vec3::new(0.37, 2.9, 1.3), Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.2), Vec3::new(-3.3, 1e3, 17.0)),
        Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)),
        Mat4::from_scale_rotation_translation(Vec3::splat(1e-3), Quat::from_rotation_z(0.1), Vec3::new(0.5, 0.5, 0.5)),
    ];
    for (k, t) in transforms.into_iter().enumerate() {
        scene.instances_mut().push(raygraph::scene::Instance { transform: t, ..base.clone() });
        scene.instances_mut().push(raygraph::scene::Instance { mesh: odd_mesh, transform: t * Mat4::from_translation(Vec3::splat(k as f32)), ..base.clone() });
    }
    scene
}

/// The GPU-made records of `scene` against [`merged_triangles`] of the CPU's merged mesh:
/// same triangles in the same order with the same scene instance, primitive and flags, and
/// the same object-space vertices. The world positions agree within 4 f32 epsilons of the
/// sum of the transform's term magnitudes (|m0 x| + |m1 y| + |m2 z| + |t|): the CPU rounds its
/// f64 result once; the kernel carries the sum in two f32s, which lavapipe's compiler reduces
/// to plain f32 arithmetic (four roundings: 1-ulp differences where the terms cancel).
fn check_gpu_records(gpu: &Gpu, maker: &mut GpuRecordMaker, scene: &Scene, what: &str) -> usize {
    let hashes: Vec<u64> = scene.meshes().iter().map(|m| mesh_hash(m)).collect();
    let made = maker.make(gpu.device(), gpu.queue(), scene, (&hashes, None), u32::MAX).unwrap().expect("records");
    let (merged, origin) = merge_instances(scene);
    let expected = merged_triangles(&merged, &origin);
    assert_eq!(made.count as usize, expected.len(), "{what}: record count");
    let bytes = read_bytes(gpu.device(), gpu.queue(), &made.records, 0, 48 * made.count as u64).unwrap();
    let records: &[GpuTriangle] = bytemuck::cast_slice(&bytes);
    let mut identical = 0;
    for (k, (got, want)) in records.iter().zip(&expected).enumerate() {
        assert_eq!((got.instance, got.prim, got.flags), (want.instance, want.prim, want.flags), "{what}: record {k}");
        let inst = &scene.instances()[want.instance as usize];
        let rows = raygraph::accel::layout::affine_rows(&raygraph::accel::bvh::instance_transform(&inst.transform).unwrap());
        let object = raygraph::accel::bvh::mesh_triangle(&scene.meshes()[inst.mesh], want.prim as usize).unwrap();
        for (c, (g, w)) in [got.v0, got.v1, got.v2].iter().zip([want.v0, want.v1, want.v2]).enumerate() {
            for r in 0..3 {
                let terms = (0..3).map(|j| (rows[r][j] * object[c][j]).abs()).sum::<f32>() + rows[r][3].abs();
                let bound = 4.0 * f32::EPSILON * terms;
                assert!((g[r] - w[r]).abs() <= bound, "{what}: record {k}, vertex {c}: {g:?} against {w:?} (bound {bound})");
            }
            identical += (g.map(f32::to_bits) == w.map(f32::to_bits)) as usize;
        }
    }
    println!("{what}: {identical} of {} world vertices bit-identical to the CPU's", 3 * records.len());
    let object = read_bytes(gpu.device(), gpu.queue(), &made.object_vertices, 0, 48 * made.count as u64).unwrap();
    // xyz: the object-space vertex; w: its index among all meshes' vertices (mesh by mesh).
    let object: &[[u32; 4]] = bytemuck::cast_slice(&object);
    for (k, want) in expected.iter().enumerate() {
        let m = scene.instances()[want.instance as usize].mesh;
        let mesh = &scene.meshes()[m];
        let first_vertex: usize = scene.meshes()[..m].iter().map(|m| m.vertices.len()).sum();
        let verts = raygraph::accel::bvh::mesh_triangle(mesh, want.prim as usize).unwrap();
        for c in 0..3 {
            let id = (first_vertex + mesh.indices[3 * want.prim as usize + c] as usize) as u32;
            assert_eq!(
                object[3 * k + c],
                [verts[c].x.to_bits(), verts[c].y.to_bits(), verts[c].z.to_bits(), id],
                "{what}: record {k}'s object-space vertex {c}"
            );
        }
    }
    made.bytes_uploaded as usize
}

#[test]
fn records_made_on_the_gpu_equal_the_cpu_merged_records() {
    let gpu = gpu();
    let mut maker = GpuRecordMaker::new(gpu.device());
    let mut scene = record_test_scene();
    let first = check_gpu_records(&gpu, &mut maker, &scene, "first");
    // One vertex of the small mesh moved: only that mesh is written again.
    let odd = scene.meshes().len() - 1;
    scene.mesh_mut(odd).vertices[4].position[2] = 0.0;
    let edit = check_gpu_records(&gpu, &mut maker, &scene, "after an edit");
    // 80 bytes per usable instance: the two under the singular transform are left out.
    let instance_bytes = 80 * (scene.instances().len() - 2);
    assert_eq!(edit, instance_bytes + 5 * 16 + 18 * 4, "an edit uploads the instances and the edited mesh (first build: {first} bytes)");
    // A triangle added to the small mesh: the meshes are laid out again.
    scene.mesh_mut(odd).indices.extend([0, 2, 4]);
    check_gpu_records(&gpu, &mut maker, &scene, "after a new triangle");
}

/// Sorts `keys` and `vals` (`capacity` pairs; the first `count` sorted) with the GPU radix sort
/// and reads both arrays back whole.
fn radix_sorted(gpu: &Gpu, sorter: &GpuRadixSort, keys: &[u32], vals: &[u32], (count, key_bits): (u32, u32)) -> (Vec<u32>, Vec<u32>) {
    use wgpu::util::DeviceExt;
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let upload = |label: &str, data: &[u32]| {
        gpu.device().create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytemuck::cast_slice(data), usage })
    };
    let (key_buffer, val_buffer) = (upload("test keys", keys), upload("test values", vals));
    let scopes = gpu.scopes();
    let job = sorter.job(gpu.device(), &key_buffer, &val_buffer, (keys.len() as u32, count), key_bits);
    let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("test radix sort") });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("test radix sort"), timestamp_writes: None });
        sorter.record(&mut pass, &job);
    }
    gpu.queue().submit([encoder.finish()]);
    scopes.finish(gpu, "radix sort").unwrap();
    let read = |b: &wgpu::Buffer| -> Vec<u32> { bytemuck::cast_slice(&read_bytes(gpu.device(), gpu.queue(), b, 0, 4 * keys.len() as u64).unwrap()).to_vec() };
    (read(&key_buffer), read(&val_buffer))
}

/// The GPU radix sort gives what a stable sort on the CPU gives: random keys of a few bits
/// (many equal) to all 32, sizes around its tile of 2048 keys and past a million, one key; the
/// values (distinct, not in key order) say where each key came from, and each sort makes as many
/// passes of 8 bits as its keys' bits need (one to four: after one or three the result is copied
/// back). Pairs past the count are left as they were. Every tile size `RAYGRAPH_SORT_TILE` offers.
#[test]
fn the_radix_sort_equals_a_stable_sort() {
    let gpu = gpu();
    for tile in ["2048", "4096", "1024", "512", "256"] {
        let sorter = with_env(&[("RAYGRAPH_SORT_TILE", tile)], || GpuRadixSort::new(gpu.device()));
        // Tiles of 4096 keys need 47,108 bytes of workgroup memory: where the device has less
        // (lavapipe: 32,768) the sort takes the largest tile that fits, and that one is checked.
        let fits = 8 * tile.parse::<u64>().unwrap() + 14_340 <= gpu.device().limits().max_compute_workgroup_storage_size as u64;
        let expected = if fits { tile.to_string() } else { "2048".to_string() };
        assert_eq!(sorter.tile().to_string(), expected, "tiles of {tile} asked for");
        check_radix_sort(&gpu, &sorter, &expected);
    }
}

/// [`the_radix_sort_equals_a_stable_sort`] for one sorter, made with tiles of `tile` keys.
fn check_radix_sort(gpu: &Gpu, sorter: &GpuRadixSort, tile: &str) {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 16) as u32
    };
    let cases: [(usize, usize, u32); 10] = [
        (1, 1, 32),
        (2, 2, 1),
        (2047, 2047, 3),
        (2048, 2048, 30),
        (2049, 2049, 9),
        (5000, 3001, 30),
        (100_003, 100_003, 17),
        (100_003, 100_003, 24),
        (100_003, 100_003, 32),
        ((1 << 20) + 3, (1 << 20) + 3, 30),
    ];
    for (capacity, count, bits) in cases {
        let mask = if bits == 32 { u32::MAX } else { (1u32 << bits) - 1 };
        let keys: Vec<u32> = (0..capacity).map(|_| next() & mask).collect();
        let vals: Vec<u32> = (0..capacity as u32).map(|i| i.wrapping_mul(2_654_435_761)).collect();
        let (got_keys, got_vals) = radix_sorted(gpu, sorter, &keys, &vals, (count as u32, bits));
        let mut order: Vec<usize> = (0..count).collect();
        order.sort_by_key(|&i| keys[i]);
        let want_keys: Vec<u32> = order.iter().map(|&i| keys[i]).chain(keys[count..].iter().copied()).collect();
        let want_vals: Vec<u32> = order.iter().map(|&i| vals[i]).chain(vals[count..].iter().copied()).collect();
        let what = format!("{count} of {capacity} keys of {bits} bits, tiles of {tile}");
        assert!(got_keys == want_keys, "{what}: keys out of order");
        assert!(got_vals == want_vals, "{what}: values not in the stable order");
    }
}

/// The tree as a traversal sees it: the nodes reached from the root in depth-first order, left
/// child first, interior nodes without their children's index (where a pair of children is
/// placed depends on the order in which the GPU's workgroups merged; the slots inside leaves
/// are never read).
fn reachable(nodes: &[GpuBvhNode]) -> Vec<GpuBvhNode> {
    let (mut out, mut stack) = (Vec::new(), vec![0usize]);
    while let Some(i) = stack.pop() {
        out.push(GpuBvhNode { left_or_first: if nodes[i].count == 0 { 0 } else { nodes[i].left_or_first }, ..nodes[i] });
        if nodes[i].count == 0 {
            stack.extend([nodes[i].left_or_first as usize + 1, nodes[i].left_or_first as usize]);
        }
    }
    out
}

/// The reachable nodes' and the triangles' bytes of a build of `input` with the environment's
/// `vars`, and its depth.
fn tree_bytes(gpu: &Gpu, builder: &GpuBlasBuilder, input: &[GpuTriangle], vars: &[(&str, &str)]) -> (Vec<u8>, Vec<u8>, u32) {
    let built = with_env(vars, || builder.build(gpu.device(), gpu.queue(), input)).unwrap();
    let (nodes, tris) = read_back(gpu, &built);
    let nodes = reachable(&nodes);
    (bytemuck::cast_slice::<GpuBvhNode, u8>(&nodes).to_vec(), bytemuck::cast_slice::<GpuTriangle, u8>(&tris).to_vec(), built.depth)
}

/// How two [`tree_bytes`] differ, in words.
fn tree_difference(a: &(Vec<u8>, Vec<u8>, u32), b: &(Vec<u8>, Vec<u8>, u32)) -> String {
    let differing = |x: &[u8], y: &[u8]| x.iter().zip(y).filter(|(p, q)| p != q).count();
    format!(
        "{} of {} bytes of the reachable nodes, {} of {} triangle bytes differ, depth {} against {}",
        differing(&a.0, &b.0),
        b.0.len(),
        differing(&a.1, &b.1),
        b.1.len(),
        a.2,
        b.2
    )
}

/// The builder's variants (`RAYGRAPH_GPU_BUILD_SORT`, `_ROUND`, `_INDIRECT`: kept to compare
/// their speed on a GPU, with the defaults chosen by that measurement) build the same tree: the
/// same triangles in the same order, the same nodes in depth-first order; H-PLOC's with either
/// sort, the PLOC rounds' (`RAYGRAPH_GPU_BUILD=ploc`) with any of their variants. The
/// environment is read at each build, and every build in this file holds [`ENV`] through
/// [`with_env`].
#[test]
fn every_builder_variant_builds_the_same_tree() {
    let gpu = gpu();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    let input = soup(5000, 11, 10.0);
    let ploc = ("RAYGRAPH_GPU_BUILD", "ploc");
    let (radix, bitonic) = (("RAYGRAPH_GPU_BUILD_SORT", "radix"), ("RAYGRAPH_GPU_BUILD_SORT", "bitonic"));
    let (indirect, pair) = (("RAYGRAPH_GPU_BUILD_INDIRECT", "1"), ("RAYGRAPH_GPU_BUILD_ROUND", "pair"));
    let families: [&[&[(&str, &str)]]; 2] =
        [&[&[], &[radix], &[bitonic]], &[&[ploc], &[ploc, radix], &[ploc, bitonic], &[ploc, indirect], &[ploc, pair], &[ploc, radix, indirect, pair]]];
    for family in families {
        let default = tree_bytes(&gpu, &builder, &input, family[0]);
        for vars in family {
            let variant = tree_bytes(&gpu, &builder, &input, vars);
            assert!(variant == default, "{vars:?} built another tree than its builder's defaults: {}", tree_difference(&variant, &default));
        }
    }
}

/// H-PLOC's tree does not depend on how its workgroups were scheduled (which invocation reached
/// a split second, in what order nodes were numbered): eight builds of the same input are one
/// tree. A record read before it was visible, or a lost exchange, would show here.
#[test]
fn hploc_builds_the_same_tree_every_time() {
    let gpu = gpu();
    let builder = GpuBlasBuilder::new(gpu.device()).unwrap();
    let input = soup(20000, 5, 20.0);
    let first = tree_bytes(&gpu, &builder, &input, &[]);
    for run in 1..8 {
        let again = tree_bytes(&gpu, &builder, &input, &[]);
        assert!(again == first, "build {run} of the same 20,000 triangles gave another tree: {}", tree_difference(&again, &first));
    }
}
