// The AO layers' parameters (layers/rt_ao.ron and its variants), shared by their passes, and
// how many invocations share a pixel's rays in the four-lane schedule.
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
