// A vertex's COLOR_0 and TEXCOORD_1 in the vertex stage of the fragment-stage layers
// (common/scene_vertex.wgsl): the mesh's extras records (32 bytes a vertex,
// after all vertices in `scene_vertices`; common/scene.wgsl's MeshRecord.extras), white and the
// first set where the mesh has none. Needs `scene_meshes` and `scene_vertices` declared by the
// main shader (read-only storage, visible to the vertex stage).

struct VertexExtras {
    uv1: vec2<f32>,
    color: vec4<f32>,
}

// `vertex_index`: the draw's vertex index (the mesh's base vertex plus the index); `uv0`: the
// vertex's TEXCOORD_0.
fn vertex_extras(inst: Instance, vertex_index: u32, uv0: vec2<f32>) -> VertexExtras {
    let mesh = scene_meshes[inst.mesh];
    if !SCENE_VERTEX_EXTRAS || mesh.extras == MESH_NO_EXTRAS {
        return VertexExtras(uv0, vec4<f32>(1.0));
    }
    let x = scene_vertices[mesh.extras + vertex_index - mesh.base_vertex];
    return VertexExtras(vec2<f32>(x.px, x.py), vec4<f32>(x.pz, x.nx, x.ny, x.nz));
}
