// Simplified PBR shared by the resolve pass and hit shading: Lambert diffuse plus GGX
// specular (Trowbridge-Reitz distribution, Smith-Schlick visibility, Schlick Fresnel), one
// directional light, one optional point light, and a sky for ambient light and missed rays.

const PI: f32 = 3.14159265359;

fn sky_color(dir: vec3<f32>) -> vec3<f32> {
    return mix(vec3<f32>(0.35, 0.3, 0.25), vec3<f32>(0.6, 0.75, 1.0), 0.5 + 0.5 * dir.y);
}

fn fresnel_schlick(cos_theta: f32, f0: vec3<f32>) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - clamp(cos_theta, 0.0, 1.0), 5.0);
}

fn specular_f0(albedo: vec3<f32>, metallic: f32) -> vec3<f32> {
    return mix(vec3<f32>(0.04), albedo, metallic);
}

// Outgoing radiance towards `v` from light arriving from `l` with irradiance `e` (normal
// incidence), for a surface with normal n.
fn brdf_light(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, e: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32) -> vec3<f32> {
    let n_l = dot(n, l);
    if n_l <= 0.0 {
        return vec3<f32>(0.0);
    }
    let n_v = max(dot(n, v), 1e-4);
    let h = normalize(l + v);
    let n_h = max(dot(n, h), 0.0);
    let a = roughness * roughness;
    let a2 = a * a;
    let d = a2 / (PI * pow(n_h * n_h * (a2 - 1.0) + 1.0, 2.0));
    let k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    let g = (n_l / (n_l * (1.0 - k) + k)) * (n_v / (n_v * (1.0 - k) + k));
    let f = fresnel_schlick(max(dot(h, v), 0.0), specular_f0(albedo, metallic));
    let specular = d * g * f / (4.0 * n_l * n_v);
    let diffuse = (vec3<f32>(1.0) - f) * (1.0 - metallic) * albedo / PI;
    // Lights are given as irradiance; scale so a white Lambert surface facing a light of
    // intensity 1 reflects 1/pi * pi = 1 (keeps the raster and ray-traced modes comparable).
    return (diffuse + specular) * e * n_l * PI;
}
