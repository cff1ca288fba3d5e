// Directions drawn from the environment map in proportion to its luminance times each texel's
// solid angle (scene::environment::EnvironmentSampler's alias table, bound as
// `scene_environment_table`, group 3 binding 4), and their density: next-event estimation of
// the environment. Needs common/environment.wgsl.

@group(3) @binding(4) var<storage, read> scene_environment_table: array<vec4<u32>>;

// A drawn direction (world frame) and its density per steradian (0: nothing drawn).
struct EnvironmentSample {
    dir: vec3<f32>,
    pdf: f32,
}

// Texel `texel`'s density per steradian at polar position `v`: its probability spread over its
// (u, v) rectangle, whose solid angle per unit of u and v is 2π² sin θ.
fn environment_texel_density(texel: u32, v: f32) -> f32 {
    let sin_theta = sin(v * ENVIRONMENT_PI);
    if sin_theta <= 0.0 {
        return 0.0;
    }
    let p = bitcast<f32>(scene_environment_table[texel].z);
    let texels = f32(scene_environment_params.width * scene_environment_params.height);
    return p * texels / (2.0 * ENVIRONMENT_PI * ENVIRONMENT_PI * sin_theta);
}

// A direction drawn from three uniform numbers in [0, 1): the first picks a slot, the second
// keeps it or takes its alias and is stretched back over [0, 1) for the point's u.
fn environment_sample(u: vec3<f32>) -> EnvironmentSample {
    if scene_environment_params.sampled == 0u {
        return EnvironmentSample(vec3<f32>(0.0, 1.0, 0.0), 0.0);
    }
    let width = scene_environment_params.width;
    let n = width * scene_environment_params.height;
    let slot = min(u32(u.x * f32(n)), n - 1u);
    let entry = scene_environment_table[slot];
    let keep = bitcast<f32>(entry.x);
    var texel = slot;
    var along = u.y / keep;
    if u.y >= keep {
        texel = entry.y;
        along = (u.y - keep) / (1.0 - keep);
    }
    let x = texel % width;
    let y = texel / width;
    let uv = vec2<f32>((f32(x) + min(along, 0.99999994)) / f32(width), min((f32(y) + u.z) / f32(scene_environment_params.height), 1.0));
    return EnvironmentSample(environment_world(environment_direction(uv)), environment_texel_density(texel, uv.y));
}

// The density per steradian with which `environment_sample` draws world direction `dir`.
fn environment_pdf(dir: vec3<f32>) -> f32 {
    if scene_environment_params.sampled == 0u {
        return 0.0;
    }
    let uv = environment_uv(environment_frame(normalize(dir)));
    let width = scene_environment_params.width;
    let height = scene_environment_params.height;
    let x = min(u32(uv.x * f32(width)), width - 1u);
    let y = min(u32(uv.y * f32(height)), height - 1u);
    return environment_texel_density(y * width + x, uv.y);
}
