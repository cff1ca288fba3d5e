// The alpha test's words (trace/alpha.wgsl): the AccelCache's alpha buffer, bound by name.
@group(2) @binding(15) var<storage, read> accel_alpha: array<vec4<u32>>;

fn trace_alpha_word(i: u32) -> vec4<u32> {
    return accel_alpha[i];
}
