// The emissive triangles as lights (src/scene/emitters.rs builds the table; its doc gives the
// layout): picking one in proportion to its power, a uniform point on it, and the probability
// of picking the triangle a ray hit. Needs the main shader to declare
// `scene_emitters: array<u32>` and the scene's instances, meshes, indices and vertices.

const NO_EMITTERS: u32 = 0xffffffffu;

fn emitter_count() -> u32 {
    return scene_emitters[0];
}

// The first word of record `i`.
fn emitter_record(i: u32) -> u32 {
    return 2u + scene_emitters[1] + 4u * i;
}

fn emitter_cumulative(i: u32) -> f32 {
    return bitcast<f32>(scene_emitters[emitter_record(i) + 2u]);
}

// The probability of picking record `i` (normalised by the table's last cumulative value, so
// rounding in the table biases nothing).
fn emitter_probability(i: u32) -> f32 {
    return bitcast<f32>(scene_emitters[emitter_record(i) + 3u]) / emitter_cumulative(emitter_count() - 1u);
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

// The probability of picking triangle `primitive` of `instance` (0 if it is no emitter).
fn hit_emitter_probability(instance: u32, primitive: u32) -> f32 {
    if emitter_count() == 0u || instance >= scene_emitters[1] {
        return 0.0;
    }
    let first = scene_emitters[2u + instance];
    if first == NO_EMITTERS {
        return 0.0;
    }
    return emitter_probability(first + primitive);
}

// A triangle of an instance in world space: its corners, and its normal on its
// counter-clockwise side (object space; the side a ray hitting it `front_face` comes from),
// twice its area long.
struct InstanceTriangle {
    corners: array<vec3<f32>, 3>,
    normal: vec3<f32>,
}

// Triangle `primitive` of `instance` (its vertices read once).
fn instance_triangle(instance: u32, primitive: u32) -> InstanceTriangle {
    let inst = scene_instances[instance];
    let mesh = scene_meshes[inst.mesh];
    let first = mesh.first_index + 3u * primitive;
    var local: array<vec3<f32>, 3>;
    var out: InstanceTriangle;
    for (var k = 0u; k < 3u; k++) {
        let v = scene_vertex(mesh.base_vertex + scene_indices[first + k]);
        local[k] = vec3<f32>(v.px, v.py, v.pz);
        out.corners[k] = (inst.model * vec4<f32>(local[k], 1.0)).xyz;
    }
    let n_obj = cross(local[1] - local[0], local[2] - local[0]);
    let n = normalize((inst.normal_matrix * vec4<f32>(n_obj, 0.0)).xyz);
    out.normal = n * length(cross(out.corners[1] - out.corners[0], out.corners[2] - out.corners[0]));
    return out;
}
