// The visibility buffer of forward shading in a compute pass (forward/shade.wgsl): per pixel,
// the instance (plus one; 0 where nothing was drawn) and the triangle the rasterizer kept, with
// the visibility every mode has (common/raster_visibility.wgsl: the alpha test; back faces of
// single-sided materials culled in the rasterizer). The fragment stage does nothing else: the
// shading runs in a compute pass, on every shader core rather than only on those a GPU gives
// its graphics pipeline.
enable primitive_index;
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/raster_visibility.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var linear_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) instance: u32,
) -> VertexOut {
    let inst = scene_instances[instance];
    var out: VertexOut;
    out.clip = frame.view_proj * (inst.model * vec4<f32>(position, 1.0));
    out.uv = uv;
    out.instance = instance;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(primitive_index) primitive: u32) -> @location(0) vec2<u32> {
    if !raster_fragment_kept(scene_instances[in.instance], in.uv) {
        discard;
    }
    return vec2<u32>(in.instance + 1u, primitive);
}
