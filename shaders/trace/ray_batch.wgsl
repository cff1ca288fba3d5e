// A batch of transmittance rays that share an origin, a reach and a start (a lane's AO rays):
//   trace_transmittance_batch_within(origin, reach, start, count, flags) -> f32
//     the sum, in k order, of trace_transmittance_within(Ray(origin, 0, dir_k, reach), start,
//     flags) for k < count, where dir_k = trace_batch_direction(k), a function the includer
//     defines; it is called once for each k, in increasing order (it may advance a random
//     stream).
// This file is the compute back-end's (a trace pass that includes it includes trace/trace.wgsl
// first): a ray below the root is traced in one loop that fetches the lane's next ray as soon
// as its last one is done, so the lanes of a subgroup do not wait for each other's slowest ray
// after every ray (PERF.md, step 25). Each ray visits the nodes and triangles, in the order,
// that trace_transmittance_within visits. Other back-ends substitute trace/ray_batch_loop.wgsl.

fn trace_transmittance_batch_within(origin: vec3<f32>, reach: f32, start: TraceStart, count: u32, flags: u32) -> f32 {
    if start.node == TRACE_START_ROOT {
        return trace_batch_one_by_one(origin, reach, start, 0u, count, flags);
    }
    let cull = (flags & TRACE_CULL_BACK_FACES) != 0u;
    var sum = 0.0;
    var next = 0u;
    var in_flight = false;
    var r: TraceRay;
    var desc = 0u;
    var sp = 0u;
    // A ray whose segment leaves the start's box (none of an AO lane's: their reach is the
    // box's) needs the whole traversal: the loop stops there, and that ray and the rest are
    // traced one by one after it, so the loop holds no second traversal.
    var leaving = false;
    var leaving_dir = vec3<f32>(0.0);
    // Every branch of an iteration ends at the iteration's end (no `continue`, one exit): a
    // subgroup whose lanes took different branches runs on together from there.
    loop {
        if !in_flight && next < count {
            let ray = Ray(origin, 0.0, trace_batch_direction(next), reach);
            next++;
            let end = ray.origin + ray.dir * ray.t_max;
            if any(min(ray.origin, end) < start.lo) || any(max(ray.origin, end) > start.hi) {
                leaving = true;
                leaving_dir = ray.dir;
            } else {
                let fetched = trace_batch_fetch(ray, start);
                if fetched.done {
                    sum += fetched.value;
                } else {
                    r = fetched.ray;
                    desc = fetched.desc;
                    sp = 0u;
                    in_flight = true;
                }
            }
        }
        if in_flight {
            let step = trace_batch_step(r, desc, reach, cull, &sp);
            if step.finished {
                sum += trace_transmittance_result(step.stopped);
                in_flight = false;
            }
            desc = step.desc;
        }
        if leaving || (!in_flight && next == count) {
            break;
        }
    }
    if leaving {
        sum += trace_transmittance_within(Ray(origin, 0.0, leaving_dir, reach), start, flags);
        sum += trace_batch_one_by_one(origin, reach, start, next, count, flags);
    }
    return sum;
}

// The sum of rays first..count of the batch, traced one after another.
fn trace_batch_one_by_one(origin: vec3<f32>, reach: f32, start: TraceStart, first: u32, count: u32, flags: u32) -> f32 {
    var sum = 0.0;
    for (var k = first; k < count; k++) {
        sum += trace_transmittance_within(Ray(origin, 0.0, trace_batch_direction(k), reach), start, flags);
    }
    return sum;
}

// One step of a batch ray's traversal from node `desc`: an interior node's children (the nearer
// one hit next, the other pushed if hit too) or a leaf's triangles; then, where that gives no
// node to visit, the stack's top, or the ray `finished` (`stopped` by a triangle, or the
// stack empty).
struct TraceBatchStep {
    desc: u32,
    finished: bool,
    stopped: bool,
}

fn trace_batch_step(r: TraceRay, desc: u32, reach: f32, cull: bool, sp: ptr<function, u32>) -> TraceBatchStep {
    let n = desc & 7u;
    let first = desc >> 3u;
    var step = TraceBatchStep(desc, false, false);
    var pop = true;
    if n > 0u {
        for (var i = first; i < first + n; i++) {
            if trace_batch_stops(r, trace_tri(i), reach, cull) {
                step.stopped = true;
                break;
            }
        }
        pop = !step.stopped;
    } else {
        let l = trace_blas_node(first);
        let rn = trace_blas_node(first + 1u);
        let hl = trace_slab(r, l, 0.0, reach);
        let hr = trace_slab(r, rn, 0.0, reach);
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
            step.desc = select(dr, dl, near_first);
            pop = false;
        } else if in_l || in_r {
            step.desc = select(dr, dl, in_l);
            pop = false;
        }
    }
    step.finished = step.stopped;
    if pop {
        if *sp == 0u {
            step.finished = true;
        } else {
            *sp -= 1u;
            step.desc = trace_stack[*sp];
        }
    }
    return step;
}

// A batch ray within the start's box as fetched: `done` with its transmittance `value` where it
// needs no traversal below the start (invalid, nothing within reach, or the start node's box
// missed); else its constants and the start node's descriptor.
struct TraceBatchFetch {
    done: bool,
    value: f32,
    ray: TraceRay,
    desc: u32,
}

// trace_transmittance_within, for a ray within the start's box, up to its traversal below the
// start.
fn trace_batch_fetch(ray: Ray, start: TraceStart) -> TraceBatchFetch {
    var f = TraceBatchFetch(true, 1.0, TraceRay(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)), 0u);
    if !trace_transmittance_starts(ray) {
        return f;
    }
    if start.node == TRACE_START_NONE {
        f.value = trace_transmittance_result(false);
        return f;
    }
    f.ray = trace_prepare(ray.origin, ray.dir);
    let node = trace_blas_node(start.node);
    let h = trace_slab(f.ray, node, ray.t_min, ray.t_max);
    if h.x > h.y {
        f.value = trace_transmittance_result(false);
        return f;
    }
    f.done = false;
    f.desc = trace_descriptor(node);
    return f;
}

// Whether triangle `tri` stops a batch ray (trace_blas's any-hit test through BLEND surfaces:
// a hit the alpha test rejects, or a BLEND surface that leaves enough getting through, passes).
fn trace_batch_stops(r: TraceRay, tri: AccelTriangle, reach: f32, cull: bool) -> bool {
    let h = trace_triangle(r, tri, 0.0, reach);
    if h.t < 0.0 || (cull && trace_back_facing(r, tri)) {
        return false;
    }
    if TRACE_ALPHA_TEST && (tri.flags & TRI_ALPHA) != 0u {
        return !trace_transmittance_passes(tri.instance, tri.prim, vec2<f32>(h.u, h.v));
    }
    return true;
}
