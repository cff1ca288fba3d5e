// trace/ray_batch.wgsl's interface for the back-ends other than compute (the runtime substitutes
// this file for it): the batch's rays traced one after another.

fn trace_transmittance_batch_within(origin: vec3<f32>, reach: f32, start: TraceStart, count: u32, flags: u32) -> f32 {
    var sum = 0.0;
    for (var k = 0u; k < count; k++) {
        sum += trace_transmittance_within(Ray(origin, 0.0, trace_batch_direction(k), reach), start, flags);
    }
    return sum;
}
