// Camera rays and their cones. Needs the main shader to declare `frame: Frame` (include
// common/frame.wgsl first).

// The world-space direction of the camera ray through the centre of pixel `p`.
fn camera_dir(p: vec2<u32>) -> vec3<f32> {
    let ndc = vec2<f32>((f32(p.x) + 0.5) * frame.resolution.z * 2.0 - 1.0, 1.0 - (f32(p.y) + 0.5) * frame.resolution.w * 2.0);
    let far = frame.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    return normalize(far.xyz / far.w - frame.camera_pos.xyz);
}

// The spread angle of pixel `p`'s ray cone: the angle to the next pixel's ray (Ray Tracing
// Gems ch. 20): a cone's width at distance d is about `spread * d`.
fn camera_pixel_spread(p: vec2<u32>) -> f32 {
    return length(camera_dir(p + vec2<u32>(1u, 0u)) - camera_dir(p));
}
