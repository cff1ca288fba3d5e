// Motion vectors and disocclusion (layers/motion.ron): the surface at each pixel carried back to
// the previous frame by its instance's previous transform and the camera's previous
// view-projection, then checked against what the previous frame showed there.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"

struct Params {
    depth_tolerance: f32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(3) var<storage, read> scene_motion: array<mat4x4<f32>>;
@group(0) @binding(4) var position: texture_2d<f32>;
@group(0) @binding(5) var surface_previous: texture_2d<f32>;
@group(0) @binding(6) var motion: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var surface: texture_storage_2d<rgba32float, write>;

// The pixel coordinates (pixel centres at +0.5) of a clip-space point of the previous frame.
fn previous_pixel(clip: vec4<f32>) -> vec2<f32> {
    let ndc = clip.xy / clip.w;
    return vec2<f32>((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5) * frame.resolution.xy;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(motion);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let here = vec2<f32>(id.xy) + 0.5;
    let p = textureLoad(position, id.xy, 0);
    textureStore(surface, id.xy, p);
    let valid = frame.history_valid == 1u;
    if p.w == 0.0 {
        // The sky is at infinity: only the camera's turn moves it (an orthographic camera's
        // projection maps no direction to a pixel: its sky is taken as still).
        var before = here;
        if !camera_is_orthographic() {
            before = previous_pixel(frame.prev_view_proj * vec4<f32>(camera_dir(id.xy), 0.0));
        }
        textureStore(motion, id.xy, vec4<f32>(here - before, select(1.0, 0.0, valid), 0.0));
        return;
    }
    let instance = u32(p.w) - 1u;
    let inst = scene_instances[instance];
    // Object space through the inverse of the model's linear part, the transpose of the
    // normal matrix's (inverse transpose) upper 3x3.
    let n = inst.normal_matrix;
    let inverse_linear = transpose(mat3x3<f32>(n[0].xyz, n[1].xyz, n[2].xyz));
    let local = inverse_linear * (p.xyz - inst.model[3].xyz);
    let was = (scene_motion[instance] * vec4<f32>(local, 1.0)).xyz;
    let clip = frame.prev_view_proj * vec4<f32>(was, 1.0);
    let before = previous_pixel(clip);
    var disoccluded = !valid || clip.w <= 0.0 || any(before < vec2<f32>(0.0)) || any(before >= frame.resolution.xy);
    if !disoccluded {
        disoccluded = !seen_before(before, p.w, was, params.depth_tolerance * length(frame.camera_pos.xyz - p.xyz));
    }
    textureStore(motion, id.xy, vec4<f32>(here - before, select(0.0, 1.0, disoccluded), 1.0));
}

// Whether the previous frame showed instance `w` at `was` around pixel position `at`: the four
// texels around it, interpolated where all four show that instance (exact on a plane to second
// order, at any angle), else any one of them that shows it within `tolerance` of `was`.
fn seen_before(at: vec2<f32>, w: f32, was: vec3<f32>, tolerance: f32) -> bool {
    let base = at - 0.5;
    let f = fract(base);
    let last = vec2<i32>(frame.resolution.xy) - 1;
    let i0 = vec2<i32>(floor(base));
    var taps: array<vec4<f32>, 4>;
    var same = 0u;
    var near = false;
    for (var k = 0; k < 4; k++) {
        let texel = clamp(i0 + vec2<i32>(k & 1, k >> 1u), vec2<i32>(0), last);
        taps[k] = textureLoad(surface_previous, texel, 0);
        if taps[k].w == w {
            same += 1u;
            near = near || length(taps[k].xyz - was) <= tolerance;
        }
    }
    if same == 4u {
        let interpolated = mix(mix(taps[0].xyz, taps[1].xyz, f.x), mix(taps[2].xyz, taps[3].xyz, f.x), f.y);
        return length(interpolated - was) <= tolerance;
    }
    return near;
}
