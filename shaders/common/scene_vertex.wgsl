// The vertex stage of the raster passes that draw the scene's materials (the G-buffer,
// deferred/deferred.wgsl, and forward shading, common/forward_draw.wgsl): world and
// object-space positions, the world normal, both uv sets and the vertex colour of each vertex
// (their fragment stages read it through common/scene_fragment.wgsl).
// Needs `frame`, `scene_instances`, `scene_meshes` and `scene_vertices` declared by the pass.
//#include "common/vertex_extras.wgsl"

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) instance: u32,
    // Object-space position: its derivatives give the face normal without the rounding of
    // large world coordinates (an instance far from the origin).
    @location(4) local: vec3<f32>,
    // TEXCOORD_1 (TEXCOORD_0 without one) and COLOR_0 (white without one).
    @location(5) uv1: vec2<f32>,
    @location(6) color: vec4<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) instance: u32,
    @builtin(vertex_index) vertex: u32,
) -> VertexOut {
    let inst = scene_instances[instance];
    let extras = vertex_extras(inst, vertex, uv);
    let world = inst.model * vec4<f32>(position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (inst.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    out.local = position;
    out.uv1 = extras.uv1;
    out.color = extras.color;
    return out;
}
