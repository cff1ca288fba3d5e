//! History resources (`LayerDesc::history`): the compiler gives a history and the resource it
//! keeps slots of their own, keeps the pass that writes it when only the next frame reads it,
//! and refuses bad declarations with the layer file's place; the executor swaps the two
//! textures before every frame (no copy), and `frame.history_valid` says when the history
//! holds the previous frame: not on the first frame, and not after a camera cut.

mod common;

use common::{gpu, TempProject};
use raygraph::graph::compile::Plan;
use raygraph::runtime::Executor;
use raygraph::scene::builtin::default_scene;
use raygraph::scene::Camera;

/// A layer that counts frames per texel: `count` = the previous frame's `count` + 1 where the
/// history is valid, else 1; `color` shows it for the graph's 8-bit output.
const COUNT_LAYER: &str = r#"Layer(
    outputs: {
        "count": Texture(format: Rgba32Float),
        "color": Texture(format: Rgba8Unorm),
    },
    history: {"count_previous": "count"},
    passes: [
        Pass(name: "count", kind: Compute, shader: "test/count.wgsl", reads: ["count_previous"], writes: ["count"]),
        Pass(name: "show", kind: Compute, shader: "test/show.wgsl", reads: ["count"], writes: ["color"]),
    ],
)
"#;

const COUNT_WGSL: &str = r#"//#include "common/frame.wgsl"
@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var count_previous: texture_2d<f32>;
@group(0) @binding(2) var count: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(count);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    var n = 1.0;
    if (frame.history_valid == 1u) {
        n = textureLoad(count_previous, id.xy, 0).x + 1.0;
    }
    textureStore(count, id.xy, vec4<f32>(n, f32(frame.frame_index), 0.0, 1.0));
}
"#;

const SHOW_WGSL: &str = r#"@group(0) @binding(0) var count: texture_2d<f32>;
@group(0) @binding(1) var color: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(color, id.xy, vec4<f32>(textureLoad(count, id.xy, 0).x / 255.0, 0.0, 0.0, 1.0));
}
"#;

const GRAPH: &str = r#"Graph(output: "counter.color", nodes: {"counter": Layer(layer: "count")})"#;

fn project(layer: &str) -> TempProject {
    let p = TempProject::with_repo_files();
    p.write("layers/count.ron", layer);
    p.write("shaders/test/count.wgsl", COUNT_WGSL);
    p.write("shaders/test/show.wgsl", SHOW_WGSL);
    p
}

fn resource(plan: &Plan, name: &str) -> usize {
    plan.resource_by_name(name).unwrap_or_else(|| panic!("no resource {name}"))
}

#[test]
fn a_history_and_the_texture_it_keeps_get_slots_of_their_own_and_show_in_the_plan() {
    let p = project(COUNT_LAYER);
    let plan = p.compile("count.ron", GRAPH).unwrap_or_else(|e| panic!("{e}"));
    let (count, previous, color) = (resource(&plan, "counter.count"), resource(&plan, "counter.count_previous"), resource(&plan, "counter.color"));
    let slot = |r: usize| plan.resources()[r].slot.expect("allocated");
    assert_ne!(slot(count), slot(previous));
    for r in [count, previous] {
        assert!(plan.resources()[r].persistent);
        assert_eq!(plan.slots()[slot(r)].members, vec![r], "{} shares its slot", plan.resources()[r].name);
    }
    assert_eq!(plan.resources()[previous].history_of, Some(count));
    assert!(!plan.resources()[color].persistent);
    let report = plan.report();
    assert!(report.contains("history: the previous frame of counter.count"), "{report}");
    assert!(report.contains("kept for the next frame"), "{report}");
    let dot = raygraph::graph::dot::to_dot(&plan);
    assert!(dot.contains("style=dashed label=\"next frame\""), "{dot}");
}

/// A layer whose `integrate` pass writes `sum`, which only the next frame reads (as
/// `sum_previous`, in `count`), with `count` reading `sum_previous` or not.
fn integrating_layer(count_reads_sum: bool) -> TempProject {
    let reads = if count_reads_sum { r#"["count_previous", "sum_previous"]"# } else { r#"["count_previous"]"# };
    let layer = format!(
        r#"Layer(
    outputs: {{"count": Texture(format: Rgba32Float), "sum": Texture(format: Rgba32Float), "color": Texture(format: Rgba8Unorm)}},
    history: {{"count_previous": "count", "sum_previous": "sum"}},
    passes: [
        Pass(name: "count", kind: Compute, shader: "test/count.wgsl", reads: {reads}, writes: ["count"]),
        Pass(name: "integrate", kind: Compute, shader: "test/integrate.wgsl", reads: ["count_previous"], writes: ["sum"]),
        Pass(name: "show", kind: Compute, shader: "test/show.wgsl", reads: ["count"], writes: ["color"]),
    ],
)
"#
    );
    let p = project(&layer);
    if count_reads_sum {
        let wgsl = COUNT_WGSL
            .replace("var count: texture_storage_2d", "var sum_previous: texture_2d<f32>;\n@group(0) @binding(3) var count: texture_storage_2d")
            .replace("var n = 1.0;", "var n = 1.0 + 0.0 * textureLoad(sum_previous, id.xy, 0).x;");
        p.write("shaders/test/count.wgsl", &wgsl);
    }
    p.write(
        "shaders/test/integrate.wgsl",
        &COUNT_WGSL.replace("count:", "sum:").replace("(count)", "(sum)").replace("textureStore(count,", "textureStore(sum,"),
    );
    p
}

#[test]
fn a_pass_whose_output_only_the_next_frame_reads_is_kept() {
    let p = integrating_layer(false);
    let plan = p.compile("count.ron", GRAPH).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plan.culled(), ["counter/integrate"], "nothing reads `sum_previous`: `integrate` is culled");
    assert!(plan.resources()[resource(&plan, "counter.sum_previous")].slot.is_none());
    let p = integrating_layer(true);
    let plan = p.compile("count.ron", GRAPH).unwrap_or_else(|e| panic!("{e}"));
    assert!(plan.culled().is_empty(), "`sum_previous` is read: `integrate` is kept ({:?})", plan.culled());
    assert!(plan.resources()[resource(&plan, "counter.sum")].persistent);
}

#[test]
fn bad_history_declarations_are_refused_with_the_layer_file_and_the_name() {
    let cases = [
        (
            COUNT_LAYER.replace(r#"{"count_previous": "count"}"#, r#"{"count_previous": "counts"}"#),
            "history `count_previous` keeps `counts`, which is not an output or transient",
        ),
        (COUNT_LAYER.replace(r#"{"count_previous": "count"}"#, r#"{"color": "count"}"#), "history `color` of layer `count` has the name of another resource"),
        (
            COUNT_LAYER.replace(r#"writes: ["count"]),"#, r#"writes: ["count", "count_previous"]),"#),
            "writes `count_previous`, the previous frame of `count`, which only the executor writes",
        ),
        (
            COUNT_LAYER
                .replace(r#""count": Texture(format: Rgba32Float),"#, r#""count": Texture(format: Rgba32Float), "list": Buffer(size: 64),"#)
                .replace(r#""count_previous": "count""#, r#""count_previous": "count", "list_previous": "list""#),
            "history `list_previous` keeps `list`, a Buffer",
        ),
    ];
    for (layer, expected) in cases {
        let p = project(&layer);
        let e = p.compile("count.ron", GRAPH).err().unwrap_or_else(|| panic!("compiled: {layer}"));
        let text = e.to_string();
        assert!(text.contains(expected), "expected `{expected}` in:\n{text}");
        assert!(text.contains("count.ron"), "the error names the layer file:\n{text}");
    }
}

fn texel(gpu: &raygraph::runtime::Gpu, exec: &Executor, name: &str) -> [f32; 4] {
    common::channel(gpu, exec, name)[5]
}

#[test]
fn the_executor_swaps_the_textures_every_frame_and_the_history_is_valid_between_cuts() {
    let gpu = gpu();
    let p = project(COUNT_LAYER);
    let plan = p.compile("count.ron", GRAPH).unwrap_or_else(|e| panic!("{e}"));
    let count = resource(&plan, "counter.count");
    let scene = default_scene();
    let mut camera = *scene.camera();
    let mut exec = Executor::new(&gpu, plan, &scene).unwrap();
    let mut textures = Vec::new();
    for frame in 1..=4 {
        exec.render(&gpu, &camera, &scene).unwrap();
        assert_eq!(exec.history_valid(), frame > 1);
        assert_eq!(texel(&gpu, &exec, "counter.count")[0], frame as f32, "frame {frame}");
        // The first frame has no history: its previous count is the texture's initial zero.
        assert_eq!(texel(&gpu, &exec, "counter.count_previous")[0], frame as f32 - 1.0, "frame {frame}");
        textures.push(exec.texture(count).unwrap().clone());
    }
    // Two textures, alternating: swapped, not copied.
    assert!(textures[0] != textures[1] && textures[0] == textures[2] && textures[1] == textures[3]);
    // An explicit cut, then a camera jump of half the scene: the count starts again.
    exec.camera_cut();
    exec.render(&gpu, &camera, &scene).unwrap();
    assert!(!exec.history_valid());
    assert_eq!(texel(&gpu, &exec, "counter.count")[0], 1.0);
    exec.render(&gpu, &camera, &scene).unwrap();
    assert_eq!(texel(&gpu, &exec, "counter.count")[0], 2.0);
    let radius = 0.5 * scene.bounds().diagonal();
    camera = Camera { position: camera.position + glam::Vec3::X * radius * 0.5, target: camera.target + glam::Vec3::X * radius * 0.5, ..camera };
    exec.render(&gpu, &camera, &scene).unwrap();
    assert!(!exec.history_valid(), "a jump of half the scene's radius is a cut");
    assert_eq!(texel(&gpu, &exec, "counter.count")[0], 1.0);
    // A small move keeps the history.
    camera.position += glam::Vec3::X * radius * 0.01;
    exec.render(&gpu, &camera, &scene).unwrap();
    assert!(exec.history_valid());
    assert_eq!(texel(&gpu, &exec, "counter.count")[0], 2.0);
}
