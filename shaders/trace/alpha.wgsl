// The trace side of the alpha test, included by every back-end module (trace/compute.wgsl,
// trace/ray_query.wgsl, trace/rt_pipeline.wgsl); passes declare nothing for it.
//
//   trace_alpha_visible(instance, primitive, bary) -> bool
//     `instance`: the scene instance (Scene::instances index); `primitive`: the triangle's
//     index within its mesh; `bary`: barycentric weights of the triangle's vertices 1 and 2.
//     True when the hit is kept: the instance's material is not alpha-tested, or
//     base_color.a x the vertex colours' alpha x the base texture's level-0 bilinear alpha (its slot's wrap modes) at the
//     interpolated, transformed TEXCOORD_0 is >= the material's cutoff (BLEND: 1/256, its
//     least coverage: a BLEND surface is translucent, composited by the passes through
//     common/ray_blend.wgsl). Same arithmetic as the raster side
//     (common/raster_alpha_test.wgsl) and the CPU references (src/accel/alpha.rs).
//   trace_transmittance_passes(instance, primitive, bary) -> bool
//     For a candidate of a transmittance ray: true where the ray passes it (the alpha test
//     rejects it, or a BLEND surface whose coverage is taken out of the private
//     trace_transmitted, still >= 1/256 after).
//   trace_visible_passes(instance, primitive, bary) -> bool
//     For a candidate of a closest-hit ray with TRACE_PASS_BLEND: true where the ray passes
//     it (a BLEND surface, which needs no texel, or the alpha test rejects it).
//   trace_blend_coverage(instance, primitive, bary) -> f32
//     base_color.a x that texture alpha where the instance's material is BLEND, else -1;
//     where its transmission texture is drawn, times 1 - the transmitted share x its texel.
//
// Bindings (bound by the executor and the batch tracer by name, like the other accel_*):
//   @group(2) @binding(15) accel_alpha: array<vec4<u32>>, the AccelCache's alpha buffer
//     (AccelCache::binding("accel_alpha", _)), one buffer for
//     every back-end:
//     - word [instance]: (uv_base, texture layer | the base colour slot's wrap bits << 24 |
//       TRACE_ALPHA_BLEND for a BLEND material | TRACE_ALPHA_TRANSMISSION where its transmission
//       texture is drawn, bitcast<u32>(coverage factor), bitcast<u32>(cutoff), or with
//       TRACE_ALPHA_TRANSMISSION the index of a word (transmission texture layer | its wrap
//       bits << 24, the transmitted share, the cutoff, 0)); uv_base == TRACE_ALPHA_OPAQUE for an
//       instance whose material is not alpha-tested (nothing else is read then);
//     - words [uv_base + 2 primitive] and [+ 1]: the triangle's TEXCOORD_0 through the base
//       colour slot's uv transform, as f32 bits, (u0, v0, u1, v1) and (u2, v2, alphas, 0), alphas
//       its corners' vertex-colour alpha (COLOR_0; 1 without), 8-bit unorm, 8 bits each. Only
//       meshes of alpha-tested instances have uvs (one copy per transform they are drawn with).
//   @group(1) @binding(0) scene_textures, declared by common/scene_textures_texels.wgsl
//     (either variant, which common/scene_textures.wgsl includes), so a trace pass that
//     reads textures itself shares the declaration.
//
// TRACE_ALPHA_TEST is a pipeline constant: the executor sets it false for a scene without
// alpha-tested instances (src/runtime/exec/features.rs), and the compute traversal
// then has no alpha branch at all. Back-ends and callers that do not set it keep the test.
//#include "common/alpha_read.wgsl"

override TRACE_ALPHA_TEST: bool = true;

// `accel_alpha` and its reader trace_alpha_word (in the compute back-end's packed buffer on
// devices with few storage buffers per stage: trace/alpha_words_packed.wgsl).
//#include "trace/alpha_words.wgsl"

const TRACE_ALPHA_OPAQUE: u32 = 0xffffffffu;
const TRACE_ALPHA_BLEND: u32 = 0x10000000u;
const TRACE_ALPHA_TRANSMISSION: u32 = 0x20000000u;

// The cutoff of an alpha-tested instance's record `rec` (in its transmission word where it
// has one).
fn trace_alpha_cutoff(rec: vec4<u32>) -> f32 {
    if (rec.y & TRACE_ALPHA_TRANSMISSION) != 0u {
        return bitcast<f32>(trace_alpha_word(rec.w).z);
    }
    return bitcast<f32>(rec.w);
}

// The base colour slot's uv (xy) and the vertex colours' alpha (z) of a hit on an alpha-tested
// instance whose record is `rec`.
fn trace_alpha_corners(rec: vec4<u32>, primitive: u32, bary: vec2<f32>) -> vec3<f32> {
    let a = trace_alpha_word(rec.x + 2u * primitive);
    let b = trace_alpha_word(rec.x + 2u * primitive + 1u);
    let w = vec3<f32>(1.0 - bary.x - bary.y, bary.x, bary.y);
    let uv = bitcast<vec2<f32>>(a.xy) * w.x + bitcast<vec2<f32>>(a.zw) * w.y + bitcast<vec2<f32>>(b.xy) * w.z;
    return vec3<f32>(uv, dot(unpack4x8unorm(b.z).xyz, w));
}

fn trace_alpha_visible(instance: u32, primitive: u32, bary: vec2<f32>) -> bool {
    let rec = trace_alpha_word(instance);
    if rec.x == TRACE_ALPHA_OPAQUE {
        return true;
    }
    return trace_alpha_kept_by(rec, primitive, bary);
}

fn trace_visible_passes(instance: u32, primitive: u32, bary: vec2<f32>) -> bool {
    let rec = trace_alpha_word(instance);
    if rec.x == TRACE_ALPHA_OPAQUE {
        return false;
    }
    if (rec.y & TRACE_ALPHA_BLEND) != 0u {
        return true;
    }
    return !trace_alpha_kept_by(rec, primitive, bary);
}

// The alpha test of a hit on an alpha-tested instance whose record is `rec`: true where kept.
fn trace_alpha_kept_by(rec: vec4<u32>, primitive: u32, bary: vec2<f32>) -> bool {
    let c = trace_alpha_corners(rec, primitive, bary);
    return alpha_kept(rec.y & 0xffffffu, bitcast<f32>(rec.z) * c.z, trace_alpha_cutoff(rec), c.xy, (rec.y >> 24u) & 15u);
}

// What a transmittance ray (trace_transmittance_flags) has let through so far; each
// back-end's any-hit step multiplies it by what a BLEND surface lets through.
var<private> trace_transmitted: f32 = 1.0;
// Less than this getting through counts as none: the ray is stopped there.
const TRACE_TRANSMITTANCE_MIN: f32 = 1.0 / 256.0;

// A transmittance ray's candidate: true when the ray passes it, either because the alpha test
// rejects it or because it is a BLEND surface (its coverage taken out of trace_transmitted,
// which stays at least TRACE_TRANSMITTANCE_MIN); false when it stops the ray (an opaque or
// MASK surface, or too little left getting through). One read of the texture for both
// questions: the coverage is the alpha test's own product.
fn trace_transmittance_passes(instance: u32, primitive: u32, bary: vec2<f32>) -> bool {
    let rec = trace_alpha_word(instance);
    if rec.x == TRACE_ALPHA_OPAQUE {
        return false;
    }
    let c = trace_alpha_corners(rec, primitive, bary);
    let alpha = trace_alpha_of(rec, c);
    if alpha < trace_alpha_cutoff(rec) {
        return true;
    }
    if (rec.y & TRACE_ALPHA_BLEND) == 0u {
        return false;
    }
    trace_transmitted *= 1.0 - min(trace_coverage_of(rec, c.xy, alpha), 1.0);
    return trace_transmitted >= TRACE_TRANSMITTANCE_MIN;
}

// The alpha of a hit on an alpha-tested instance (record `rec`, corners `c`): base_color.a x
// the vertex colours' alpha x the base texture's level-0 bilinear alpha.
fn trace_alpha_of(rec: vec4<u32>, c: vec3<f32>) -> f32 {
    return bitcast<f32>(rec.z) * c.z * scene_alpha_level0(rec.y & 0xffffffu, c.xy, (rec.y >> 24u) & 15u);
}

// The coverage of a BLEND hit of alpha `alpha` at `uv`: the alpha, where its transmission
// texture is drawn times 1 - the transmitted share x its texel.
fn trace_coverage_of(rec: vec4<u32>, uv: vec2<f32>, alpha: f32) -> f32 {
    if (rec.y & TRACE_ALPHA_TRANSMISSION) == 0u {
        return alpha;
    }
    let t = trace_alpha_word(rec.w);
    return alpha * (1.0 - bitcast<f32>(t.y) * scene_bilinear_level0(t.x & 0xffffffu, uv, (t.x >> 24u) & 15u).r);
}

// The start of each back-end's trace_transmittance_flags: false for an invalid ray (counted as
// such; it lets everything through), else the ray is counted as an any-hit ray and
// trace_transmitted starts at 1.
fn trace_transmittance_starts(ray: Ray) -> bool {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return false;
    }
    trace_count_any++;
    trace_transmitted = 1.0;
    return true;
}

// A transmittance ray's result (each back-end's trace_transmittance_flags): 0 where something
// stopped it, else what its BLEND surfaces let through (trace_transmitted); a hit is counted
// wherever less than all of it got through.
fn trace_transmittance_result(stopped: bool) -> f32 {
    let transmittance = select(trace_transmitted, 0.0, stopped);
    if transmittance < 1.0 {
        trace_count_hits++;
    }
    return transmittance;
}

fn trace_blend_coverage(instance: u32, primitive: u32, bary: vec2<f32>) -> f32 {
    let rec = trace_alpha_word(instance);
    if rec.x == TRACE_ALPHA_OPAQUE || (rec.y & TRACE_ALPHA_BLEND) == 0u {
        return -1.0;
    }
    let c = trace_alpha_corners(rec, primitive, bary);
    return trace_coverage_of(rec, c.xy, trace_alpha_of(rec, c));
}
