// One light of the scene picked by resampled importance sampling (Talbot et al. 2005), to stand
// for all of them at a shading point: of `candidates` lights drawn uniformly, one in proportion
// to the luminance of its unshadowed light there; its weight (the candidates' mean of luminance
// over density, divided by the picked one's luminance) makes weight x its light an unbiased
// estimate of every light's. Used by rt/shadow.wgsl and, at ray hits, common/hit_lighting.wgsl.
// Needs common/lighting.wgsl, common/sampling.wgsl, `frame` and `scene_lights`.

struct PickedLight {
    index: u32,
    weight: f32,
}

// No candidate lights the point.
const NO_LIGHT: u32 = 0xffffffffu;

fn pick_light(s: ShadingPoint, p: vec3<f32>, candidates: u32, state: ptr<function, u32>) -> PickedLight {
    let count = frame.light_count;
    var picked = PickedLight(NO_LIGHT, 0.0);
    var picked_goal = 0.0;
    var sum = 0.0;
    for (var k = 0u; k < candidates && count > 0u; k++) {
        let i = min(u32(next_random1(state) * f32(count)), count - 1u);
        let goal = dot(light_radiance(s, light_sample(scene_lights[i], p)), vec3<f32>(0.2126, 0.7152, 0.0722));
        let w = goal * f32(count);
        sum += w;
        if w > 0.0 && next_random1(state) * sum < w {
            picked.index = i;
            picked_goal = goal;
        }
    }
    if picked.index != NO_LIGHT {
        picked.weight = sum / (f32(candidates) * picked_goal);
    }
    return picked;
}
