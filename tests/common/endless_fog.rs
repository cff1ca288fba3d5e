//! A project whose fog layer loops forever (the GPU deadline's tests).

/// A fog layer whose loop waits for a negative density, which a parameter declared with
/// `min: 0.0` never gives: naga accepts it, and no compiler can prove it never ends.
const FOG_LAYER: &str = r#"Layer(
    outputs: { "hdr": Texture(format: Rgba16Float) },
    params: { "density": Float(default: 1.0, min: 0.0, max: 8.0) },
    passes: [
        Pass(name: "fog", kind: Compute, shader: "fog/fog.wgsl", writes: ["hdr"]),
    ],
)
"#;

const FOG_WGSL: &str = r#"struct Params {
    density: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var hdr: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    var fog = params.density;
    loop {
        if fog < 0.0 {
            break;
        }
        fog = fog * 0.5 + params.density;
    }
    textureStore(hdr, id.xy, vec4<f32>(fog, fog, fog, 1.0));
}
"#;

const FOG_GRAPH: &str = r#"Graph(
    output: "tonemap.color",
    nodes: {
        "fog": Layer(layer: "fog"),
        "tonemap": Layer(layer: "tonemap", inputs: {"hdr": "fog.hdr"}),
    },
)
"#;

/// A copy of the project with the fog layer, and its graph file `graph/fog.ron`.
pub fn project() -> (super::TempProject, std::path::PathBuf) {
    let p = super::TempProject::with_repo_files();
    p.write("layers/fog.ron", FOG_LAYER);
    p.write("shaders/fog/fog.wgsl", FOG_WGSL);
    let graph = p.write("graph/fog.ron", FOG_GRAPH);
    (p, graph)
}
