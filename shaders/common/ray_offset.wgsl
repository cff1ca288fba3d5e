// Robust ray origins from surface points (Wächter & Binder, "A Fast and Robust Method for
// Avoiding Self-Intersection", Ray Tracing Gems ch. 6): move the point along the geometric
// normal by a number of integer ulps that scales with its magnitude, or by a fixed small
// distance near the origin, where ulps are too small to escape the surface's rounding.
const RAY_OFFSET_ORIGIN: f32 = 1.0 / 32.0;
const RAY_OFFSET_FLOAT_SCALE: f32 = 1.0 / 65536.0;
const RAY_OFFSET_INT_SCALE: f32 = 256.0;

fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let of_i = vec3<i32>(RAY_OFFSET_INT_SCALE * n);
    let p_i = vec3<f32>(
        bitcast<f32>(bitcast<i32>(p.x) + select(of_i.x, -of_i.x, p.x < 0.0)),
        bitcast<f32>(bitcast<i32>(p.y) + select(of_i.y, -of_i.y, p.y < 0.0)),
        bitcast<f32>(bitcast<i32>(p.z) + select(of_i.z, -of_i.z, p.z < 0.0)),
    );
    return select(p_i, p + RAY_OFFSET_FLOAT_SCALE * n, abs(p) < vec3<f32>(RAY_OFFSET_ORIGIN));
}
