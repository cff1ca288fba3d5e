// Sampling the one shading model (common/lighting.wgsl) for the path tracer (rt/path.wgsl):
// the BSDF times the cosine is `light_radiance` itself, evaluated for a light of unit radiance
// from the sampled direction, so the reference and every mode share one BSDF source. A
// direction is drawn from a mixture of the cosine-weighted hemisphere (the diffuse lobe) and
// the GGX distribution of half vectors (the specular lobe, alpha = roughness^2 as brdf_light),
// chosen by their estimated weights; `bsdf_pdf` is the mixture's density, which covers the
// whole hemisphere (the diffuse part), so the estimate is unbiased whatever lobes a material
// has (the clear coat's lobe is evaluated, not sampled apart).
// Needs common/lighting.wgsl and common/sampling.wgsl.

// A sampled direction, its mixture density (solid angle) and BSDF x cosine there.
struct BsdfSample {
    dir: vec3<f32>,
    pdf: f32,
    f_cos: vec3<f32>,
}

// The BSDF of `s` times the cosine for light arriving from unit `l` (0 where `l` is opposite
// the view, which has no half vector: a shading normal can put both above the surface).
fn bsdf_cos(s: ShadingPoint, l: vec3<f32>) -> vec3<f32> {
    let half = l + s.view;
    if dot(half, half) < 1e-12 {
        return vec3<f32>(0.0);
    }
    return light_radiance(s, LightSample(l, vec3<f32>(1.0 / PI), 3.0e38));
}

fn bsdf_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The probability of sampling the specular lobe at `s`: its Fresnel weight against the
// diffuse lobe's, kept within [0.1, 0.9] so either lobe is drawn now and then.
fn specular_probability(s: ShadingPoint) -> f32 {
    let f = point_fresnel(s, max(dot(s.normal, s.view), 0.0));
    let spec = bsdf_luminance(f);
    let diffuse = bsdf_luminance((vec3<f32>(1.0) - f) * (1.0 - s.metallic) * s.albedo);
    return clamp(spec / max(spec + diffuse, 1e-6), 0.1, 0.9);
}

// GGX density of half vector `h` about `n` times cos(n, h) (brdf_light's D), for alpha^2 `a2`.
fn ggx_half_pdf(n_h: f32, a2: f32) -> f32 {
    let t = n_h * n_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * t * t) * n_h;
}

// The mixture's density of direction `l` at `s` (solid angle).
fn bsdf_pdf(s: ShadingPoint, l: vec3<f32>) -> f32 {
    let n_l = dot(s.normal, l);
    if n_l <= 0.0 {
        return 0.0;
    }
    let p_spec = specular_probability(s);
    let a = s.roughness * s.roughness;
    let half = l + s.view;
    var spec = 0.0;
    if dot(half, half) >= 1e-12 {
        // The sampled half vector that reflects the view to `l` is this one or its opposite
        // (reflect(-v, h) = reflect(-v, -h)): the one about the normal.
        var h = normalize(half);
        if dot(s.normal, h) < 0.0 {
            h = -h;
        }
        spec = ggx_half_pdf(dot(s.normal, h), a * a) / (4.0 * max(abs(dot(s.view, h)), 1e-6));
    }
    return p_spec * spec + (1.0 - p_spec) * n_l / PI;
}

// A direction drawn from the mixture at `s` with uniform numbers `u_lobe` and `u`; pdf 0 when
// the draw leaves the hemisphere of the shading normal (the path ends there).
fn bsdf_sample(s: ShadingPoint, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    var l: vec3<f32>;
    if u_lobe < specular_probability(s) {
        let a = s.roughness * s.roughness;
        let cos2 = (1.0 - u.x) / (1.0 + (a * a - 1.0) * u.x);
        let sin_t = sqrt(max(0.0, 1.0 - cos2));
        let phi = 6.28318530718 * u.y;
        let h = normalize(around(s.normal, vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), sqrt(cos2))));
        l = reflect(-s.view, h);
    } else {
        l = cosine_hemisphere(s.normal, u);
    }
    let pdf = bsdf_pdf(s, l);
    if pdf <= 0.0 {
        return BsdfSample(l, 0.0, vec3<f32>(0.0));
    }
    return BsdfSample(l, pdf, bsdf_cos(s, l));
}
