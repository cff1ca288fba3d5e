// Sampling helpers: per-pixel random numbers (PCG hash), the R2 low-discrepancy sequence
// (Roberts 2018) and cosine-weighted hemisphere directions around a normal.

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Two uniform numbers in [0, 1) for a pixel and seed.
fn pixel_random2(pixel: vec2<u32>, seed: u32) -> vec2<f32> {
    let h1 = pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(seed)));
    let h2 = pcg_hash(h1);
    return vec2<f32>(f32(h1 >> 8u), f32(h2 >> 8u)) * (1.0 / 16777216.0);
}

// The next two uniform numbers in [0, 1) of the PCG stream `state`, which it advances.
fn next_random2(state: ptr<function, u32>) -> vec2<f32> {
    *state = pcg_hash(*state);
    let a = *state;
    *state = pcg_hash(*state);
    return vec2<f32>(f32(a >> 8u), f32(*state >> 8u)) * (1.0 / 16777216.0);
}

// The next uniform number in [0, 1) of the PCG stream `state`, which it advances.
fn next_random1(state: ptr<function, u32>) -> f32 {
    *state = pcg_hash(*state);
    return f32(*state >> 8u) * (1.0 / 16777216.0);
}

// `seed`, made new every frame when `per_frame` is set (for layers whose samples a temporal
// filter accumulates).
fn frame_seed(seed: u32, frame_index: u32, per_frame: u32) -> u32 {
    return seed + select(0u, frame_index, per_frame != 0u) * 0x9e3779b9u;
}

// The i-th point of the R2 sequence in [0, 1)^2.
fn r2_sample(i: u32) -> vec2<f32> {
    let g = 1.32471795724474602596;
    return fract(vec2<f32>(0.5) + f32(i + 1u) * vec2<f32>(1.0 / g, 1.0 / (g * g)));
}

// `local` (z along `n`) in world space, through an orthonormal basis around unit `n` (Duff et
// al. 2017).
fn around(n: vec3<f32>, local: vec3<f32>) -> vec3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    return local.x * t + local.y * bt + local.z * n;
}

// A cosine-weighted direction around unit `n` from two uniform numbers.
fn cosine_hemisphere(n: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let r = sqrt(u.x);
    let phi = 6.28318530718 * u.y;
    return normalize(around(n, vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)))));
}

// A direction uniform in solid angle within `cos_max` of unit `n` (a cone), from two uniform
// numbers.
fn uniform_cone(n: vec3<f32>, cos_max: f32, u: vec2<f32>) -> vec3<f32> {
    let c = 1.0 - u.x * (1.0 - cos_max);
    let s = sqrt(max(0.0, 1.0 - c * c));
    let phi = 6.28318530718 * u.y;
    return normalize(around(n, vec3<f32>(s * cos(phi), s * sin(phi), c)));
}

// A point uniform on the unit disc around the origin perpendicular to unit `n`.
fn uniform_disc(n: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let r = sqrt(u.x);
    let phi = 6.28318530718 * u.y;
    return around(n, vec3<f32>(r * cos(phi), r * sin(phi), 0.0));
}
