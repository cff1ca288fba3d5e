// The rays of a pixel traced by its own lane: the `rt-pipeline` back-end's module for
// trace/pixel_rays.wgsl (its ray-generation shader has no workgroup to share the rays with; the
// driver schedules them). Same interface and the same rays.

fn pixel_rays_sum(id: vec2<u32>, pixel: PixelRays, has_rays: bool, count: u32) -> f32 {
    var sum = 0.0;
    if has_rays {
        for (var i = 0u; i < count; i++) {
            sum += clamp(pixel_ray(pixel, i), 0.0, 1.0);
        }
    }
    return sum;
}
