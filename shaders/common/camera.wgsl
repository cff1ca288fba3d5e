// Camera rays and their cones. Needs the main shader to declare `frame: Frame` (include
// common/frame.wgsl first). `frame.camera_pos.w` is 1 for a perspective camera (rays leave its
// position) and 0 for an orthographic one (parallel rays leave the near plane).

// The camera's projection as a pipeline constant the executor sets from the frame's camera
// (src/runtime/exec/features.rs; the passes are built again when it changes): 1 perspective,
// 2 orthographic, 0 (the default, for pipelines made without it) read from `frame`. A branch on
// the frame's word in every camera function costs the raster shade pass about 5% on an H200.
override CAMERA_PROJECTION: u32 = 0u;

fn camera_is_orthographic() -> bool {
    if CAMERA_PROJECTION != 0u {
        return CAMERA_PROJECTION == 2u;
    }
    return frame.camera_pos.w == 0.0;
}

// The world-space points of the image point `at` (in pixels from the top left corner) on the
// near (depth 0) and far (depth 1) planes.
fn camera_unproject_at(at: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(at.x * frame.resolution.z * 2.0 - 1.0, 1.0 - at.y * frame.resolution.w * 2.0);
    let q = frame.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
    return q.xyz / q.w;
}

// The world-space points of pixel `p`'s centre on the near (depth 0) and far (depth 1) planes.
fn camera_unproject(p: vec2<u32>, depth: f32) -> vec3<f32> {
    return camera_unproject_at(vec2<f32>(f32(p.x) + 0.5, f32(p.y) + 0.5), depth);
}

// Where the camera ray through image point `at` starts: the camera's position, or the point on
// the near plane for an orthographic camera.
fn camera_origin_at(at: vec2<f32>) -> vec3<f32> {
    if camera_is_orthographic() {
        return camera_unproject_at(at, 0.0);
    }
    return frame.camera_pos.xyz;
}

// Where the camera ray through pixel `p`'s centre starts (`camera_origin_at`).
fn camera_origin(p: vec2<u32>) -> vec3<f32> {
    return camera_origin_at(vec2<f32>(f32(p.x) + 0.5, f32(p.y) + 0.5));
}

// The world-space direction of the camera ray through the centre of pixel `p`.
fn camera_dir(p: vec2<u32>) -> vec3<f32> {
    return normalize(camera_unproject(p, 1.0) - camera_origin(p));
}

// The unit direction from the world-space point `x` towards the camera (along the view axis
// for an orthographic camera).
fn camera_view_dir(x: vec3<f32>) -> vec3<f32> {
    if camera_is_orthographic() {
        return -camera_dir(vec2<u32>(0u, 0u));
    }
    return normalize(frame.camera_pos.xyz - x);
}

// The spread angle of pixel `p`'s ray cone: the angle to the next pixel's ray (Ray Tracing
// Gems ch. 20): a cone's width at distance d is about `spread * d` (0 for parallel rays).
fn camera_pixel_spread(p: vec2<u32>) -> f32 {
    return length(camera_dir(p + vec2<u32>(1u, 0u)) - camera_dir(p));
}

// The width of pixel `p`'s ray cone at `distance` along it: `spread * distance`, or the
// pixel's constant width for an orthographic camera.
fn camera_cone_width(p: vec2<u32>, distance: f32) -> f32 {
    if camera_is_orthographic() {
        return length(camera_origin(p + vec2<u32>(1u, 0u)) - camera_origin(p));
    }
    return camera_pixel_spread(p) * distance;
}
