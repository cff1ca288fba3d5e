// GPU deformation of skinned and morphed meshes (src/runtime/deform.rs), one dispatch per
// deforming mesh: its rest vertices plus the weighted morph displacements, then linear blend
// skinning with the weighted sum of its joint matrices (normals through that sum's cofactor
// matrix, signed by its determinant), in the order src/scene/animation.rs's
// `Deformer::deform` computes them. Writes the scene's vertex buffer (position and normal; the
// uv stays) and the acceleration structure's positions, at the mesh's first vertex.

struct Params {
    // The mesh's first vertex in the scene's buffers.
    first_vertex: u32,
    vertex_count: u32,
    // Morph targets, and whether they displace normals (1) or not (0).
    targets: u32,
    target_normals: u32,
    // Groups of four influences per vertex (0: not skinned).
    sets: u32,
    // Where this mesh's data starts: rest vertices and morph displacements in `shape` (in
    // vec4s), influences in `influences` (in vec4s), joint matrices and morph weights in
    // `frame` (in vec4s).
    shape: u32,
    influences: u32,
    joints: u32,
    weights: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Per vertex (position, 0) and (normal, 0); then per target and vertex (dposition, 0) and,
// with target normals, (dnormal, 0).
@group(0) @binding(1) var<storage, read> shape: array<vec4<f32>>;
// Per vertex and set: four joint indices, then their four weights (f32 bits).
@group(0) @binding(2) var<storage, read> influences: array<vec4<u32>>;
// This frame's joint matrices (four columns each) and morph weights (four per vec4).
@group(0) @binding(3) var<storage, read> frame: array<vec4<f32>>;
// The scene's vertices: position (3 floats), normal (3), uv (2).
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;
// The acceleration structure's positions (xyz), all meshes one after another.
@group(0) @binding(5) var<storage, read_write> positions: array<vec4<f32>>;

fn joint(j: u32) -> mat4x4<f32> {
    let base = params.joints + 4u * j;
    return mat4x4<f32>(frame[base], frame[base + 1u], frame[base + 2u], frame[base + 3u]);
}

fn morph_weight(t: u32) -> f32 {
    let i = 4u * params.weights + t;
    return frame[i / 4u][i % 4u];
}

fn finite(v: vec3<f32>) -> bool {
    let b = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(b != vec3<u32>(0x7f800000u));
}

@compute @workgroup_size(64)
fn deform(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = gid.y * groups.x * 64u + gid.x;
    if v >= params.vertex_count {
        return;
    }
    var p = shape[params.shape + 2u * v].xyz;
    var n = shape[params.shape + 2u * v + 1u].xyz;
    let per_target = params.vertex_count * (1u + params.target_normals);
    for (var t = 0u; t < params.targets; t++) {
        let w = morph_weight(t);
        if w != 0.0 {
            let base = params.shape + 2u * params.vertex_count + t * per_target;
            p += w * shape[base + (1u + params.target_normals) * v].xyz;
            if params.target_normals == 1u {
                n += w * shape[base + 2u * v + 1u].xyz;
            }
        }
    }
    if params.sets > 0u {
        var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        for (var s = 0u; s < params.sets; s++) {
            let at = params.influences + 2u * (v * params.sets + s);
            let j = influences[at];
            let w = bitcast<vec4<f32>>(influences[at + 1u]);
            for (var k = 0u; k < 4u; k++) {
                if w[k] != 0.0 {
                    m += joint(j[k]) * w[k];
                }
            }
        }
        p = (m * vec4<f32>(p, 1.0)).xyz;
        let a = mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz);
        var cof = mat3x3<f32>(cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1]));
        if determinant(a) < 0.0 {
            cof = cof * -1.0;
        }
        n = cof * n;
    }
    let len2 = dot(n, n);
    if finite(n) && len2 > 1e-20 {
        n = n / sqrt(len2);
    } else {
        n = vec3<f32>(0.0, 1.0, 0.0);
    }
    let g = params.first_vertex + v;
    vertices[8u * g] = p.x;
    vertices[8u * g + 1u] = p.y;
    vertices[8u * g + 2u] = p.z;
    vertices[8u * g + 3u] = n.x;
    vertices[8u * g + 4u] = n.y;
    vertices[8u * g + 5u] = n.z;
    positions[g] = vec4<f32>(p, 0.0);
}
