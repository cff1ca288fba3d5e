// Back-end `compute`: the project's own two-level BVH (src/accel/layout.rs), traversed here.
// TLAS over instances; per instance the ray goes to object space (direction not renormalised,
// so t stays the world t) and the instance's BLAS is traversed. Nearer child first with one
// stack for both levels; any-hit rays stop at the first hit. The slab test never forms
// infinities (zero direction components become a tiny signed value before the reciprocal),
// takes one multiply-add per plane with a slack that keeps boxes conservative, and widens
// t_far by a few ulps (Ize 2013); the ray-triangle test is watertight (Woop, Benthin, Wald
// 2013) with each edge function's sign taken by comparing its two products, so a shared edge
// gives both triangles opposite signs however the compiler fuses the arithmetic.
// In the merged layout (src/accel/layout.rs) the one instance is the identity and each
// triangle names its scene instance.
// Back-face culling (TRACE_CULL_BACK_FACES) is a per-ray value tested only when a triangle
// test has accepted a hit (trace_back_facing), so rays without it pay one untaken branch per
// accepted hit and nothing per node or triangle.
// Alpha test (trace/alpha.wgsl): also only on an accepted hit, when the instance's flags
// (two-level) or the triangle's (merged layout) say it is alpha-tested; both words come with
// what the traversal already loads, so opaque geometry pays one untaken branch per accepted hit.
//#include "trace/common.wgsl"
//#include "trace/alpha.wgsl"

struct AccelNode {
    min: vec3<f32>,
    // Interior (count == 0): left child; the right child follows it. Leaf: first primitive.
    left_or_first: u32,
    max: vec3<f32>,
    count: u32,
}

struct AccelTriangle {
    v0: vec3<f32>,
    prim: u32,
    v1: vec3<f32>,
    // Merged layout only (instance_id == MERGED_INSTANCE): the triangle's scene instance;
    // `flags` bit 0 set where that instance's transform mirrors, TRI_ALPHA where it is
    // alpha-tested.
    instance: u32,
    v2: vec3<f32>,
    flags: u32,
}

const MERGED_INSTANCE: u32 = 0xfffffffeu;
const TRI_ALPHA: u32 = 2u;
const INSTANCE_ALPHA: u32 = 1u;

// What the traversal reads of an instance (112 bytes in the buffer: the rows of the 3x4
// world-to-object and object-to-world matrices, then blas_root, instance_id, mask, flags).
struct AccelInstance {
    w2o0: vec4<f32>,
    w2o1: vec4<f32>,
    w2o2: vec4<f32>,
    blas_root: u32,
    instance_id: u32,
    mask: u32,
    // INSTANCE_ALPHA: the instance is alpha-tested (two-level layout).
    flags: u32,
}

// The four arrays and their readers: separate bindings (trace/compute_arrays.wgsl), or one
// packed buffer on devices with few storage buffers per stage (trace/compute_arrays_packed.wgsl,
// an include substitution the device selects).
//#include "trace/compute_arrays.wgsl"
@group(2) @binding(4) var<storage, read_write> accel_stats: array<atomic<u32>>;

// The traversal stack, shared by both levels (a BLAS's entries go on top of the TLAS's). WGSL
// zero-initialises every variable: a function-scope array would be cleared on every call (64
// stores per ray, or per instance entered), a module-scope one once per invocation.
const TRACE_STACK: u32 = 64u;
var<private> trace_stack: array<u32, TRACE_STACK>;
// gamma(n) = n u / (1 - n u), u = 2^-24: rounding-error bounds of n floating-point operations.
const TRACE_GAMMA2: f32 = 1.1920930e-7;
const TRACE_GAMMA3: f32 = 1.7881396e-7;
const TRACE_GAMMA5: f32 = 2.9802326e-7;
// 1 + 4 ulps: t_far is widened by this factor so a box the ray grazes is not lost to rounding.
const TRACE_WIDEN: f32 = 1.0000005;

// Per-ray constants of the slab and watertight tests, in one space (world or object).
struct TraceRay {
    origin: vec3<f32>,
    inv_dir: vec3<f32>,
    // The slab test's t = (b - origin) * inv_dir as fma(b, inv_dir, c), one operation per
    // component instead of two: c = -origin * inv_dir, moved by a bound on the rounding error
    // of -origin * inv_dir and of the split product (2^-21 |origin * inv_dir|) towards the
    // outside of the slab: c_min for the box's min planes, c_max for its max planes. The
    // boxes stay conservative for every ray and origin (the hard-case suite's translated
    // scenes), at one added slack per axis.
    c_min: vec3<f32>,
    c_max: vec3<f32>,
    // The watertight test's permute-and-shear map (kz = the largest |dir| component, kx, ky
    // the others; x' = p[kx] - Sx p[kz], y' = p[ky] - Sy p[kz], z' = Sz p[kz]) as three rows,
    // so a vertex is mapped with three dot products instead of nine dynamically indexed
    // components (each row has a 1, an exact -S and a 0, so the values are the same).
    row_x: vec3<f32>,
    row_y: vec3<f32>,
    row_z: vec3<f32>,
}

fn trace_safe_inverse(d: vec3<f32>) -> vec3<f32> {
    // 2^-80: its inverse is exact, so a ray in a slab's plane gets t = 0 there exactly.
    let tiny = select(vec3<f32>(-8.2718061e-25), vec3<f32>(8.2718061e-25), d >= vec3<f32>(0.0));
    return 1.0 / select(d, tiny, abs(d) < vec3<f32>(8.2718061e-25));
}

fn trace_prepare(origin: vec3<f32>, dir: vec3<f32>) -> TraceRay {
    let a = abs(dir);
    var kz = 2u;
    if a.x > a.y && a.x > a.z {
        kz = 0u;
    } else if a.y > a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if dir[kz] < 0.0 {
        let t = kx;
        kx = ky;
        ky = t;
    }
    let shear = vec3<f32>(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
    let axes = vec3<u32>(0u, 1u, 2u);
    let ex = select(vec3<f32>(0.0), vec3<f32>(1.0), axes == vec3<u32>(kx));
    let ey = select(vec3<f32>(0.0), vec3<f32>(1.0), axes == vec3<u32>(ky));
    let ez = select(vec3<f32>(0.0), vec3<f32>(1.0), axes == vec3<u32>(kz));
    let inv = trace_safe_inverse(dir);
    let oi = -origin * inv;
    let slack = abs(oi) * 4.7683716e-7;
    let pos = inv >= vec3<f32>(0.0);
    let c_min = select(oi + slack, oi - slack, pos);
    let c_max = select(oi - slack, oi + slack, pos);
    return TraceRay(origin, inv, c_min, c_max, ex - shear.x * ez, ey - shear.y * ez, shear.z * ez);
}

// The slab test's constants of a ray alone, the watertight test's rows left zero: what the
// test of the root's box needs (trace_merged forms the rows only for rays that hit it). The
// same lines as trace_prepare's last six, written twice on purpose: with trace_prepare taking
// them from here, the driver gave the AO kernel, whose rays call trace_prepare, 64 registers a
// lane instead of 56 (the atrium 1.8% slower; PERF.md step 40).
fn trace_prepare_box(origin: vec3<f32>, dir: vec3<f32>) -> TraceRay {
    let inv = trace_safe_inverse(dir);
    let oi = -origin * inv;
    let slack = abs(oi) * 4.7683716e-7;
    let pos = inv >= vec3<f32>(0.0);
    let c_min = select(oi + slack, oi - slack, pos);
    let c_max = select(oi - slack, oi + slack, pos);
    let zero = vec3<f32>(0.0);
    return TraceRay(origin, inv, c_min, c_max, zero, zero, zero);
}

// Entry and exit distances of the ray through a box (exit < entry: missed).
fn trace_slab(r: TraceRay, node: AccelNode, t_min: f32, t_max: f32) -> vec2<f32> {
    let t1 = fma(node.min, r.inv_dir, r.c_min);
    let t2 = fma(node.max, r.inv_dir, r.c_max);
    let near = min(t1, t2);
    let far = max(t1, t2);
    let enter = max(max(near.x, near.y), max(near.z, t_min));
    let exit = min(min(far.x, far.y), min(far.z, t_max)) * TRACE_WIDEN;
    return vec2<f32>(enter, exit);
}

// A node as the traversal carries it: `left_or_first << 3 | count` (a leaf holds at most 7
// primitives and every index is below 2^29 - 1, which src/accel/layout.rs checks). A step
// reads the two children, whose descriptors come with their boxes, so the node itself is never
// read again.
fn trace_descriptor(n: AccelNode) -> u32 {
    // A shift and an add (one instruction where the GPU has a shift-and-add): count < 8, so
    // the add is the OR.
    return (n.left_or_first << 3u) + n.count;
}

// The descriptor to visit after an interior node whose children `l`, `r` the ray enters over
// the intervals `hl`, `hr` (entry, exit): the nearer child hit (left on a tie), the other
// pushed if hit too; NO_HIT if neither is.
fn trace_children(l: AccelNode, r: AccelNode, hl: vec2<f32>, hr: vec2<f32>, sp: ptr<function, u32>) -> u32 {
    let in_l = hl.x <= hl.y;
    let in_r = hr.x <= hr.y;
    let dl = trace_descriptor(l);
    let dr = trace_descriptor(r);
    if in_l && in_r {
        let near_first = hl.x <= hr.x;
        if *sp < TRACE_STACK {
            trace_stack[*sp] = select(dl, dr, near_first);
            *sp += 1u;
        }
        return select(dr, dl, near_first);
    }
    if in_l {
        return dl;
    }
    if in_r {
        return dr;
    }
    return NO_HIT;
}

// Edge function of the 2D points p, q (sheared triangle vertices) as its two products:
// e = x - y. The inside test compares them (x < y, x > y) rather than the sign of the
// difference: a comparison cannot be fused into an FMA, and swapping p and q swaps x and y
// bitwise, so the two triangles of a shared edge always see opposite signs (watertight).
fn trace_edge(p: vec2<f32>, q: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(p.x * q.y, p.y * q.x);
}

struct TriHit {
    t: f32,
    u: f32,
    v: f32,
}

// Watertight ray-triangle test; t < 0 means no hit inside (t_min, t_max).
fn trace_triangle(r: TraceRay, tri: AccelTriangle, t_min: f32, t_max: f32) -> TriHit {
    let a3 = tri.v0 - r.origin;
    let b3 = tri.v1 - r.origin;
    let c3 = tri.v2 - r.origin;
    let a = vec2<f32>(dot(r.row_x, a3), dot(r.row_y, a3));
    let b = vec2<f32>(dot(r.row_x, b3), dot(r.row_y, b3));
    let c = vec2<f32>(dot(r.row_x, c3), dot(r.row_y, c3));
    let eu = trace_edge(b, c);
    let ev = trace_edge(c, a);
    let ew = trace_edge(a, b);
    let miss = TriHit(-1.0, 0.0, 0.0);
    if (eu.x < eu.y || ev.x < ev.y || ew.x < ew.y) && (eu.x > eu.y || ev.x > ev.y || ew.x > ew.y) {
        return miss;
    }
    let u = eu.x - eu.y;
    let v = ev.x - ev.y;
    let w = ew.x - ew.y;
    let det = u + v + w;
    if det == 0.0 {
        return miss;
    }
    let az = dot(r.row_z, a3);
    let bz = dot(r.row_z, b3);
    let cz = dot(r.row_z, c3);
    let t = (u * az + v * bz + w * cz) / det;
    if !(t > t_min && t <= t_max) {
        return miss;
    }
    // A conservative bound on t's rounding error (PBR 3rd ed. 3.9.2, with the shear term of x'
    // and y' bounded by |dir[kx]| z' and |dir[ky]| z' instead of z': PBR's bound rejects true
    // hits of grazing rays): closer hits may lie behind the origin (a ray leaving a large
    // triangle at a shallow angle would hit it again).
    let max_z = max(abs(az), max(abs(bz), abs(cz)));
    let max_x = max(abs(a.x), max(abs(b.x), abs(c.x)));
    let max_y = max(abs(a.y), max(abs(b.y), abs(c.y)));
    let max_e = max(abs(u), max(abs(v), abs(w)));
    let delta_z = TRACE_GAMMA3 * max_z;
    // |dir[kx]| = |Sx / Sz| = |row_x . row_z| / (row_z . row_z) (row_x = e_kx - Sx e_kz,
    // row_z = Sz e_kz), widened by 1e-6 for its own rounding; the same for y. Computed here,
    // for accepted hits only, rather than carried with the ray.
    let zz = dot(r.row_z, r.row_z);
    let shear_x = abs(dot(r.row_x, r.row_z)) / zz * 1.000001;
    let shear_y = abs(dot(r.row_y, r.row_z)) / zz * 1.000001;
    let delta_x = TRACE_GAMMA5 * (max_x + shear_x * max_z);
    let delta_y = TRACE_GAMMA5 * (max_y + shear_y * max_z);
    let delta_e = 2.0 * (TRACE_GAMMA2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let delta_t = 3.0 * (TRACE_GAMMA3 * max_e * max_z + delta_e * max_z + delta_z * max_e) * abs(1.0 / det);
    if t <= delta_t {
        return miss;
    }
    return TriHit(t, v / det, w / det);
}

// Whether an accepted hit of `tri` is on its back face: clockwise seen from the ray origin in
// object space (the sign of dot((v1 - v0) x (v2 - v0), dir)), for the merged layout's world-space
// triangles flipped back where the instance mirrors. The direction comes from the shear rows:
// row_x x row_y = |Sz| dir for both orders of kx, ky.
fn trace_back_facing(r: TraceRay, tri: AccelTriangle) -> bool {
    let n = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    return (dot(n, cross(r.row_x, r.row_y)) > 0.0) != ((tri.flags & 1u) != 0u);
}

fn trace_to_object(m0: vec4<f32>, m1: vec4<f32>, m2: vec4<f32>, p: vec3<f32>, w: f32) -> vec3<f32> {
    let h = vec4<f32>(p, w);
    return vec3<f32>(dot(m0, h), dot(m1, h), dot(m2, h));
}

// Traverses one BLAS on top of the TLAS entries already on `trace_stack`. Returns the index of the closest (or, for any-hit, the first) triangle hit, NO_HIT if none;
// `best` carries t and barycentrics in and out; `sp` is back where it was on return.
// `cull`: back faces are passed through (TRACE_CULL_BACK_FACES). `alpha_instance`: the scene
// instance if the whole instance is alpha-tested, else NO_HIT (merged triangles carry TRI_ALPHA
// and their instance themselves); hits the alpha test rejects are passed through.
// `through_blend` (with `any_hit`): a BLEND surface the alpha test keeps is passed through,
// its coverage taken out of trace_transmitted, unless what is left falls below
// TRACE_TRANSMITTANCE_MIN (then it stops the ray as an opaque one does); without `any_hit`
// (TRACE_PASS_BLEND): every BLEND surface is passed through.
fn trace_blas(root: u32, r: TraceRay, t_min: f32, best: ptr<function, TriHit>, any_hit: bool, through_blend: bool, cull: bool, alpha_instance: u32, sp: ptr<function, u32>) -> u32 {
    let base = *sp;
    var desc = trace_descriptor(trace_blas_node(root));
    var found = NO_HIT;
    loop {
        let count = desc & 7u;
        let first = desc >> 3u;
        if count > 0u {
            for (var i = first; i < first + count; i++) {
                let tri = trace_tri(i);
                let h = trace_triangle(r, tri, t_min, (*best).t);
                if h.t >= 0.0 && !(cull && trace_back_facing(r, tri)) {
                    let tri_alpha = (tri.flags & TRI_ALPHA) != 0u;
                    if TRACE_ALPHA_TEST && (alpha_instance != NO_HIT || tri_alpha) {
                        let owner = select(alpha_instance, tri.instance, tri_alpha);
                        let bary = vec2<f32>(h.u, h.v);
                        var passed: bool;
                        if through_blend && any_hit {
                            passed = trace_transmittance_passes(owner, tri.prim, bary);
                        } else if through_blend {
                            passed = trace_visible_passes(owner, tri.prim, bary);
                        } else {
                            passed = !trace_alpha_visible(owner, tri.prim, bary);
                        }
                        if passed {
                            continue;
                        }
                    }
                    *best = h;
                    found = i;
                    if any_hit {
                        *sp = base;
                        return found;
                    }
                }
            }
        } else {
            let l = trace_blas_node(first);
            let rn = trace_blas_node(first + 1u);
            // trace_children, written out: continuing from each branch instead of returning a
            // descriptor to test measured 4% faster on the H100 (PERF.md).
            let hl = trace_slab(r, l, t_min, (*best).t);
            let hr = trace_slab(r, rn, t_min, (*best).t);
            let in_l = hl.x <= hl.y;
            let in_r = hr.x <= hr.y;
            let dl = trace_descriptor(l);
            let dr = trace_descriptor(rn);
            if in_l && in_r {
                let near_first = hl.x <= hr.x;
                if *sp < TRACE_STACK {
                    trace_stack[*sp] = select(dl, dr, near_first);
                    *sp += 1u;
                }
                desc = select(dr, dl, near_first);
                continue;
            }
            if in_l {
                desc = dl;
                continue;
            }
            if in_r {
                desc = dr;
                continue;
            }
        }
        if *sp == base {
            break;
        }
        *sp -= 1u;
        desc = trace_stack[*sp];
    }
    return found;
}

struct TraceResult {
    hit: Hit,
    any: bool,
}

// Whether the acceleration structure is the merged layout (one identity instance whose BLAS
// holds every triangle, src/accel/layout.rs `merge`), set by the executor where the plan's
// `Accel` node merges on this back-end. Each traversal call in a kernel is a copy of its loops,
// and the driver gives the whole kernel the registers of its worst point: with it, each call
// is the one BLAS loop, without the two-level code the merged layout never runs (PERF.md step
// 38: 56 registers a lane in the AO and primary tests' kernels instead of 72-80). The default
// traverses both levels, right for every layout.
override TRACE_MERGED: bool = false;

// The scene instance whose hits run the alpha test, if the whole instance `inst` is
// alpha-tested (two-level layout), else NO_HIT (trace_blas's `alpha_instance`).
fn trace_alpha_instance(inst: AccelInstance) -> u32 {
    return select(NO_HIT, inst.instance_id, (inst.flags & INSTANCE_ALPHA) != 0u);
}

// The hit record of triangle `tri` of the instance `inst_id` hit at `best`; `d` the ray's
// direction in the instance's space. A merged triangle names its scene instance, and its
// `flags` bit 0 says that instance mirrors.
fn trace_hit_record(tri: u32, best: TriHit, d: vec3<f32>, inst_id: u32, merged: bool) -> Hit {
    let t = trace_tri(tri);
    let n = cross(t.v1 - t.v0, t.v2 - t.v0);
    let id = select(inst_id, t.instance, merged);
    let front = (dot(n, d) < 0.0) != (merged && (t.flags & 1u) != 0u);
    return Hit(best.t, id, t.prim, vec2<f32>(best.u, best.v), front);
}

fn trace_impl(ray: Ray, any_hit: bool, through_blend: bool, cull: bool) -> TraceResult {
    let root = trace_tlas_node(0u);
    if TRACE_MERGED {
        return trace_merged(ray, root, any_hit, through_blend, cull);
    }
    return trace_levels(ray, trace_prepare(ray.origin, ray.dir), root, any_hit, through_blend, cull);
}

// trace_impl in the merged layout (TRACE_MERGED): the root's box (the TLAS's one leaf), then
// the one instance's BLAS, in world space. The same nodes in the same order as trace_levels.
// The root's box is tested with the slab's constants alone and the watertight test's rows are
// formed after it: with them formed first, rays that miss the scene took 49% longer (PERF.md
// steps 39-40).
fn trace_merged(ray: Ray, root: AccelNode, any_hit: bool, through_blend: bool, cull: bool) -> TraceResult {
    let h = trace_slab(trace_prepare_box(ray.origin, ray.dir), root, ray.t_min, ray.t_max);
    if h.x > h.y {
        return TraceResult(trace_miss(), false);
    }
    let world = trace_prepare(ray.origin, ray.dir);
    let inst = trace_instance(root.left_or_first);
    if inst.mask == 0u {
        return TraceResult(trace_miss(), false); // padding instance of an empty scene
    }
    var best = TriHit(ray.t_max, 0.0, 0.0);
    var sp = 0u;
    let alpha_instance = trace_alpha_instance(inst);
    let tri = trace_blas(inst.blas_root, world, ray.t_min, &best, any_hit, through_blend, cull, alpha_instance, &sp);
    if tri == NO_HIT {
        return TraceResult(trace_miss(), false);
    }
    if any_hit {
        return TraceResult(trace_miss(), true);
    }
    return TraceResult(trace_hit_record(tri, best, ray.dir, inst.instance_id, true), true);
}

// trace_impl through both levels: the TLAS from its root `root` and, in each instance the ray
// enters, its BLAS.
fn trace_levels(ray: Ray, world: TraceRay, root: AccelNode, any_hit: bool, through_blend: bool, cull: bool) -> TraceResult {
    var best = TriHit(ray.t_max, 0.0, 0.0);
    var result = trace_miss();
    var hit_anything = false;
    // A root that is a leaf (one instance) is entered unconditionally by the loop below; its
    // box is tested here first, so rays that miss the scene stop.
    if root.count > 0u {
        let h = trace_slab(world, root, ray.t_min, best.t);
        if h.x > h.y {
            return TraceResult(result, false);
        }
    }
    var sp = 0u;
    var desc = trace_descriptor(root);
    loop {
        let count = desc & 7u;
        let first = desc >> 3u;
        if count > 0u {
            for (var i = first; i < first + count; i++) {
                let inst = trace_instance(i);
                if inst.mask == 0u {
                    continue; // padding instance of an empty scene
                }
                // The merged layout's one instance is the identity: the world ray is the
                // object-space ray.
                let merged = inst.instance_id == MERGED_INSTANCE;
                var d = ray.dir;
                var r = world;
                if !merged {
                    d = trace_to_object(inst.w2o0, inst.w2o1, inst.w2o2, ray.dir, 0.0);
                    r = trace_prepare(trace_to_object(inst.w2o0, inst.w2o1, inst.w2o2, ray.origin, 1.0), d);
                }
                let alpha_instance = trace_alpha_instance(inst);
                let tri = trace_blas(inst.blas_root, r, ray.t_min, &best, any_hit, through_blend, cull, alpha_instance, &sp);
                if tri != NO_HIT {
                    hit_anything = true;
                    if any_hit {
                        return TraceResult(result, true);
                    }
                    result = trace_hit_record(tri, best, d, inst.instance_id, merged);
                }
            }
        } else {
            let l = trace_tlas_node(first);
            let rn = trace_tlas_node(first + 1u);
            let next = trace_children(l, rn, trace_slab(world, l, ray.t_min, best.t), trace_slab(world, rn, ray.t_min, best.t), &sp);
            if next != NO_HIT {
                desc = next;
                continue;
            }
        }
        if sp == 0u {
            break;
        }
        sp--;
        desc = trace_stack[sp];
    }
    return TraceResult(result, hit_anything);
}

fn trace_closest_flags(ray: Ray, flags: u32) -> Hit {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return trace_miss();
    }
    trace_count_closest++;
    let r = trace_impl(ray, false, (flags & TRACE_PASS_BLEND) != 0u, (flags & TRACE_CULL_BACK_FACES) != 0u);
    if r.any {
        trace_count_hits++;
    }
    return r.hit;
}

fn trace_any_flags(ray: Ray, flags: u32) -> bool {
    if !trace_ray_is_valid(ray) {
        trace_count_invalid++;
        return false;
    }
    trace_count_any++;
    let hit = trace_impl(ray, true, false, (flags & TRACE_CULL_BACK_FACES) != 0u).any;
    if hit {
        trace_count_hits++;
    }
    return hit;
}

fn trace_transmittance_flags(ray: Ray, flags: u32) -> f32 {
    if !trace_transmittance_starts(ray) {
        return 1.0;
    }
    return trace_transmittance_result(trace_impl(ray, true, true, (flags & TRACE_CULL_BACK_FACES) != 0u).any);
}

// Whether rays within a sphere start below the root (trace_start_within). The executor turns
// it off for a scene of few triangles (src/runtime/exec/features.rs), whose AO the per-lane
// descent slowed; the default keeps it.
override TRACE_START_BELOW_ROOT: bool = true;

// Whether boxes [a_lo, a_hi] and [b_lo, b_hi] overlap.
fn trace_boxes_overlap(a_lo: vec3<f32>, a_hi: vec3<f32>, b_lo: vec3<f32>, b_hi: vec3<f32>) -> bool {
    return all(a_lo <= b_hi) && all(b_lo <= a_hi);
}

// The node of the merged BLAS under which lies every triangle that a ray staying within
// `radius` of `origin` can hit: from the root down, while only one child's box overlaps the
// box of that sphere (a triangle such a ray hits lies in that box, and in the box of every node
// that holds it); where neither does, nothing is within reach. The box is widened by 1e-4 of
// the radius and 1e-6 of the origin's largest coordinate, beyond the rounding of a hit's t.
// TRACE_START_ROOT where the scene is not one merged instance (two levels, or an alpha-tested
// instance of its own), or where TRACE_START_BELOW_ROOT is off.
fn trace_start_within(origin: vec3<f32>, radius: f32) -> TraceStart {
    let e = radius * 1.0001 + max(max(abs(origin.x), abs(origin.y)), abs(origin.z)) * 1e-6;
    var start = TraceStart(TRACE_START_ROOT, origin - vec3<f32>(e), origin + vec3<f32>(e));
    let root = trace_tlas_node(0u);
    if !TRACE_START_BELOW_ROOT || root.count != 1u || !(radius >= 0.0) {
        return start;
    }
    let inst = trace_instance(root.left_or_first);
    if inst.instance_id != MERGED_INSTANCE || inst.mask == 0u || (inst.flags & INSTANCE_ALPHA) != 0u {
        return start;
    }
    start.node = select(TRACE_START_NONE, inst.blas_root, trace_boxes_overlap(root.min, root.max, start.lo, start.hi));
    while start.node != TRACE_START_NONE {
        let n = trace_blas_node(start.node);
        if n.count > 0u {
            break;
        }
        let l = trace_blas_node(n.left_or_first);
        let r = trace_blas_node(n.left_or_first + 1u);
        let in_l = trace_boxes_overlap(l.min, l.max, start.lo, start.hi);
        let in_r = trace_boxes_overlap(r.min, r.max, start.lo, start.hi);
        if in_l && in_r {
            break;
        }
        start.node = select(select(TRACE_START_NONE, n.left_or_first + 1u, in_r), n.left_or_first, in_l);
    }
    return start;
}

fn trace_transmittance_within(ray: Ray, start: TraceStart, flags: u32) -> f32 {
    if TRACE_MERGED {
        return trace_transmittance_merged(ray, start, flags);
    }
    if start.node == TRACE_START_ROOT {
        return trace_transmittance_flags(ray, flags);
    }
    if !trace_transmittance_starts(ray) {
        return 1.0;
    }
    let cull = (flags & TRACE_CULL_BACK_FACES) != 0u;
    if !trace_segment_within(ray, start) {
        return trace_transmittance_result(trace_impl(ray, true, true, cull).any);
    }
    if start.node == TRACE_START_NONE {
        return trace_transmittance_result(false);
    }
    return trace_transmittance_below(ray, start.node, NO_HIT, cull);
}

// Whether the segment [0, t_max] of `ray` stays in the start's box: both its ends do (the box
// is convex).
fn trace_segment_within(ray: Ray, start: TraceStart) -> bool {
    let end = ray.origin + ray.dir * ray.t_max;
    return !(any(min(ray.origin, end) < start.lo) || any(max(ray.origin, end) > start.hi));
}

// The any-hit traversal of transmittance rays from BLAS node `node` (trace_blas's
// `alpha_instance`, `cull`), as trace_transmittance_result gives it.
fn trace_transmittance_below(ray: Ray, node: u32, alpha_instance: u32, cull: bool) -> f32 {
    var best = TriHit(ray.t_max, 0.0, 0.0);
    var sp = 0u;
    let r = trace_prepare(ray.origin, ray.dir);
    let h = trace_slab(r, trace_blas_node(node), ray.t_min, best.t);
    let stopped = h.x <= h.y && trace_blas(node, r, ray.t_min, &best, true, true, cull, alpha_instance, &sp) != NO_HIT;
    return trace_transmittance_result(stopped);
}

// trace_transmittance_within in the merged layout (TRACE_MERGED), with one traversal call:
// from the start node, or from the instance's BLAS root for rays from the root (trace_levels
// would enter that BLAS through the TLAS's one leaf, whose box is the BLAS root's). A ray is
// not tested for staying in the start's box: the interface's rays reach no farther than its
// radius (trace/common.wgsl), and the test cost the atrium's frame 2.8% (PERF.md step 43).
fn trace_transmittance_merged(ray: Ray, start: TraceStart, flags: u32) -> f32 {
    if !trace_transmittance_starts(ray) {
        return 1.0;
    }
    var node = start.node;
    var alpha_instance = NO_HIT;
    if node == TRACE_START_ROOT {
        let inst = trace_instance(trace_tlas_node(0u).left_or_first);
        node = select(inst.blas_root, TRACE_START_NONE, inst.mask == 0u);
        alpha_instance = trace_alpha_instance(inst);
    }
    if node == TRACE_START_NONE {
        return trace_transmittance_result(false);
    }
    return trace_transmittance_below(ray, node, alpha_instance, (flags & TRACE_CULL_BACK_FACES) != 0u);
}
