// Forward shading of the scene's opaque and alpha-tested meshes (common/forward_draw.wgsl:
// the shading model of every mode). Writes linear HDR colour; alpha 1 marks geometry. Texels
// the alpha test cuts are discarded (common/raster_alpha_test.wgsl); translucent instances are
// not drawn here (`skip_blend`) but blended by forward/translucent.wgsl.
//#include "common/forward_draw.wgsl"

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    if !scene_fragment_kept(in) {
        discard;
    }
    let r = scene_fragment_surface(in, scene_instances[in.instance], front_facing);
    return vec4<f32>(fragment_radiance(in, r), 1.0);
}
