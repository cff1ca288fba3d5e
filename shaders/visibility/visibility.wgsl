// A visibility buffer, shaded in a compute pass (forward/shade.wgsl) or turned into the
// G-buffer (deferred/gbuffer.wgsl): per pixel,
// the instance, the side the rasterizer saw and the triangle it kept
// (common/visibility_buffer.wgsl), with
// the visibility every mode has (common/raster_visibility.wgsl: the alpha test; back faces of
// single-sided materials culled in the rasterizer). The fragment stage does nothing else: the
// material reads and shading run in a compute pass, on every shader core rather than only on
// those a GPU gives its graphics pipeline.
enable primitive_index;
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/raster_visibility.wgsl"
//#include "common/visibility_buffer.wgsl"
//#include "common/vertex_extras.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
    // The vertex colours' alpha (COLOR_0), for the alpha test; read only by the pipelines of
    // alpha-tested draws (RASTER_ALPHA_TEST), 1 in the others.
    @location(2) alpha: f32,
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
    var out: VertexOut;
    out.clip = frame.view_proj * (inst.model * vec4<f32>(position, 1.0));
    out.uv = uv;
    out.instance = instance;
    out.alpha = 1.0;
    if RASTER_ALPHA_TEST {
        out.alpha = vertex_extras(inst, vertex, uv).color.a;
    }
    return out;
}

// The texel of common/visibility_buffer.wgsl (the side from `raster_front_face`).
@fragment
fn fs_main(in: VertexOut, @builtin(primitive_index) primitive: u32, @builtin(front_facing) front_facing: bool) -> @location(0) vec2<u32> {
    let inst = scene_instances[in.instance];
    if !raster_fragment_kept(inst, in.uv, in.clip.xy, in.alpha) {
        discard;
    }
    let front = select(0u, VISIBLE_FRONT_FACE, raster_front_face(front_facing, inst.model));
    return vec2<u32>((in.instance + 1u) | front, primitive);
}
