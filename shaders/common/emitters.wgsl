// The emissive triangles as lights (src/scene/emitters.rs builds the table; its doc gives the
// layout): picking one in proportion to its power, a uniform point on it, its density, and the
// probability of picking the triangle a ray hit. Each record holds the triangle's world-space
// corners and mean emission, so this needs only the main shader's
// `scene_emitters: array<u32>` (rt/path.wgsl, rt/shadow.wgsl).

// Some material emits light (src/runtime/exec/features.rs): without, the passes compile the
// emitters out.
override SCENE_EMITTERS: bool = true;

const NO_EMITTERS: u32 = 0xffffffffu;
// Words per record (`EMITTER_WORDS` in src/scene/emitters.rs).
const EMITTER_WORDS: u32 = 16u;

fn emitter_count() -> u32 {
    if !SCENE_EMITTERS {
        return 0u;
    }
    return scene_emitters[0];
}

// The first word of record `i`.
fn emitter_record(i: u32) -> u32 {
    return 2u + scene_emitters[1] + EMITTER_WORDS * i;
}

fn emitter_float(record: u32, k: u32) -> f32 {
    return bitcast<f32>(scene_emitters[record + k]);
}

fn emitter_cumulative(i: u32) -> f32 {
    return emitter_float(emitter_record(i), 2u);
}

// The probability of picking record `i` (normalised by the table's last cumulative value, so
// rounding in the table biases nothing).
fn emitter_probability(i: u32) -> f32 {
    return emitter_float(emitter_record(i), 3u) / emitter_cumulative(emitter_count() - 1u);
}

// The record whose cumulative range holds `u` (in [0, 1)) times the total: a binary search.
fn emitter_pick(u: f32) -> u32 {
    let wanted = u * emitter_cumulative(emitter_count() - 1u);
    var lo = 0u;
    var hi = emitter_count() - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if emitter_cumulative(mid) > wanted {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// The record of triangle `primitive` of `instance` (NO_EMITTERS if its material emits nothing).
fn hit_emitter(instance: u32, primitive: u32) -> u32 {
    if emitter_count() == 0u || instance >= scene_emitters[1] {
        return NO_EMITTERS;
    }
    let first = scene_emitters[2u + instance];
    if first == NO_EMITTERS {
        return NO_EMITTERS;
    }
    return first + primitive;
}

// An emitting triangle: its world-space corners, its normal on its emitting (counter-clockwise)
// side twice its area long, and its mean emitted radiance.
struct EmitterTriangle {
    corners: array<vec3<f32>, 3>,
    normal: vec3<f32>,
    emission: vec3<f32>,
}

fn emitter_triangle(i: u32) -> EmitterTriangle {
    let r = emitter_record(i);
    var out: EmitterTriangle;
    for (var k = 0u; k < 3u; k++) {
        out.corners[k] = vec3<f32>(emitter_float(r, 4u + 3u * k), emitter_float(r, 5u + 3u * k), emitter_float(r, 6u + 3u * k));
    }
    out.normal = cross(out.corners[1] - out.corners[0], out.corners[2] - out.corners[0]);
    out.emission = vec3<f32>(emitter_float(r, 13u), emitter_float(r, 14u), emitter_float(r, 15u));
    return out;
}

// Barycentrics (of corners 1 and 2) of a uniform point of a triangle, from `u` in [0, 1)^2.
fn uniform_barycentrics(u: vec2<f32>) -> vec2<f32> {
    let r = sqrt(u.x);
    return vec2<f32>(r * (1.0 - u.y), r * u.y);
}

// The point of `t` at barycentrics `b` (of its corners 1 and 2).
fn emitter_point(t: EmitterTriangle, b: vec2<f32>) -> vec3<f32> {
    return t.corners[0] * (1.0 - b.x - b.y) + t.corners[1] * b.x + t.corners[2] * b.y;
}

// The density (solid angle) of next-event estimation's point at the end of `to` on a triangle
// picked with `probability` whose normal `n2` is twice its area long.
fn emitter_density(probability: f32, n2: vec3<f32>, to: vec3<f32>) -> f32 {
    let cosine = abs(dot(normalize(n2), normalize(to)));
    return probability * dot(to, to) / max(0.5 * length(n2) * cosine, 1e-30);
}

// The diffuse part of `light_radiance` (common/lighting.wgsl, which the includer includes) for
// irradiance `e` from `l`: the base's Lambert lobe, less what its Fresnel term and the clear
// coat reflect (rt/shadow.wgsl and common/restir.wgsl light smooth surfaces by it).
fn diffuse_radiance(s: ShadingPoint, l: vec3<f32>, e: vec3<f32>) -> vec3<f32> {
    let n_l = dot(s.normal, l);
    if n_l <= 0.0 || s.unlit {
        return vec3<f32>(0.0);
    }
    let f = point_fresnel(s, max(dot(normalize(l + s.view), s.view), 0.0));
    var diffuse = (vec3<f32>(1.0) - f) * (1.0 - s.metallic) * s.albedo * e * n_l;
    if SCENE_LOBES && s.clearcoat > 0.0 {
        diffuse *= 1.0 - s.clearcoat * coat_fresnel(dot(s.coat_normal, s.view));
    }
    return diffuse;
}
