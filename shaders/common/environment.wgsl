// The scene's environment map (`--env`; src/runtime/environment_upload.rs), bind group 3 of
// every pass that lights surfaces or shows the sky: the radiance (equirectangular, half floats;
// mip level k: prefiltered for GGX roughness k / (levels - 1)), the irradiance at every normal on a 64 x 32 grid
// (scene::environment::IrradianceMap) and the parameters. A scene without a map binds 1x1
// stand-ins (width 1) and `SCENE_ENVIRONMENT` (common/scene_features.wgsl) is false there.
// Directions: +Y up; the map's centre column looks along -Z and u grows towards +X:
// u = 1/2 + atan2(x, -z) / 2π, v = acos(y) / π, in the map's frame, which is the world's turned
// by the rotation about +Y (scene::environment).
//#include "common/scene_features.wgsl"

// Mirrors EnvironmentUniforms in src/uniforms.rs.
struct EnvironmentParams {
    intensity: f32,
    rotation_cos: f32,
    rotation_sin: f32,
    // mip levels of scene_environment (level k: the map prefiltered for roughness k / (levels - 1))
    levels: f32,
    width: u32,
    height: u32,
    // 1: scene_environment_table holds the map's sampler (0: a black map)
    sampled: u32,
    _pad: u32,
}

@group(3) @binding(0) var scene_environment: texture_2d<f32>;
@group(3) @binding(1) var scene_environment_irradiance: texture_2d<f32>;
@group(3) @binding(2) var environment_sampler: sampler;
@group(3) @binding(3) var<uniform> scene_environment_params: EnvironmentParams;

const ENVIRONMENT_PI: f32 = 3.14159265359;

// Whether an environment map lights the scene (the constant, and a real map bound).
fn has_environment() -> bool {
    return SCENE_ENVIRONMENT && scene_environment_params.width > 1u;
}

// World direction `d` in the map's frame (turned back by the rotation about +Y).
fn environment_frame(d: vec3<f32>) -> vec3<f32> {
    let c = scene_environment_params.rotation_cos;
    let s = scene_environment_params.rotation_sin;
    return vec3<f32>(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// The map's direction `d` in the world's frame.
fn environment_world(d: vec3<f32>) -> vec3<f32> {
    let c = scene_environment_params.rotation_cos;
    let s = scene_environment_params.rotation_sin;
    return vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// (u, v) of unit direction `d` of the map's frame.
fn environment_uv(d: vec3<f32>) -> vec2<f32> {
    let u = 0.5 + atan2(d.x, -d.z) / (2.0 * ENVIRONMENT_PI);
    let v = atan2(length(d.xz), d.y) / ENVIRONMENT_PI;
    return vec2<f32>(fract(u), v);
}

// The unit direction of the map's frame at (u, v).
fn environment_direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = (uv.x - 0.5) * 2.0 * ENVIRONMENT_PI;
    let theta = uv.y * ENVIRONMENT_PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// The radiance arriving from world direction `dir`: its texel's (as the importance sampler and
// scene::environment see it), times the intensity.
fn environment_radiance(dir: vec3<f32>) -> vec3<f32> {
    let uv = environment_uv(environment_frame(normalize(dir)));
    let size = vec2<u32>(scene_environment_params.width, scene_environment_params.height);
    let texel = min(vec2<u32>(uv * vec2<f32>(size)), size - vec2<u32>(1u));
    return textureLoad(scene_environment, texel, 0).rgb * scene_environment_params.intensity;
}

// The radiance from world direction `dir` at mip level `level` (0: the map), times the
// intensity.
fn environment_radiance_level(dir: vec3<f32>, level: f32) -> vec3<f32> {
    let uv = environment_uv(environment_frame(normalize(dir)));
    let l = clamp(level, 0.0, scene_environment_params.levels - 1.0);
    return textureSampleLevel(scene_environment, environment_sampler, uv, l).rgb * scene_environment_params.intensity;
}

// The irradiance at a surface of world normal `n` (the grid, read bilinearly; intensity and
// rotation included).
fn environment_irradiance(n: vec3<f32>) -> vec3<f32> {
    let uv = environment_uv(normalize(n));
    return textureSampleLevel(scene_environment_irradiance, environment_sampler, uv, 0.0).rgb;
}

// The split-sum approximation's first factor (Karis 2013) for a surface of `roughness`: the map
// prefiltered with the GGX lobe around the mirror direction `r`, read between the two
// roughness steps about it (scene::environment::Environment::specular_chain).
fn environment_prefiltered(r: vec3<f32>, roughness: f32) -> vec3<f32> {
    return environment_radiance_level(r, clamp(roughness, 0.0, 1.0) * (scene_environment_params.levels - 1.0));
}

// Its second factor, the GGX lobe's directional albedo as a scale and bias of the Fresnel
// reflectance at normal incidence (`f0 * x + f90 * y`), by Karis's fit for mobile ("Physically
// Based Shading on Mobile", 2014) rather than a tabulated integral.
fn environment_brdf_scale_bias(n_v: f32, roughness: f32) -> vec2<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_v)) * r.x + r.y;
    return vec2<f32>(-1.04, 1.04) * a004 + r.zw;
}
