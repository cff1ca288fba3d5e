// The raster side of the alpha test (decision in docs/ARCHITECTURE.md, "Alpha-tested
// geometry"): a fragment of an alpha-tested material (MATERIAL_ALPHA_MASK, which BLEND
// materials carry too, with cutoff 0.5) is discarded when base_color.a x the base texture's
// level-0 bilinear alpha at `uv` is below the cutoff; the same read as the ray tracers', so
// every mode cuts the same texels. Usable from depth-only passes:
//   if !material_alpha_visible(material, uv) { discard; }
// Needs common/scene.wgsl included and `scene_materials` declared by the pass
// (`scene_textures` comes with the include).
//
// RASTER_ALPHA_TEST is a pipeline constant: the executor draws the instances of opaque
// materials with a pipeline where it is false (src/runtime/raster.rs), so their fragment stage
// has no discard and keeps early depth testing.
//#include "common/alpha_read.wgsl"
//#include "common/texture_slots.wgsl"

override RASTER_ALPHA_TEST: bool = true;

fn material_alpha_visible(material: u32, uv: vec2<f32>) -> bool {
    if !RASTER_ALPHA_TEST {
        return true;
    }
    let m = scene_materials[material];
    if (m.flags & MATERIAL_ALPHA_MASK) == 0u {
        return true;
    }
    // The base colour slot's uv transform and wrap modes (its filter does not apply: the test
    // is always bilinear at level 0).
    return alpha_kept(m.base_texture, m.base_color.a, m.alpha_cutoff, slot_uv(material, SLOT_BASE, uv), slot_sampler(material, SLOT_BASE) & 15u);
}
