// Deforming meshes in the merged layout (src/accel/deform.rs). `gather_positions` copies each
// leaf triangle's three object-space vertices from the meshes' current positions into the
// refit's input (`object_vertices`, whose w word holds the vertex's index into `positions`,
// written with it by src/accel/refit.rs or shaders/accel/records.wgsl); the refit then moves
// them to world space and recomputes every box (sah.wgsl then measures the tree).

// Every mesh's positions (xyz), one mesh after another.
@group(0) @binding(0) var<storage, read> positions: array<vec4<f32>>;
// Per leaf triangle, three (x, y, z bits, vertex index).
@group(0) @binding(1) var<storage, read_write> object_vertices: array<vec4<u32>>;

const NO_VERTEX: u32 = 0xffffffffu;

@compute @workgroup_size(256)
fn gather_positions(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.y * groups.x * 256u + gid.x;
    if i >= arrayLength(&object_vertices) {
        return;
    }
    let v = object_vertices[i];
    if v.w == NO_VERTEX || v.w >= arrayLength(&positions) {
        return;
    }
    object_vertices[i] = vec4<u32>(bitcast<vec3<u32>>(positions[v.w].xyz), v.w);
}
