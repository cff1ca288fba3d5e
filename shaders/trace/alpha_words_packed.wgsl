// The alpha test's words in the compute back-end's packed buffer (trace/compute_arrays_packed.wgsl,
// which declares `accel_packed` and `accel_bases`): the substitution of trace/alpha_words.wgsl
// that goes with it.
fn trace_alpha_word(i: u32) -> vec4<u32> {
    return bitcast<vec4<u32>>(accel_packed[accel_bases().w + i]);
}
