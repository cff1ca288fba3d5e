// Robust ray origins from surface points: the point is moved along the geometric normal by a
// distance proportional to its largest coordinate (256 ulps of it), and by at least a fixed
// 2^-16 near the origin. A surface point (from a G-buffer or origin + t * dir) carries a
// rounding error of a few ulps of the largest coordinate involved in computing it, in every
// component: a per-component offset (Wächter & Binder, Ray Tracing Gems ch. 6) moves a
// component that happens to be near zero by too little when the others are large, and a plane
// then shadows itself (tests/hard_cases.rs, a plane scaled by 1e4).
const RAY_OFFSET_RELATIVE: f32 = 256.0 / 8388608.0; // 256 ulps of 1 (2^-23 each)
const RAY_OFFSET_MIN: f32 = 1.0 / 65536.0;

fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let a = abs(p);
    let largest = max(a.x, max(a.y, a.z));
    return p + n * max(largest * RAY_OFFSET_RELATIVE, RAY_OFFSET_MIN);
}
