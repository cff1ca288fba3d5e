// The rays of a pixel, shared out over a workgroup's lanes: the `compute` and `ray-query`
// back-ends' module (the `rt-pipeline` back-end substitutes trace/pixel_rays_per_lane.wgsl,
// as a ray-generation shader has no workgroup). A pass whose pixels each trace `count` rays
// (AO: rt/ao.wgsl) defines `PixelRays` (what a pixel's rays start from) and
// `pixel_ray(pixel: PixelRays, i: u32) -> f32` (ray i's value, in [0, 1]), and calls
// `pixel_rays_sum` from every lane of its 8x8 workgroup (no lane may return before it).
//
// Why: when few pixels of a workgroup have rays (a model covering a small part of the frame,
// the edge of a surface against the sky), a pixel per lane leaves most lanes idle while a few
// trace `count` rays each. Here the pixels that have rays are gathered in workgroup memory and
// every lane takes items (pixel, ray) in turn, so the workgroup's time follows its rays, not
// its busiest pixel. Each ray is the one the pixel would trace itself (same `i`), and the sums
// are exact for values 0 and 1 (fixed point, 2^-16 otherwise).

const PIXEL_RAYS_LANES: u32 = 64u;
const PIXEL_RAYS_FIXED_POINT: f32 = 65536.0;

var<workgroup> pixel_rays_of_slot: array<PixelRays, PIXEL_RAYS_LANES>;
var<workgroup> pixel_rays_slot_sum: array<atomic<u32>, PIXEL_RAYS_LANES>;
var<workgroup> pixel_rays_next_slot: atomic<u32>;
var<workgroup> pixel_rays_pixels: u32;

// The sum of `pixel_ray(pixel, i)` for i < `count` for this lane's pixel (0 where it is not
// `has_rays`). `id`: the lane's global invocation id (its place in the 8x8 workgroup).
fn pixel_rays_sum(id: vec2<u32>, pixel: PixelRays, has_rays: bool, count: u32) -> f32 {
    let lane = (id.x % 8u) + 8u * (id.y % 8u);
    if lane == 0u {
        atomicStore(&pixel_rays_next_slot, 0u);
    }
    atomicStore(&pixel_rays_slot_sum[lane], 0u);
    workgroupBarrier();
    var slot = 0u;
    if has_rays {
        slot = atomicAdd(&pixel_rays_next_slot, 1u);
        pixel_rays_of_slot[slot] = pixel;
    }
    workgroupBarrier();
    if lane == 0u {
        pixel_rays_pixels = atomicLoad(&pixel_rays_next_slot);
    }
    let pixels = workgroupUniformLoad(&pixel_rays_pixels);
    // Item k: ray k / pixels of slot k % pixels, so that the lanes trace ray i of many pixels
    // at once, as a pixel per lane would.
    for (var item = lane; item < pixels * count; item += PIXEL_RAYS_LANES) {
        let s = item % pixels;
        let value = clamp(pixel_ray(pixel_rays_of_slot[s], item / pixels), 0.0, 1.0);
        atomicAdd(&pixel_rays_slot_sum[s], u32(round(value * PIXEL_RAYS_FIXED_POINT)));
    }
    workgroupBarrier();
    return select(0.0, f32(atomicLoad(&pixel_rays_slot_sum[slot])) / PIXEL_RAYS_FIXED_POINT, has_rays);
}
