// The translucent surfaces of the raster image (glTF BLEND, and transmissive ones, thin-walled),
// drawn after the opaque ones, back to front by the centre of each instance's bounds, each
// fragment shaded as forward/forward.wgsl shades one (common/forward_draw.wgsl) with coverage
// c (common/raster_alpha_test.wgsl's material_coverage). The executor's `translucent` pass draws
// only the translucent instances (src/runtime/raster.rs) into two targets cleared to 0:
//   - `translucent`: radiance x c with premultiplied-alpha blending (the layer's radiance and
//     coverage);
//   - `translucent_filter`: one minus the product of the surfaces' transmittances t (blended
//     `src + (1 - src) x dst` with src = 1 - t), t = 1 - c, times the albedo for a transmissive
//     surface (the tint of what it lets through, as common/hit_lighting.wgsl's composite_blend
//     tints it).
// forward/shade.wgsl or forward/composite.wgsl then puts the layer over the opaque image:
// `layer + (1 - absorbed) x opaque` (docs/ARCHITECTURE.md, "Blended surfaces"). There is no depth
// attachment: a fragment is kept where it lies nearer than the opaque surface of its pixel
// (`depth`, the opaque pass's).
//
// What it gets wrong: instances are sorted, not triangles, so two translucent instances whose
// bounds' centres order differently from their surfaces at a pixel, and the overlapping layers
// of one mesh, composite in the wrong order there; and between translucent surfaces the one in
// front attenuates the one behind by 1 - c, untinted (the opaque surface behind them all gets
// every tint). The ray-traced modes composite each ray's surfaces in depth order, tinted.
//#include "common/forward_draw.wgsl"

@group(0) @binding(13) var depth: texture_depth_2d;

struct TranslucentOut {
    @location(0) layer: vec4<f32>,
    @location(1) absorbed: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front_facing: bool) -> TranslucentOut {
    let inst = scene_instances[in.instance];
    let r = scene_fragment_surface(in, inst, front_facing);
    let material = inst.material;
    let c = clamp(material_coverage(material, in.uv, in.color.a), 0.0, 1.0);
    if in.clip.z >= textureLoad(depth, vec2<i32>(in.clip.xy), 0) || c <= 0.0 {
        discard;
    }
    let transmissive = (scene_materials[material].flags & MATERIAL_TRANSMISSION) != 0u;
    let t = (1.0 - c) * select(vec3<f32>(1.0), r.albedo, transmissive);
    return TranslucentOut(vec4<f32>(fragment_radiance(in, r) * c, c), vec4<f32>(1.0 - t, 0.0));
}
