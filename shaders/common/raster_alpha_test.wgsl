// The raster side of the alpha test (decision in docs/ARCHITECTURE.md, "Alpha-tested
// geometry"): a fragment of an alpha-tested material (MATERIAL_ALPHA_MASK) is discarded when
// base_color.a x the base texture's level-0 bilinear alpha at `uv` is below the cutoff; the
// same read as the ray tracers', so every mode cuts the same texels. BLEND materials (which
// carry MATERIAL_ALPHA_MASK too) are drawn screen-door in the shadow maps: a fragment is kept
// where that coverage exceeds the 4x4 ordered-dither threshold of its pixel `pixel` (the
// fragment's position), so a 4x4 block keeps a share of its fragments equal to the coverage to
// within 1/16, in any order (the maps' PCF then lets that share of the light through). The
// passes that draw the camera's view do not draw them among the opaque surfaces
// (`skip_blend`): the forward layers blend them in a translucent pass
// (forward/translucent.wgsl), the G-buffer's get them from the rt_blend layer. Usable from
// depth-only passes:
//   if !material_alpha_visible(material, uv, in.clip.xy, vertex_alpha) { discard; }
// Needs common/scene.wgsl included and `scene_materials` declared by the pass
// (`scene_textures` comes with the include).
//
// RASTER_ALPHA_TEST is a pipeline constant: the executor draws the instances of opaque
// materials with a pipeline where it is false (src/runtime/raster.rs), so their fragment stage
// has no discard and keeps early depth testing.
//#include "common/alpha_read.wgsl"
//#include "common/texture_slots.wgsl"

override RASTER_ALPHA_TEST: bool = true;

// The ordered-dither (Bayer) threshold of pixel `pixel`, in (0, 1): the 16 values (k + 0.5) / 16
// spread over every 4x4 block.
fn screen_door_threshold(pixel: vec2<f32>) -> f32 {
    let p = vec2<u32>(pixel) & vec2<u32>(3u);
    let bayer = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return (f32(bayer[p.y * 4u + p.x]) + 0.5) / 16.0;
}

// The coverage of a fragment of `material` at `uv`: base_color.a (a transmissive material's
// coverage factor, with its transmission texture) x `vertex_alpha` (the interpolated vertex
// colours' alpha: COLOR_0, 1 without) x the base texture's level-0 bilinear alpha. The raster
// translucent pass blends with it (forward/translucent.wgsl).
fn material_coverage(material: u32, uv: vec2<f32>, vertex_alpha: f32) -> f32 {
    let m = &scene_materials[material];
    var factor = select(m.base_color.a, m.clearcoat.w, (m.flags & MATERIAL_TRANSMISSION) != 0u);
    // The base colour slot's uv transform and wrap modes (its filter does not apply: the test
    // is always bilinear at level 0).
    let base_uv = slot_uv(material, SLOT_BASE, uv);
    if (m.flags & MATERIAL_TRANSMISSION_TEXTURE) != 0u {
        // The transmission texture reads the same uv (Material::transmission_texture_drawn).
        let texel = scene_bilinear_level0(m.slot_words.y, base_uv, slot_sampler(material, SLOT_TRANSMISSION) & 15u).r;
        factor *= 1.0 - m.clearcoat.z * (1.0 - m.metallic) * texel;
    }
    return factor * vertex_alpha * scene_alpha_level0(m.base_texture, base_uv, slot_sampler(material, SLOT_BASE) & 15u);
}

// `vertex_alpha`: the interpolated vertex colours' alpha (COLOR_0; 1 without).
fn material_alpha_visible(material: u32, uv: vec2<f32>, pixel: vec2<f32>, vertex_alpha: f32) -> bool {
    if !RASTER_ALPHA_TEST {
        return true;
    }
    let m = &scene_materials[material];
    if (m.flags & MATERIAL_ALPHA_MASK) == 0u {
        return true;
    }
    // Translucent (BLEND, transmissive): the coverage against the pixel's dither threshold
    // instead of a cutoff.
    let cutoff = select(m.alpha_cutoff, screen_door_threshold(pixel), (m.flags & MATERIAL_ALPHA_BLEND) != 0u);
    return material_coverage(material, uv, vertex_alpha) >= cutoff;
}
