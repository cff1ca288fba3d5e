// Translucent surfaces along rays (docs/ARCHITECTURE.md, "Blended surfaces"): glTF BLEND ones,
// and transmissive ones (KHR_materials_transmission, thin-walled), both called BLEND below. The
// traversal hits a BLEND surface wherever its coverage (base_color.a x (1 - transmission x
// (1 - metallic)) x the base texture's alpha, trace/alpha.wgsl's trace_blend_coverage) reaches
// its cutoff (1/256; 0 for a transmissive one, which is always hit); the passes then:
//   - skip it on primary rays (common/primary_hit.wgsl: the G-buffer holds the first opaque
//     surface; the rt_blend layer composites the translucent ones over the resolved image);
//   - let shadow and AO rays through it, attenuated by one minus its coverage
//     (trace_transmittance: the product over every BLEND surface on the segment, found in one
//     traversal, 0 at an opaque one or once less than 1/256 gets through);
//   - composite it front to back along primary and reflection rays (at most BLEND_LAYERS
//     surfaces a ray; what lies past them is taken as seen through the last one).
// SCENE_BLEND is a pipeline constant (common/scene_features.wgsl): the executor sets it false
// for a scene without translucent materials (src/runtime/exec/features.rs), and every function
// here is then one plain trace.
// Needs trace/trace.wgsl included first.
//#include "common/scene_features.wgsl"

// BLEND surfaces composited along one primary or reflection ray, at most.
const BLEND_LAYERS: u32 = 8u;

// A distance just past `t` on the same ray: 64 ulps, so the surface hit at `t` is not hit
// again (the same rule as the culled back faces of common/primary_hit.wgsl).
fn blend_past(t: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(t) + 64u);
}

// The coverage of the BLEND surface `hit` is on, or -1 for an opaque surface (or a miss).
fn hit_blend_coverage(hit: Hit) -> f32 {
    if !SCENE_BLEND || hit.instance == NO_HIT {
        return -1.0;
    }
    return trace_blend_coverage(hit.instance, hit.primitive, hit.bary);
}

// The fraction of light that gets through [t_min, t_max] of `ray`: 0 past an opaque surface,
// else the product of one minus the coverage of every BLEND surface on it (order does not
// matter, so each back-end finds them in one traversal: trace_transmittance_flags), 0 once
// that falls below TRACE_TRANSMITTANCE_MIN. Without BLEND materials: one any-hit ray, 0 or 1.
fn trace_transmittance(ray: Ray) -> f32 {
    if !SCENE_BLEND {
        return select(1.0, 0.0, trace_any(ray));
    }
    return trace_transmittance_flags(ray, TRACE_FLAGS_NONE);
}
