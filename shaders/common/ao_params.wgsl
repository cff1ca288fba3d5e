// The AO layer's parameters (layers/rt_ao.ron), shared by its two passes (rt/ao.wgsl,
// rt/ao_sum.wgsl), and how many invocations share a pixel's rays.
struct Params {
    rays: u32,
    range: f32,
    range_scale: f32,
    sampling: u32,
    seed: u32,
    per_frame: u32,
}

// Lanes per pixel: the 2x2 texels of `partial` over each pixel.
const AO_LANES: u32 = 4u;
