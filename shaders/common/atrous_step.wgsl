// One à-trous step of the edge-aware wavelet filter (layers/atrous.ron): a 5x5 B3-spline
// kernel with taps `step` pixels apart, each weighted by the likeness of its surface (normal,
// distance along this pixel's normal) and luminance; the variance (alpha) filtered with the
// squared weights. Needs the main shader to declare `frame`, `params` (sigma_luminance,
// sigma_normal, sigma_depth), `position` and `normal`.

fn atrous_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The filtered value of `src` (rgb: signal, a: variance) at pixel `p`.
fn atrous_step(src: texture_2d<f32>, p: vec2<i32>, step: i32) -> vec4<f32> {
    let centre = textureLoad(src, p, 0);
    let x = textureLoad(position, p, 0);
    if x.w == 0.0 || centre.a < 0.0 {
        return centre; // no surface, or no signal here
    }
    let n = normalize(textureLoad(normal, p, 0).xyz);
    let l = atrous_luminance(centre.rgb);
    let depth_scale = params.sigma_depth * length(frame.camera_pos.xyz - x.xyz) * f32(step) + 1e-6;
    let luminance_scale = params.sigma_luminance * sqrt(max(centre.a, 0.0)) + 1e-4;
    let kernel = array<f32, 5>(1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
    let last = vec2<i32>(textureDimensions(src)) - 1;
    var sum = vec3<f32>(0.0);
    var variance = 0.0;
    var weights = 0.0;
    for (var j = -2; j <= 2; j++) {
        for (var i = -2; i <= 2; i++) {
            let q = p + vec2<i32>(i, j) * step;
            if any(q < vec2<i32>(0)) || any(q > last) {
                continue;
            }
            let y = textureLoad(position, q, 0);
            if y.w == 0.0 {
                continue;
            }
            let v = textureLoad(src, q, 0);
            if v.a < 0.0 {
                continue; // no signal there
            }
            let m = normalize(textureLoad(normal, q, 0).xyz);
            let w_normal = pow(max(dot(n, m), 0.0), params.sigma_normal);
            let w_depth = exp(-abs(dot(n, y.xyz - x.xyz)) / depth_scale);
            let w_luminance = exp(-abs(atrous_luminance(v.rgb) - l) / luminance_scale);
            let w = kernel[i + 2] * kernel[j + 2] * w_normal * w_depth * w_luminance;
            sum += w * v.rgb;
            variance += w * w * v.a;
            weights += w;
        }
    }
    // The centre's weight is at least 9/64: never zero.
    return vec4<f32>(sum / weights, variance / (weights * weights));
}
