//! A pass kind written in Rust (`examples/rust_pass.rs`) on the GPU (lavapipe in CI): it inverts
//! what the WGSL pass before it drew, gets its timestamps and its row in the pass table, follows
//! `set_param`, and a graph naming a Rust pass the executor does not have is an error naming
//! the layer file and the pass.

use raygraph::graph::desc::ParamValue;
use raygraph::runtime::{Gpu, RustPasses};

mod common;
use common::TempProject;

#[allow(dead_code)] // `main` is the example's; the tests call its functions
#[path = "../examples/rust_pass.rs"]
mod rust_pass;

fn gpu() -> Gpu {
    Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required for GPU tests")
}

#[test]
fn the_rust_pass_inverts_what_the_wgsl_pass_drew() {
    let dir = TempProject::new();
    let (invert_graph, gradient_graph) = rust_pass::write_project(&dir.root).unwrap();
    let gpu = gpu();
    let (gradient, _, _) = rust_pass::render(&gpu, &gradient_graph).unwrap();
    let (inverted, timings, mut exec) = rust_pass::render(&gpu, &invert_graph).unwrap();
    assert_eq!(inverted.dimensions(), rust_pass::SIZE);
    assert!(gradient.pixels().any(|p| p != gradient.get_pixel(0, 0)), "the gradient is one flat colour");
    for (x, y, g) in gradient.enumerate_pixels() {
        let i = inverted.get_pixel(x, y);
        assert_eq!(i.0, [255 - g[0], 255 - g[1], 255 - g[2], g[3]], "pixel ({x}, {y}): gradient {g:?}, inverted {i:?}");
    }

    // The Rust pass is a pass like the others: a row in the pass table, a timestamp pair.
    let names: Vec<(String, &'static str)> = exec.plan().passes().iter().map(|p| (p.name.clone(), p.kind.name())).collect();
    assert_eq!(names, vec![("gradient/gradient".to_string(), "compute"), ("invert/invert".to_string(), "rust")]);
    let table = raygraph::runtime::profiler::pass_table(&names, std::slice::from_ref(&timings), 1);
    assert!(table.contains("invert/invert") && table.contains("rust"), "{table}");
    assert_eq!(timings.cpu_ms.len(), 2);
    if gpu.timestamps() {
        let gpu_ms = timings.gpu_ms.as_ref().expect("timestamps are on");
        assert_eq!(gpu_ms.len(), 2);
        assert!(gpu_ms.iter().all(|ms| ms.is_finite() && *ms >= 0.0), "{gpu_ms:?}");
    }

    // Its parameter reaches it: amount 0 leaves the gradient as it is.
    assert!(exec.set_param(&gpu, "invert", "amount", ParamValue::Float(0.0)).unwrap());
    let scene = raygraph::scene::builtin::default_scene();
    exec.render(&gpu, scene.camera(), &scene).unwrap();
    assert_eq!(exec.read_output(&gpu).unwrap(), gradient);
}

#[test]
fn a_rust_pass_that_is_not_registered_is_an_error_naming_the_layer_file_and_the_pass() {
    let dir = TempProject::new();
    let (invert_graph, _) = rust_pass::write_project(&dir.root).unwrap();
    let gpu = gpu();
    let err = rust_pass::executor(&gpu, &invert_graph, RustPasses::new()).err().expect("the graph runs a Rust pass nobody registered").to_string();
    assert!(err.contains("invert.ron"), "{err}");
    assert!(err.contains("pass `invert/invert` runs Rust pass `invert`, which is not registered"), "{err}");
    assert!(err.contains("registered: none"), "{err}");

    // Registered under another name: the help lists what is registered.
    let other = RustPasses::new().with("blur", rust_pass::Invert::default);
    let err = rust_pass::executor(&gpu, &invert_graph, other).err().expect("`invert` is still not registered").to_string();
    assert!(err.contains("registered: blur"), "{err}");
}
