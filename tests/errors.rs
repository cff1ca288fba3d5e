//! Every class of compile error, each asserting its kind and the file:line it points at.

mod common;
use common::{line_of, TempProject};
use raygraph::error::{ErrorKind, GraphError};

fn expect(err: Result<raygraph::graph::Plan, GraphError>, kind: ErrorKind, file_suffix: &str, line: u32) -> GraphError {
    let e = match err {
        Ok(_) => panic!("expected a {kind:?} error, but the graph compiled"),
        Err(e) => e,
    };
    let text = e.to_string();
    assert_eq!(e.kind, kind, "wrong error class: {text}");
    assert!(e.location.file.ends_with(file_suffix), "error should point at {file_suffix}: {text}");
    assert_eq!(e.location.line, line, "wrong line: {text}");
    assert!(e.location.col >= 1);
    let prefix = format!("{}:{}:{}: error:", e.location.file.display(), e.location.line, e.location.col);
    assert!(text.starts_with(&prefix), "message must start with file:line:col: {text}");
    assert!(e.help.is_some(), "every error says what to change: {text}");
    e
}

/// Compiles `graph` with layer file `layer` (a path under the project) written as `broken`:
/// an error of `kind` at the line of `broken` that holds `at`, whose message holds `message`.
fn expect_in_layer(repo: &TempProject, graph: &str, (layer, broken): (&str, &str), kind: ErrorKind, (at, message): (&str, &str)) -> GraphError {
    repo.write(layer, broken);
    let e = expect(repo.compile("g.ron", graph), kind, layer, line_of(broken, at));
    assert!(e.to_string().contains(message), "{message}: {e}");
    e
}

const GOOD: &str = r#"Graph(
    output: "out.color",
    nodes: {
        "fill": Layer(layer: "fill", params: {"value": 0.5}),
        "out": Layer(layer: "to8", inputs: {"src": "fill.color"}),
    },
)
"#;

#[test]
fn the_baseline_graph_compiles() {
    let p = TempProject::new();
    let plan = p.compile("good.ron", GOOD).expect("baseline compiles");
    assert_eq!(plan.passes().len(), 2);
}

#[test]
fn syntax_error() {
    let p = TempProject::new();
    let g = GOOD.replace(r#""fill": Layer(layer: "fill", params: {"value": 0.5}),"#, r#""fill": Layer(layer: "fill" params: {"value": 0.5}),"#);
    expect(p.compile("g.ron", &g), ErrorKind::Syntax, "graph/g.ron", line_of(&g, r#""fill": Layer"#));
}

#[test]
fn syntax_error_in_layer_file() {
    let p = TempProject::new();
    let layer = "Layer(\n    outputs: {\n        \"color\": Texture(format: Rgba16Floatt),\n    },\n    passes: [],\n)\n";
    p.write("layers/broken.ron", layer);
    let g = GOOD.replace(r#"layer: "fill""#, r#"layer: "broken""#);
    expect(p.compile("g.ron", &g), ErrorKind::Syntax, "layers/broken.ron", 3);
}

/// Two `Accel` nodes: refused at the second, naming both (one cache per graph).
#[test]
fn two_accel_nodes() {
    let p = TempProject::new();
    let g = GOOD.replace(
        r#""fill": Layer(layer: "fill", params: {"value": 0.5}),"#,
        "\"fill\": Layer(layer: \"fill\", params: {\"value\": 0.5}),\n        \"accel_a\": Accel(),\n        \"accel_b\": Accel(merge: true),",
    );
    let e = expect(p.compile("g.ron", &g), ErrorKind::Unsupported, "graph/g.ron", line_of(&g, r#""accel_b""#));
    let text = e.to_string();
    assert!(text.contains("2 Accel nodes") && text.contains("`accel_a`") && text.contains("`accel_b`"), "{text}");
}

#[test]
fn unknown_layer() {
    let p = TempProject::new();
    let g = GOOD.replace(r#"layer: "to8""#, r#"layer: "to_eight""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::UnknownLayer, "graph/g.ron", line_of(&g, "to_eight"));
    assert!(e.to_string().contains("to8"), "help lists the known layers: {e}");
}

#[test]
fn unknown_node_output() {
    let p = TempProject::new();
    let g = GOOD.replace(r#""src": "fill.color""#, r#""src": "fill.colour""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::UnknownOutput, "graph/g.ron", line_of(&g, "fill.colour"));
    assert!(e.to_string().contains("color"), "help lists the outputs: {e}");
    let g = GOOD.replace(r#""src": "fill.color""#, r#""src": "fil.color""#);
    expect(p.compile("g2.ron", &g), ErrorKind::UnknownOutput, "graph/g2.ron", line_of(&g, "fil.color"));
    let g = GOOD.replace(r#"output: "out.color""#, r#"output: "out.rgb""#);
    expect(p.compile("g3.ron", &g), ErrorKind::UnknownOutput, "graph/g3.ron", line_of(&g, "out.rgb"));
}

/// `hdr_output`: kept to the end of the frame, with the passes that write it, where it names a
/// float output; an unknown output or a texture that is not float RGBA is an error at its line;
/// a switched-off node gives none.
#[test]
fn hdr_output_names_a_float_output() {
    let p = TempProject::new();
    // A second `fill` node that the presented output does not read.
    let spare = GOOD.replace("    nodes: {", "    nodes: {\n        \"spare\": Layer(layer: \"fill\"),");
    let with = |hdr: &str| spare.replace("    nodes: {", &format!("    hdr_output: \"{hdr}\",\n    nodes: {{"));
    let without = p.compile("spare.ron", &spare).unwrap();
    assert_eq!((without.hdr_output(), without.culled()), (None, &["spare/fill".to_string()][..]), "no field: no HDR output");
    let plan = p.compile("hdr.ron", &with("spare.color")).expect("a float output");
    let hdr = plan.hdr_output().expect("the plan has the HDR output");
    assert_eq!((plan.resources()[hdr].name.as_str(), plan.passes().len()), ("spare.color", 3), "its writer is kept");
    assert_eq!(plan.resources()[hdr].last_use, plan.passes().len() - 1, "it lives to the end of the frame");
    assert!(plan.resources()[hdr].usage.copy_src, "it can be read back");
    let g = with("spare.colour");
    expect(p.compile("h1.ron", &g), ErrorKind::UnknownOutput, "graph/h1.ron", line_of(&g, "spare.colour"));
    let g = with("out.color");
    let e = expect(p.compile("h2.ron", &g), ErrorKind::Unsupported, "graph/h2.ron", line_of(&g, "hdr_output"));
    assert!(e.to_string().contains("Rgba16Float"), "{e}");
    let options = raygraph::graph::compile::CompileOptions { enabled: [("spare".to_string(), false)].into(), ..Default::default() };
    let path = p.write("graph/h3.ron", &with("spare.color"));
    let off = raygraph::graph::compile::compile_with(&path, &p.project(), (8, 8), &options).unwrap();
    assert_eq!((off.hdr_output(), off.passes().len()), (None, 2), "its node switched off: no HDR output");
}

/// A graph of `invert` nodes, each `(name, the node it reads)`, with `out` reading `tail`.
fn invert_loop(links: &[(&str, &str)], tail: &str) -> String {
    let nodes: String = links.iter().map(|(n, from)| format!("        \"{n}\": Layer(layer: \"invert\", inputs: {{\"src\": \"{from}.dst\"}}),\n")).collect();
    format!(
        "Graph(\n    output: \"out.color\",\n    nodes: {{\n{nodes}        \"out\": Layer(layer: \"to8\", inputs: {{\"src\": \"{tail}.dst\"}}),\n    }},\n)\n"
    )
}

#[test]
fn names_in_comments_do_not_move_the_error() {
    let p = TempProject::new();
    let comments = "nodes: {\n        // \"out\": Layer(layer: \"to_eight\"), \"src\": \"fill.colour\" /* \"fill\" */\n        /* \"out\": Layer(layer:\n           /* nested */ \"to_eight\"), \"fill.colour\" */";
    let g = GOOD.replace(r#"layer: "to8""#, r#"layer: "to_eight""#).replace("nodes: {", comments);
    expect(p.compile("g.ron", &g), ErrorKind::UnknownLayer, "graph/g.ron", line_of(&g, r#""out": Layer(layer: "to_eight", inputs"#));
    let g = GOOD.replace(r#""src": "fill.color""#, r#""src": "fill.colour""#).replace("nodes: {", comments);
    expect(p.compile("g2.ron", &g), ErrorKind::UnknownOutput, "graph/g2.ron", line_of(&g, r#"{"src": "fill.colour"}"#));
    // A string holding `//` is not a comment.
    let g = GOOD.replace(r#""fill": Layer"#, "\"a//b\": Layer(layer: \"fill\",\n            params: {\"value\": 1.5}),\n        \"fill\": Layer");
    expect(p.compile("g3.ron", &g), ErrorKind::ParamOutOfRange, "graph/g3.ron", line_of(&g, r#""value": 1.5"#));
}

#[test]
fn cycle() {
    let p = TempProject::new();
    let g = invert_loop(&[("a", "b"), ("b", "a")], "b");
    let e = p.compile("g.ron", &g).expect_err("cycle");
    assert_eq!(e.kind, ErrorKind::Cycle, "{e}");
    assert!(e.location.file.ends_with("graph/g.ron"));
    let text = e.to_string();
    assert!(text.contains("cycle: a -> b -> a") || text.contains("cycle: b -> a -> b"), "names the whole path: {text}");
    let first = if text.contains("cycle: a ->") { r#""a": Layer"# } else { r#""b": Layer"# };
    assert_eq!(e.location.line, line_of(&g, first), "points at the path's first node: {text}");

    // A longer loop through three nodes, with a node outside it.
    let g = invert_loop(&[("a", "c"), ("b", "a"), ("c", "b")], "c");
    let e = p.compile("g3.ron", &g).expect_err("cycle of three");
    assert_eq!(e.kind, ErrorKind::Cycle, "{e}");
    let text = e.to_string();
    let paths = ["a -> b -> c -> a", "b -> c -> a -> b", "c -> a -> b -> c"];
    assert!(paths.iter().any(|p| text.contains(&format!("cycle: {p}"))), "names the whole path: {text}");
    assert!(!text.contains("-> out") && !text.contains("cycle: out"), "the path holds only the loop's nodes: {text}");
}

#[test]
fn read_with_no_producer() {
    let p = TempProject::new();
    // An input left unconnected.
    let g = GOOD.replace(r#", inputs: {"src": "fill.color"}"#, "");
    expect(p.compile("g.ron", &g), ErrorKind::NoProducer, "graph/g.ron", line_of(&g, r#""out": Layer"#));
    // A pass that reads a transient no pass writes.
    let layer = r#"Layer(
    outputs: { "color": Texture(format: Rgba16Float) },
    transients: { "tmp": Texture(format: Rgba16Float) },
    passes: [
        Pass(name: "invert", kind: Compute, shader: "test/invert.wgsl", reads: ["tmp"], writes: ["color"]),
    ],
)
"#;
    p.write("layers/orphan.ron", layer);
    let g = GOOD.replace(r#"layer: "fill", params: {"value": 0.5}"#, r#"layer: "orphan""#);
    expect(p.compile("g2.ron", &g), ErrorKind::NoProducer, "layers/orphan.ron", line_of(layer, r#"name: "invert""#));
}

#[test]
fn every_unconnected_input_is_reported_at_once() {
    let p = TempProject::new();
    // Two nodes without their `src`: `inv` (added) and `out` (its connection removed).
    let g = GOOD.replace(r#", inputs: {"src": "fill.color"}"#, "").replace(r#"        "out":"#, "        \"inv\": Layer(layer: \"invert\"),\n        \"out\":");
    let g = g.as_str();
    let e = expect(p.compile("g.ron", g), ErrorKind::NoProducer, "graph/g.ron", line_of(g, r#""inv": Layer"#));
    assert!(e.message.starts_with("2 inputs are not connected"), "{e}");
    assert!(e.message.contains("input `src` of node `inv` (layer `invert`)"), "{e}");
    assert_eq!(e.notes.len(), 1, "one note per further input: {e}");
    let (loc, text) = &e.notes[0];
    assert_eq!(loc.line, line_of(g, r#""out": Layer"#), "{e}");
    assert_eq!(text, "input `src` of node `out` (layer `to8`)", "{e}");
}

#[test]
fn two_producers() {
    let p = TempProject::new();
    let layer = r#"Layer(
    outputs: { "color": Texture(format: Rgba16Float) },
    params: { "value": Float(default: 1.0, min: 0.0, max: 1.0), "counter": Int(default: 0, min: 0, max: 15) },
    passes: [
        Pass(name: "first", kind: Compute, shader: "test/fill.wgsl", writes: ["color"]),
        Pass(name: "second", kind: Compute, shader: "test/fill.wgsl", writes: ["color"]),
    ],
)
"#;
    p.write("layers/twice.ron", layer);
    let g = GOOD.replace(r#"layer: "fill""#, r#"layer: "twice""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::TwoProducers, "layers/twice.ron", line_of(layer, r#"name: "second""#));
    assert_eq!(e.notes[0].0.line, line_of(layer, r#"name: "first""#), "notes the first producer: {e}");
}

/// A texture of several layers is written a layer at a time, by render passes that each name
/// one: a compute pass writing it is refused at the pass, a texture of 0 or too many layers at
/// its declaration, and two passes on one layer are two producers.
#[test]
fn layered_textures_are_written_one_layer_a_pass() {
    let p = TempProject::new();
    let layer = r#"Layer(
    outputs: { "color": Texture(format: Rgba16Float) },
    transients: { "scratch": Texture(format: Rgba16Float, layers: 2) },
    params: { "value": Float(default: 1.0, min: 0.0, max: 1.0), "counter": Int(default: 0, min: 0, max: 15) },
    passes: [
        Pass(name: "fill", kind: Compute, shader: "test/fill.wgsl", writes: ["color"]),
        Pass(name: "fill_layers", kind: Compute, shader: "test/fill.wgsl", writes: ["color=scratch"]),
    ],
)
"#;
    p.write("layers/layered.ron", layer);
    let g = GOOD.replace(r#"layer: "fill""#, r#"layer: "layered""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::Unsupported, "layers/layered.ron", line_of(layer, r#"name: "fill_layers""#));
    assert!(e.to_string().contains("2 layers"), "{e}");
    for count in ["0", "257"] {
        let none = layer.replace("layers: 2", &format!("layers: {count}"));
        p.write("layers/layered.ron", &none);
        let e = expect(p.compile("g.ron", &g), ErrorKind::Syntax, "layers/layered.ron", line_of(&none, r#""scratch""#));
        assert!(e.to_string().contains(&format!("declares {count} layers")), "{e}");
    }

    let repo = TempProject::with_repo_files();
    let shadow_layer = std::fs::read_to_string(repo.root.join("layers/shadow_map.ron")).unwrap();
    let same_layer = shadow_layer.replace(
        r#"name: "cube_1", kind: SceneRaster, shader: "shadow_map/shadow_map.wgsl", writes: ["cube"], layer: Some(1)"#,
        r#"name: "cube_1", kind: SceneRaster, shader: "shadow_map/shadow_map.wgsl", writes: ["cube"], layer: Some(0)"#,
    );
    assert_ne!(same_layer, shadow_layer, "layers/shadow_map.ron no longer draws cube_1 into layer 1");
    let raster = std::fs::read_to_string(common::repo().join("graph/raster.ron")).unwrap();
    let shadow = ("layers/shadow_map.ron", same_layer.as_str());
    expect_in_layer(&repo, &raster, shadow, ErrorKind::TwoProducers, (r#"name: "cube_1""#, "(layer 0)"));
}

/// A pass's shadow tiles hold the slots from its `shadow_slot` on: tiles without a slot, or
/// more tiles than the slots left, or a grid without a column, or tiles of no texel, are refused
/// at the pass.
#[test]
fn shadow_tiles_hold_slots_that_exist() {
    let repo = TempProject::with_repo_files();
    let shadow_layer = std::fs::read_to_string(repo.root.join("layers/shadow_map.ron")).unwrap();
    let raster = std::fs::read_to_string(common::repo().join("graph/raster.ron")).unwrap();
    let cube_1 = r#"shadow_slot: Some(10), shadow_tiles: Some(3, 2)"#;
    assert!(shadow_layer.contains(cube_1), "layers/shadow_map.ron no longer draws cube_1 as 3 x 2 tiles from slot 10");
    let cases = [
        ("cull_closed_back_faces: false, shadow_tiles: Some(3, 2)", "has `shadow_tiles` but no `shadow_slot`"),
        ("cull_closed_back_faces: true, shadow_slot: Some(10), shadow_tiles: Some(3, 3)", "3 x 3 shadow tiles from slot 10, but there are 16 slots"),
        ("cull_closed_back_faces: true, shadow_slot: Some(10), shadow_tiles: Some(0, 2)", "0 x 2 shadow tiles from slot 10"),
    ];
    for (options, message) in cases {
        let broken = shadow_layer.replace(&format!("cull_closed_back_faces: true, {cube_1}"), options);
        assert_ne!(broken, shadow_layer);
        expect_in_layer(&repo, &raster, ("layers/shadow_map.ron", &broken), ErrorKind::Unsupported, (r#"name: "cube_1""#, message));
    }
    let tiny = shadow_layer.replace(
        r#""cube": Texture(format: Depth32Float, size: Absolute(3072, 2048), layers: 2)"#,
        r#""cube": Texture(format: Depth32Float, size: Absolute(2, 2), layers: 2)"#,
    );
    assert_ne!(tiny, shadow_layer, "layers/shadow_map.ron no longer declares `cube` as 3072x2048, 2 layers");
    let message = "3 x 2 shadow tiles into `cube` of 2x2 texels";
    expect_in_layer(&repo, &raster, ("layers/shadow_map.ron", &tiny), ErrorKind::Unsupported, (r#"name: "cube_0""#, message));
}

/// A pass's `runs_when` names a buffer of its layer, of two words at least, that a pass of
/// the layer writes, and a finite, non-negative fraction; anything else is refused at the pass.
#[test]
fn runs_when_counts_in_a_buffer_the_layer_writes() {
    let repo = TempProject::with_repo_files();
    let ao_layer = std::fs::read_to_string(repo.root.join("layers/rt_ao.ron")).unwrap();
    let graph = std::fs::read_to_string(common::repo().join("graph/ao.ron")).unwrap();
    let condition = r#"runs_when: Some(AtLeast(buffer: "covered", fraction: 0.125))"#;
    assert!(ao_layer.contains(condition), "layers/rt_ao.ron no longer runs `ao` when an eighth of the frame is covered");
    let cases = [
        (
            ao_layer.replace(condition, r#"runs_when: Some(AtLeast(buffer: "uncovered", fraction: 0.125))"#),
            ErrorKind::UnknownOutput,
            "which layer `rt_ao` does not declare",
            "\"uncovered\"",
        ),
        (
            ao_layer.replace(condition, r#"runs_when: Some(AtLeast(buffer: "partial", fraction: 0.125))"#),
            ErrorKind::Unsupported,
            "`partial` is not a buffer of at least 8 bytes",
            r#"name: "ao""#,
        ),
        (
            ao_layer.replace(condition, r#"runs_when: Some(AtLeast(buffer: "covered", fraction: -1.0))"#),
            ErrorKind::Unsupported,
            "-1 x its whole: not a finite, non-negative fraction",
            r#"name: "ao""#,
        ),
        (
            ao_layer.replace(r#""covered": Buffer(size: 16, zeroed: true)"#, r#""covered": Buffer(size: 4, zeroed: true)"#),
            ErrorKind::Unsupported,
            "`covered` is not a buffer of at least 8 bytes",
            r#"name: "list""#,
        ),
        (
            ao_layer.replace(r#"writes: ["ao", "covered"]"#, r#"writes: ["ao"]"#),
            ErrorKind::Unsupported,
            "no pass of its layer writes `covered`",
            r#"name: "list""#,
        ),
    ];
    // Each case with the text of the line the error points at: where an unknown buffer is
    // named, else the first pass whose condition is wrong.
    for (broken, kind, message, at) in cases {
        assert_ne!(broken, ao_layer, "{message}: the layer did not change");
        expect_in_layer(&repo, &graph, ("layers/rt_ao.ron", &broken), kind, (at, message));
    }
    // The layer as it is compiles, and the plan's report says when each pass runs.
    repo.write("layers/rt_ao.ron", &ao_layer);
    let report = repo.compile("g.ron", &graph).expect("layers/rt_ao.ron compiles").report();
    let ao_line = report.lines().find(|l| l.contains("ao/ao ")).expect("the report lists ao/ao");
    assert!(ao_line.ends_with("runs when ao/covered of the frame before is at least 0.125 x its whole"), "{ao_line}");
}

#[test]
fn parameter_out_of_range() {
    let p = TempProject::new();
    let g = GOOD.replace(r#""value": 0.5"#, r#""value": 1.5"#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::ParamOutOfRange, "graph/g.ron", line_of(&g, r#""value": 1.5"#));
    assert!(e.to_string().contains("0..=1"), "{e}");
    let g = GOOD.replace(r#"params: {"value": 0.5}"#, r#"params: {"counter": 99}"#);
    expect(p.compile("g2.ron", &g), ErrorKind::ParamOutOfRange, "graph/g2.ron", line_of(&g, "99"));
}

#[test]
fn parameter_of_wrong_type() {
    let p = TempProject::new();
    let g = GOOD.replace(r#""value": 0.5"#, r#""value": true"#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::ParamType, "graph/g.ron", line_of(&g, r#""value": true"#));
    assert!(e.message.contains("expected float, found bool (`true`)"), "the value as the file writes it: {e}");
    let g = GOOD.replace(r#"params: {"value": 0.5}"#, r#"params: {"counter": 2.5}"#);
    let e = expect(p.compile("g2.ron", &g), ErrorKind::ParamType, "graph/g2.ron", line_of(&g, "2.5"));
    assert!(e.message.contains("expected int, found float (`2.5`)"), "{e}");
}

#[test]
fn unknown_parameter() {
    let p = TempProject::new();
    let g = GOOD.replace(r#""value": 0.5"#, r#""valeu": 0.5"#);
    expect(p.compile("g.ron", &g), ErrorKind::UnknownParam, "graph/g.ron", line_of(&g, "valeu"));
}

#[test]
fn graph_output_of_the_wrong_format_is_written_as_in_the_layer_file() {
    let p = TempProject::new();
    let g = GOOD.replace(r#"output: "out.color""#, r#"output: "fill.color""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::Unsupported, "graph/g.ron", line_of(&g, r#"output: "fill.color""#));
    assert!(e.message.contains("graph output `fill.color` is `Texture(format: Rgba16Float)`"), "{e}");
    assert!(!e.message.contains("TextureDecl") && !e.message.contains("size:"), "no Rust debug output, no default fields: {e}");
}

#[test]
fn texture_format_mismatch_between_producer_and_consumer() {
    let p = TempProject::new();
    // to8 outputs Rgba8Unorm; invert expects Rgba16Float.
    let g = r#"Graph(
    output: "out.color",
    nodes: {
        "fill": Layer(layer: "fill"),
        "first": Layer(layer: "to8", inputs: {"src": "fill.color"}),
        "inv": Layer(layer: "invert", inputs: {"src": "first.color"}),
        "out": Layer(layer: "to8", inputs: {"src": "inv.dst"}),
    },
)
"#;
    let e = expect(p.compile("g.ron", g), ErrorKind::FormatMismatch, "graph/g.ron", line_of(g, r#""src": "first.color""#));
    let text = e.to_string();
    assert!(text.contains("Rgba16Float") && text.contains("Rgba8Unorm"), "{text}");
    assert!(e.notes.iter().any(|(l, _)| l.file.ends_with("layers/invert.ron")), "notes the layer's declaration: {text}");
}

#[test]
fn shader_binding_mismatch() {
    let p = TempProject::new();
    // Storage format differs from the resource's format.
    let wgsl = std::fs::read_to_string(p.root.join("shaders/test/fill.wgsl"))
        .unwrap()
        .replace("texture_storage_2d<rgba16float, write>", "texture_storage_2d<rgba8unorm, write>");
    p.write("shaders/test/fill_rgba8.wgsl", &wgsl);
    let layer = std::fs::read_to_string(p.root.join("layers/fill.ron")).unwrap().replace("test/fill.wgsl", "test/fill_rgba8.wgsl");
    p.write("layers/fill8.ron", &layer);
    let g = GOOD.replace(r#"layer: "fill""#, r#"layer: "fill8""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::BindingMismatch, "layers/fill8.ron", line_of(&layer, r#"name: "fill""#));
    let (loc, _) = &e.notes[0];
    assert!(loc.file.ends_with("shaders/test/fill_rgba8.wgsl"), "names the WGSL file: {e}");
    assert_eq!(loc.line, line_of(&wgsl, "var color"), "names the WGSL line: {e}");

    // A binding the pass does not declare.
    let wgsl = std::fs::read_to_string(p.root.join("shaders/test/to8.wgsl")).unwrap() + "@group(0) @binding(7) var extra: texture_2d<f32>;\n";
    p.write("shaders/test/to8_extra.wgsl", &wgsl);
    let layer = std::fs::read_to_string(p.root.join("layers/to8.ron")).unwrap().replace("test/to8.wgsl", "test/to8_extra.wgsl");
    p.write("layers/to8x.ron", &layer);
    let g = GOOD.replace(r#"layer: "to8""#, r#"layer: "to8x""#);
    let e = expect(p.compile("g2.ron", &g), ErrorKind::BindingMismatch, "layers/to8x.ron", line_of(&layer, "name: \"convert\""));
    assert_eq!(e.notes[0].0.line, line_of(&wgsl, "var extra"), "{e}");
    assert!(e.message.contains("shader binding `extra` (texture_2d<f32>) is not a resource"), "the type as WGSL writes it: {e}");

    // A declared resource the shader does not bind.
    let layer = std::fs::read_to_string(p.root.join("layers/to8.ron"))
        .unwrap()
        .replace(r#"reads: ["src"]"#, r#"reads: ["src", "more"]"#)
        .replace("inputs: {", "inputs: {\n        \"more\": Texture(format: Rgba16Float),");
    p.write("layers/to8m.ron", &layer);
    let g = GOOD.replace(r#"layer: "to8", inputs: {"src": "fill.color"}"#, r#"layer: "to8m", inputs: {"src": "fill.color", "more": "fill.color"}"#);
    let e = expect(p.compile("g3.ron", &g), ErrorKind::BindingMismatch, "layers/to8m.ron", line_of(&layer, "name: \"convert\""));
    assert!(e.to_string().contains("`more`"), "{e}");
}

#[test]
fn wgsl_that_fails_to_validate() {
    let p = TempProject::new();
    // Parses, but assigns a vec3 to a vec4 store: a type error found by the front end.
    let wgsl = std::fs::read_to_string(p.root.join("shaders/test/to8.wgsl")).unwrap().replace(
        "textureStore(color, id.xy, clamp(textureLoad(src, id.xy, 0), vec4<f32>(0.0), vec4<f32>(1.0)));",
        "let bad: vec4<f32> = vec3<f32>(1.0);\n    textureStore(color, id.xy, bad);",
    );
    p.write("shaders/test/to8_bad.wgsl", &wgsl);
    let layer = std::fs::read_to_string(p.root.join("layers/to8.ron")).unwrap().replace("test/to8.wgsl", "test/to8_bad.wgsl");
    p.write("layers/to8b.ron", &layer);
    let g = GOOD.replace(r#"layer: "to8""#, r#"layer: "to8b""#);
    let e = expect(p.compile("g.ron", &g), ErrorKind::ShaderInvalid, "shaders/test/to8_bad.wgsl", line_of(&wgsl, "let bad"));
    assert!(e.message.starts_with("WGSL does not validate:"), "a type error is not a syntax error: {e}");
    assert!(e.message.contains("`vec4<f32>`") && e.message.contains("`vec3<f32>`"), "types as WGSL writes them: {e}");
    assert!(e.notes.iter().any(|(l, _)| l.file.ends_with("layers/to8b.ron")), "names the layer file: {e}");

    // Syntax error in WGSL.
    let wgsl = std::fs::read_to_string(p.root.join("shaders/test/to8.wgsl"))
        .unwrap()
        .replace("let size = textureDimensions(color);", "let size = textureDimensions(color)");
    p.write("shaders/test/to8_syntax.wgsl", &wgsl);
    let layer = std::fs::read_to_string(p.root.join("layers/to8.ron")).unwrap().replace("test/to8.wgsl", "test/to8_syntax.wgsl");
    p.write("layers/to8s.ron", &layer);
    let g = GOOD.replace(r#"layer: "to8""#, r#"layer: "to8s""#);
    let e = p.compile("g2.ron", &g).expect_err("bad WGSL");
    assert_eq!(e.kind, ErrorKind::ShaderInvalid, "{e}");
    assert!(e.location.file.ends_with("shaders/test/to8_syntax.wgsl"), "{e}");
    assert!(e.message.starts_with("WGSL does not parse:"), "{e}");
    let l = line_of(&wgsl, "let size");
    assert!(e.location.line == l || e.location.line == l + 1, "{e}");

    // Invalid only for the validator (not the parser): an atomic in a uniform buffer.
    let wgsl = "@group(0) @binding(0) var<uniform> n: atomic<u32>;\n@compute @workgroup_size(1) fn cs_main() {}\n";
    p.write("shaders/test/uniform_atomic.wgsl", wgsl);
    let layer = "Layer(\n    outputs: { \"color\": Texture(format: Rgba16Float) },\n    passes: [ Pass(name: \"x\", kind: Compute, shader: \"test/uniform_atomic.wgsl\", writes: [\"color\"]) ],\n)\n";
    p.write("layers/ua.ron", layer);
    let g = GOOD.replace(r#"layer: "fill", params: {"value": 0.5}"#, r#"layer: "ua""#);
    let e = p.compile("g3.ron", &g).expect_err("invalid WGSL");
    assert_eq!(e.kind, ErrorKind::ShaderInvalid, "{e}");
    assert!(e.location.file.ends_with("shaders/test/uniform_atomic.wgsl"), "{e}");
    assert!(e.message.starts_with("WGSL does not validate:"), "{e}");
    assert_eq!(e.location.line, 1, "{e}");
}

#[test]
fn a_trace_entry_point_with_a_compute_only_builtin_names_it_as_wgsl_does() {
    let wgsl = "@compute @workgroup_size(8, 8) fn cs_main(@builtin(local_invocation_id) l: vec3<u32>) {}\n";
    let mut module = naga::front::wgsl::parse_str(wgsl).expect("valid WGSL");
    let message = raygraph::graph::reflect::compute_to_ray_generation(&mut module).expect_err("local ids have no ray-generation equivalent");
    assert!(message.starts_with("entry point `cs_main` reads @builtin(local_invocation_id), which a ray-generation shader does not have"), "{message}");
}

#[test]
fn missing_graph_file_is_an_io_error() {
    let p = TempProject::new();
    let e = raygraph::graph::compile(&p.root.join("graph/none.ron"), &p.project(), (8, 8)).expect_err("missing");
    assert_eq!(e.kind, ErrorKind::Io);
    assert!(e.to_string().contains("none.ron"));
}
