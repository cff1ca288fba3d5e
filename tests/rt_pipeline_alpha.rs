//! The rt-pipeline back-end's alpha-tested hit group (src/accel/rt_pipeline.rs and
//! rt_pipeline/any_hit.rs): the any-hit shader, written by naga and patched as SPIR-V, is valid
//! SPIR-V with `OpIgnoreIntersectionKHR` and a `HitAttributeKHR` variable; checkerboard-alpha
//! quads cut out exactly the analytic texels for closest-hit and shadow rays, ray by ray as on
//! `compute`, on two levels and merged (a mirrored instance, and an opaque instance sharing
//! the alpha-tested mesh); opaque scenes build no non-opaque geometry; nothing leaks.

mod common;

use raygraph::accel::cache::AccelSettings;
use raygraph::accel::rt_pipeline::{any_hit_binding_map, any_hit_spirv, entry_calls, live_hal_objects};
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions, Project};
use raygraph::runtime::batch::{BatchTracer, GpuRay};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{AlphaMode, Instance, Material, Mesh, Scene, TextureImage, Vertex};

/// The GPU tests of this file run one at a time: `live_hal_objects` counts the whole process.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Texels per side of the checkerboard alpha texture.
const CELLS: u32 = 8;

/// Whether texel (column, row) of the checkerboard is opaque (alpha 255; the others are 0).
fn opaque_texel(column: u32, row: u32) -> bool {
    (column + row).is_multiple_of(2)
}

/// The unit square in z = 0, facing +z, uv = (x, 1 - y): image row 0 at the top (y = 1).
fn quad() -> Mesh {
    let v = |x: f32, y: f32| Vertex { position: [x, y, 0.0], normal: [0.0, 0.0, 1.0], uv: [x, 1.0 - y] };
    Mesh {
        name: "quad".into(),
        vertices: vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    }
}

/// Instance 0: an alpha-tested quad (MASK 0.5) over x in [0, 1]; 1: the same, mirrored (x
/// negated) over x in [2, 3]; 2: the quad mesh with an opaque material over x in [4, 5];
/// 3: an opaque backdrop in z = -1 behind them all.
fn alpha_scene() -> Scene {
    let mut rgba = Vec::new();
    for row in 0..CELLS {
        for column in 0..CELLS {
            rgba.extend_from_slice(&[200, 200, 200, if opaque_texel(column, row) { 255 } else { 0 }]);
        }
    }
    let mut scene = raygraph::scene::builtin::default_scene();
    scene.set_name("alpha quads");
    *scene.textures_mut() = vec![TextureImage { name: "checker alpha".into(), width: CELLS, height: CELLS, rgba: rgba.into() }];
    let mut cutout = Material::diffuse("cutout", [1.0; 4], Some(0));
    cutout.alpha_mode = AlphaMode::Mask(0.5);
    *scene.materials_mut() = vec![cutout, Material::diffuse("opaque", [1.0; 4], None)];
    let mut backdrop = quad();
    backdrop.name = "backdrop".into();
    scene.set_meshes(vec![quad(), backdrop]);
    let at = |x: f32| glam::Mat4::from_translation(glam::Vec3::new(x, 0.0, 0.0));
    *scene.instances_mut() = vec![
        Instance { mesh: 0, material: 0, transform: at(0.0) },
        Instance { mesh: 0, material: 0, transform: at(3.0) * glam::Mat4::from_scale(glam::Vec3::new(-1.0, 1.0, 1.0)) },
        Instance { mesh: 0, material: 1, transform: at(4.0) },
        Instance {
            mesh: 1,
            material: 1,
            transform: glam::Mat4::from_scale_rotation_translation(glam::Vec3::new(8.0, 3.0, 1.0), glam::Quat::IDENTITY, glam::Vec3::new(-1.0, -1.0, -1.0)),
        },
    ];
    scene
}

/// One ray per texel of each quad instance (0..3), from z = +1 down to the quads (and
/// through a cut-out texel to the backdrop), with the instance it must hit; and the shadow
/// ray back up from the backdrop through the same point, which must be blocked exactly there.
fn rays() -> (Vec<GpuRay>, Vec<GpuRay>, Vec<u32>) {
    let (mut down, mut up, mut expected) = (Vec::new(), Vec::new(), Vec::new());
    for instance in 0..3u32 {
        for row in 0..CELLS {
            for column in 0..CELLS {
                // A tenth of a texel left of the texel centre in uv (off the quad's diagonal, the
                // edge its two triangles share; the bilinear alpha there is 0.9 or 0.1), its
                // point on the unit square, then in the world.
                let (u, v) = ((column as f32 + 0.4) / CELLS as f32, (row as f32 + 0.5) / CELLS as f32);
                let (x, y) = (u, 1.0 - v);
                let wx = match instance {
                    0 => x,
                    1 => 3.0 - x,
                    _ => 4.0 + x,
                };
                down.push(GpuRay { origin: [wx, y, 1.0], t_min: 0.0, dir: [0.0, 0.0, -1.0], t_max: 10.0 });
                up.push(GpuRay { origin: [wx, y, -0.999], t_min: 0.0, dir: [0.0, 0.0, 1.0], t_max: 1.5 });
                expected.push(if instance == 2 || opaque_texel(column, row) { instance } else { 3 });
            }
        }
    }
    (down, up, expected)
}

/// The SPIR-V words of `opcode` instructions in `words`.
fn count_op(words: &[u32], opcode: u32) -> usize {
    let mut at = 5;
    let mut n = 0;
    while at < words.len() {
        n += (words[at] & 0xffff == opcode) as usize;
        at += (words[at] >> 16) as usize;
    }
    n
}

/// Every trace pass of the shipped graphs, compiled for rt-pipeline with either texture path:
/// its any-hit shader patches, and `spirv-val` (SPIRV-Tools, installed by
/// `.ci/install-vulkan.sh`) accepts it for Vulkan 1.2.
#[test]
fn the_any_hit_shader_is_valid_spirv() {
    let spirv_val = std::process::Command::new("spirv-val").arg("--version").output().is_ok();
    assert!(spirv_val, "spirv-val not found: install SPIRV-Tools (`bash .ci/install-vulkan.sh` does)");
    let mut checked = 0;
    for bindless in [false, true] {
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let graph = common::repo().join(graph);
            let options = CompileOptions { includes: raygraph::runtime::gpu::include_aliases(bindless), backend: Backend::RtPipeline, ..Default::default() };
            let plan = compile_with(&graph, &Project::beside_graph(&graph), (64, 48), &options).unwrap();
            for pass in plan.passes().iter().filter(|p| p.shader.ray_tracing.is_some()) {
                let module = pass.shader.ray_tracing.as_ref().unwrap();
                // The pass's bindings in hal's numbering: each group's entries in order, the
                // texture binding array of 64 (any count makes the same instructions).
                let groups = pass.shader.bindings.iter().map(|b| b.group + 1).max().unwrap_or(0);
                let layouts: Vec<Vec<wgpu::BindGroupLayoutEntry>> = (0..groups)
                    .map(|g| {
                        pass.shader
                            .bindings
                            .iter()
                            .filter(|b| b.group == g)
                            .map(|b| wgpu::BindGroupLayoutEntry {
                                binding: b.binding,
                                visibility: wgpu::ShaderStages::ANY_HIT,
                                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                                count: matches!(b.kind, raygraph::graph::reflect::BindingKind::TextureBindingArray)
                                    .then(|| std::num::NonZeroU32::new(64).unwrap()),
                            })
                            .collect()
                    })
                    .collect();
                let words = any_hit_spirv(&module.module, &module.info, "trace_any_hit_shader", &pass.entry, any_hit_binding_map(&layouts))
                    .unwrap_or_else(|e| panic!("pass {}: {e}", pass.name));
                // OpIgnoreIntersectionKHR (4448) once; OpVariable (59) of storage class
                // HitAttributeKHR (5339) once.
                assert_eq!(count_op(&words, 4448), 1, "pass {}", pass.name);
                let hit_attributes = words.windows(4).filter(|w| w[0] == (4 << 16 | 59) && w[3] == 5339).count();
                assert_eq!(hit_attributes, 1, "pass {}", pass.name);
                {
                    let path = std::env::temp_dir().join(format!("raygraph-any-hit-{}-{}.spv", std::process::id(), checked));
                    std::fs::write(&path, words.iter().flat_map(|w| w.to_le_bytes()).collect::<Vec<u8>>()).unwrap();
                    let out = std::process::Command::new("spirv-val").arg("--target-env").arg("vulkan1.2").arg(&path).output().unwrap();
                    let _ = std::fs::remove_file(&path);
                    assert!(out.status.success(), "pass {}: spirv-val: {}", pass.name, String::from_utf8_lossy(&out.stderr));
                }
                checked += 1;
            }
        }
    }
    println!("{checked} any-hit modules patched and validated by spirv-val");
    assert!(checked >= 4, "the graphs' trace passes were not found");
}

/// The any-hit shader keeps its branch for closest-hit rays past BLEND surfaces
/// (TRACE_CLOSEST_RAYS) in the pipelines of passes that trace closest-hit rays, and only there:
/// the G-buffer's primary rays and the reflection rays call `trace_closest_flags`, the shadow
/// and AO passes do not (their pipelines' any-hit shaders compile the branch out).
#[test]
fn only_passes_that_trace_closest_hit_rays_keep_the_past_blend_branch() {
    let mut seen = std::collections::BTreeMap::new();
    for graph in ["graph/hybrid.ron", "graph/full_rt.ron", "graph/bench_rays.ron"] {
        let graph = common::repo().join(graph);
        let options = CompileOptions { includes: raygraph::runtime::gpu::include_aliases(false), backend: Backend::RtPipeline, ..Default::default() };
        let plan = compile_with(&graph, &Project::beside_graph(&graph), (64, 48), &options).unwrap();
        for pass in plan.passes().iter().filter(|p| p.shader.ray_tracing.is_some()) {
            let module = &pass.shader.ray_tracing.as_ref().unwrap().module;
            seen.insert(pass.name.clone(), entry_calls(module, &pass.entry, "trace_closest_flags"));
        }
    }
    println!("{seen:?}");
    let with = |prefix: &str| seen.iter().filter(move |(name, _)| name.starts_with(prefix)).map(|(_, &calls)| calls).collect::<Vec<_>>();
    for (prefix, expected) in [("gbuffer/", true), ("reflection/", true), ("shadow/", false), ("ao/", false)] {
        let found = with(prefix);
        assert!(!found.is_empty(), "no trace pass named {prefix}* in the shipped graphs: {seen:?}");
        assert!(found.iter().all(|&calls| calls == expected), "{prefix}*: calls trace_closest_flags should be {expected}: {seen:?}");
    }
}

/// The quads cut out exactly the opaque texels: closest-hit rays hit the quad there and the
/// backdrop elsewhere, shadow rays are blocked there only; the opaque instance of the same
/// mesh is hit everywhere. Ray by ray the same on rt-pipeline as on compute, with one BLAS per
/// mesh (shared by alpha-tested and opaque instances), one per instance, and merged.
#[test]
fn alpha_quads_cut_out_the_same_texels_on_rt_pipeline_as_on_compute() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    assert!(gpu.backends().contains(&Backend::RtPipeline), "lavapipe >= 24.1 has ray-tracing pipelines");
    let scene = alpha_scene();
    let (down, up, expected) = rays();
    let start = live_hal_objects();
    for settings in [AccelSettings { dedup: true, merge: false }, AccelSettings { dedup: false, merge: false }, AccelSettings { dedup: true, merge: true }] {
        let mut results = Vec::new();
        for backend in [Backend::Compute, Backend::RtPipeline] {
            let tracer = BatchTracer::with_settings(&gpu, backend, &scene, &common::repo().join("shaders"), settings).unwrap();
            let (hits, stats) = tracer.closest(&gpu, &down).unwrap();
            let (blocked, any_stats) = tracer.any(&gpu, &up).unwrap();
            let instances: Vec<u32> = hits.iter().map(|h| h.map_or(u32::MAX, |h| h.instance)).collect();
            let quad_hits = instances.iter().filter(|&&i| i < 3).count();
            println!(
                "{backend:?} {settings:?}: {quad_hits} of {} rays hit a quad, {} of {} shadow rays blocked",
                down.len(),
                blocked.iter().filter(|&&b| b).count(),
                up.len()
            );
            assert_eq!(instances, expected, "{backend:?} {settings:?}: the instance each ray hits");
            // Half the texels of each alpha-tested quad are opaque, and all of the opaque one.
            assert_eq!(quad_hits, 32 + 32 + 64, "{backend:?} {settings:?}");
            let expect_blocked: Vec<bool> = expected.iter().map(|&i| i < 3).collect();
            assert_eq!(blocked, expect_blocked, "{backend:?} {settings:?}: the shadow rays blocked");
            assert_eq!((stats.hits, any_stats.hits), (down.len() as u64, 128), "{backend:?} {settings:?}: hit counters");
            results.push(hits);
        }
        // The same triangle and barycentrics on both back-ends.
        for (k, (c, r)) in results[0].iter().zip(&results[1]).enumerate() {
            let (c, r) = (c.unwrap(), r.unwrap());
            assert_eq!((c.instance, c.primitive, c.front_face), (r.instance, r.primitive, r.front_face), "{settings:?} ray {k}");
            assert!(
                (c.t - r.t).abs() < 1e-5 && (c.bary[0] - r.bary[0]).abs() < 1e-4 && (c.bary[1] - r.bary[1]).abs() < 1e-4,
                "{settings:?} ray {k}: {c:?} against {r:?}"
            );
        }
    }
    assert_eq!(live_hal_objects(), start, "hal objects left after the tracers were dropped");
}

/// Only alpha-tested geometry is built non-opaque (so the any-hit shader runs nowhere else):
/// none in the default scene, the quad mesh's one geometry (two levels) or the alpha-tested
/// triangles' geometry (merged) in the alpha scene; and the executors leave no hal object.
#[test]
fn only_alpha_tested_geometry_is_non_opaque() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    let start = live_hal_objects();
    let hybrid = std::fs::read_to_string(common::repo().join("graph/hybrid.ron")).unwrap();
    assert!(hybrid.contains("Accel(merge: true)"), "graph/hybrid.ron changed: update the test");
    let p = common::TempProject::with_repo_files();
    p.write("graph/two_level.ron", &hybrid.replace("Accel(merge: true)", "Accel()"));
    for graph in [p.root.join("graph/two_level.ron"), common::repo().join("graph/hybrid.ron")] {
        for (scene, non_opaque) in [(raygraph::scene::builtin::default_scene(), 0), (alpha_scene(), 1)] {
            let plan = compile_with(&graph, &Project::beside_graph(&graph), (64, 48), &gpu.compile_options_for(Backend::RtPipeline)).unwrap();
            let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
            exec.render(&gpu, scene.camera(), &scene).unwrap();
            let rt = exec.accel().and_then(|c| c.rt_accel()).expect("the rt-pipeline structures");
            assert_eq!(rt.non_opaque_geometries(), non_opaque, "{} on {}", scene.name(), graph.display());
        }
    }
    assert_eq!(live_hal_objects(), start, "hal objects left after the executors were dropped");
}
