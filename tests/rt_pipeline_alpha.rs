//! The rt-pipeline back-end's alpha-tested hit group (src/accel/rt_pipeline.rs and
//! rt_pipeline/any_hit.rs): the any-hit shader, written by naga and patched as SPIR-V, is valid
//! SPIR-V with `OpIgnoreIntersectionKHR` and a `HitAttributeKHR` variable.

mod common;

use raygraph::accel::backend::Backend;
use raygraph::accel::rt_pipeline::{any_hit_binding_map, any_hit_spirv};
use raygraph::graph::compile::{compile_with, CompileOptions, Project};

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
/// its any-hit shader patches, and `spirv-val` (SPIRV-Tools, where installed: CI's Vulkan
/// validation layer checks the same module when the pipeline is made) accepts it for Vulkan 1.2.
#[test]
fn the_any_hit_shader_is_valid_spirv() {
    let spirv_val = std::process::Command::new("spirv-val").arg("--version").output().is_ok();
    let mut checked = 0;
    for bindless in [false, true] {
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let graph = common::repo().join(graph);
            let options = CompileOptions { includes: raygraph::runtime::gpu::include_aliases(bindless), backend: Backend::RtPipeline, ..Default::default() };
            let plan = compile_with(&graph, &Project::beside_graph(&graph), (64, 48), &options).unwrap();
            for pass in plan.passes.iter().filter(|p| p.shader.ray_tracing.is_some()) {
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
                let words = any_hit_spirv(&module.module, &module.info, "trace_any_hit_shader", any_hit_binding_map(&layouts))
                    .unwrap_or_else(|e| panic!("pass {}: {e}", pass.name));
                // OpIgnoreIntersectionKHR (4448) once; OpVariable (59) of storage class
                // HitAttributeKHR (5339) once.
                assert_eq!(count_op(&words, 4448), 1, "pass {}", pass.name);
                let hit_attributes = words.windows(4).filter(|w| w[0] == (4 << 16 | 59) && w[3] == 5339).count();
                assert_eq!(hit_attributes, 1, "pass {}", pass.name);
                if spirv_val {
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
    println!("{checked} any-hit modules patched{}", if spirv_val { " and validated by spirv-val" } else { " (spirv-val not installed)" });
    assert!(checked >= 4, "the graphs' trace passes were not found");
}
