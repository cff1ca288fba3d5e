// Which rasterized fragments of the scene are kept, the same visibility the rays have: back
// faces of single-sided materials (glTF doubleSided false) and texels the alpha test cuts are
// discarded. Both sides of every triangle are drawn, so facing is decided here.
// Needs common/scene.wgsl and `scene_materials`, like common/alpha.wgsl.
//#include "common/material_inputs.wgsl"
//#include "common/alpha.wgsl"

fn raster_fragment_kept(inst: Instance, front_facing: bool, uv: vec2<f32>) -> bool {
    let material = scene_materials[inst.material];
    if !raster_front_face(front_facing, inst.model) && (material.flags & MATERIAL_DOUBLE_SIDED) == 0u {
        return false;
    }
    return material_alpha_visible(inst.material, uv);
}
