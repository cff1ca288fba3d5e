// The one shading model of every mode (forward raster, the hybrid/full-RT resolve, reflection
// hits): Lambert diffuse plus GGX specular (Trowbridge-Reitz distribution, Smith-Schlick
// visibility, Schlick Fresnel) per light, a sky for ambient light (scaled by AO and the
// material's occlusion), missed rays and the specular reflection of surfaces no reflection ray
// leaves, and emission. Each mode supplies only the visibility
// of each light (shadow maps or shadow rays) and the AO.
//
// Lights are records of `scene_lights` (`frame.light_count` of them; src/runtime/scene_upload.rs):
// directional, point and spot, with glTF KHR_lights_punctual's range window
// clamp(1 - (d/range)^4, 0, 1)^2 / d^2 and cone falloff
// clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1)^2. Intensities are a linear
// radiance scale: a white Lambert surface facing a directional light of intensity 1 (or a point
// light of intensity 1 at distance 1) has radiance 1.
// With an environment map (`--env`, common/environment.wgsl) the sky is the map: misses and
// mirrors show it, the ambient term is its irradiance at the normal (x AO x material occlusion),
// and modes that trace no reflection ray reflect it by the split-sum approximation (`sky_specular`).
// Needs the main shader to declare `frame` (common/frame.wgsl).
//#include "common/gbuffer_material_word.wgsl"
//#include "common/scene_features.wgsl"
//#include "common/environment.wgsl"
//#include "common/lobes.wgsl"

const PI: f32 = 3.14159265359;

const LIGHT_DIRECTIONAL: u32 = 0u;
const LIGHT_POINT: u32 = 1u;
const LIGHT_SPOT: u32 = 2u;

// Mirrors LightUniforms in src/uniforms.rs.
struct Light {
    position: vec3<f32>,
    kind: u32,
    // the way the light shines (from the light towards the scene)
    direction: vec3<f32>,
    // 0: infinite
    range: f32,
    // colour x intensity
    radiance: vec3<f32>,
    cos_inner: f32,
    cos_outer: f32,
    // raster shadow-map slot (frame.shadow_view_proj), -1: none
    shadow_map: i32,
    // world length of the shadow map's depth range
    shadow_depth_range: f32,
    _pad: u32,
}

// Light arriving at a point: unit direction towards the light, irradiance at normal incidence,
// and the distance a shadow ray may travel (3e38 for directional lights).
struct LightSample {
    l: vec3<f32>,
    e: vec3<f32>,
    distance: f32,
}

// What every mode knows about a shaded point.
struct ShadingPoint {
    position: vec3<f32>,
    // shading normal
    normal: vec3<f32>,
    // unit direction towards the viewer
    view: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // material occlusion (1: none); scales the ambient term only
    occlusion: f32,
    emissive: vec3<f32>,
    // KHR_materials_unlit: the point shows its albedo (the base colour) and nothing else
    // (false in a zero-initialised point)
    unlit: bool,
    // The specular lobes (set by shading_lobes; common/lobes.wgsl): the dielectric part's
    // reflectance at normal incidence (0.04: glTF's core material) and at grazing angles (1),
    // the clear coat's weight (0: none), perceptual roughness and normal.
    f0: vec3<f32>,
    f90: f32,
    clearcoat: f32,
    clearcoat_roughness: f32,
    coat_normal: vec3<f32>,
}

// Sets the specular lobes of `s`.
fn shading_lobes(s: ptr<function, ShadingPoint>, lobes: SurfaceLobes) {
    (*s).f0 = lobes.f0;
    (*s).f90 = lobes.f90;
    (*s).clearcoat = lobes.clearcoat;
    (*s).clearcoat_roughness = lobes.clearcoat_roughness;
    (*s).coat_normal = lobes.coat_normal;
}

// The sky's colour towards `dir`: the environment map's radiance, or the analytic sky (whose
// light the ambient term scales by `frame.ambient`).
fn sky_color(dir: vec3<f32>) -> vec3<f32> {
    if has_environment() {
        return environment_radiance(dir);
    }
    return mix(vec3<f32>(0.35, 0.3, 0.25), vec3<f32>(0.6, 0.75, 1.0), 0.5 + 0.5 * dir.y);
}

fn fresnel_schlick(cos_theta: f32, f0: vec3<f32>) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - clamp(cos_theta, 0.0, 1.0), 5.0);
}

// Reflectance at normal incidence: the dielectric part's `dielectric` (0.04 for glTF's core
// material), the base colour for metals.
fn specular_f0(albedo: vec3<f32>, metallic: f32, dielectric: vec3<f32>) -> vec3<f32> {
    return mix(dielectric, albedo, metallic);
}

// Schlick's Fresnel term from `f0` at normal incidence to `f90` at grazing angles.
fn fresnel_schlick_f90(cos_theta: f32, f0: vec3<f32>, f90: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(f90) - f0) * pow(1.0 - clamp(cos_theta, 0.0, 1.0), 5.0);
}

// The Fresnel reflectance of point `s` seen at cosine `cos_theta`: the dielectric part's
// (f0 to f90) mixed with the metal's (base colour to 1) by metalness.
fn point_fresnel(s: ShadingPoint, cos_theta: f32) -> vec3<f32> {
    return fresnel_schlick_f90(cos_theta, specular_f0(s.albedo, s.metallic, s.f0), mix(s.f90, 1.0, s.metallic));
}

// The clear coat's Fresnel reflectance (ior 1.5) at cosine `cos_theta`.
fn coat_fresnel(cos_theta: f32) -> f32 {
    return fresnel_schlick(cos_theta, vec3<f32>(0.04)).x;
}

fn light_sample(light: Light, p: vec3<f32>) -> LightSample {
    var s: LightSample;
    if light.kind == LIGHT_DIRECTIONAL {
        s.l = -light.direction;
        s.e = light.radiance;
        s.distance = 3.0e38;
        return s;
    }
    let to_light = light.position - p;
    let d2 = max(dot(to_light, to_light), 1e-8);
    let d = sqrt(d2);
    s.l = to_light / d;
    s.distance = d;
    var falloff = 1.0 / d2;
    if light.range > 0.0 {
        let x = d / light.range;
        let window = clamp(1.0 - x * x * x * x, 0.0, 1.0);
        falloff *= window * window;
    }
    if light.kind == LIGHT_SPOT {
        let scale = 1.0 / max(light.cos_inner - light.cos_outer, 0.001);
        let cone = clamp((dot(light.direction, -s.l) - light.cos_outer) * scale, 0.0, 1.0);
        falloff *= cone * cone;
    }
    s.e = light.radiance * falloff;
    return s;
}

// Outgoing radiance towards `v` from light arriving from `l` with irradiance `e` (normal
// incidence), for a surface with normal n; `f0` and `f90`: its Fresnel reflectance at normal
// incidence and at grazing angles.
fn brdf_light(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, e: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32, f0: vec3<f32>, f90: f32) -> vec3<f32> {
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
    let f = fresnel_schlick_f90(max(dot(h, v), 0.0), f0, f90);
    let specular = d * g * f / (4.0 * n_l * n_v);
    let diffuse = (vec3<f32>(1.0) - f) * (1.0 - metallic) * albedo / PI;
    // Lights are given as irradiance; scale so a white Lambert surface facing a light of
    // intensity 1 reflects 1/pi * pi = 1 (keeps the raster and ray-traced modes comparable).
    return (diffuse + specular) * e * n_l * PI;
}

// Unshadowed radiance towards the viewer from one light with sample `ls`.
fn light_radiance(s: ShadingPoint, ls: LightSample) -> vec3<f32> {
    if all(ls.e == vec3<f32>(0.0)) || s.unlit {
        return vec3<f32>(0.0);
    }
    let f0 = specular_f0(s.albedo, s.metallic, s.f0);
    let base = brdf_light(s.normal, s.view, ls.l, ls.e, s.albedo, s.metallic, s.roughness, f0, mix(s.f90, 1.0, s.metallic));
    if !SCENE_LOBES || s.clearcoat <= 0.0 {
        return base;
    }
    // KHR_materials_clearcoat: the coat's GGX lobe (ior 1.5, no diffuse) over the base, which
    // gets what the coat does not reflect towards the viewer.
    let coat = brdf_light(s.coat_normal, s.view, ls.l, ls.e, vec3<f32>(0.0), 0.0, s.clearcoat_roughness, vec3<f32>(0.04), 1.0);
    return base * (1.0 - s.clearcoat * coat_fresnel(dot(s.coat_normal, s.view))) + s.clearcoat * coat;
}

// Specular reflection of `incoming` radiance arriving along the mirror direction (a
// ray-traced reflection, or `sky_reflection`), weighted by the Fresnel term.
fn reflected_radiance(s: ShadingPoint, incoming: vec3<f32>) -> vec3<f32> {
    if s.unlit {
        return vec3<f32>(0.0);
    }
    let cos_v = dot(s.normal, s.view);
    let base = point_fresnel(s, cos_v) * incoming;
    if !SCENE_LOBES || s.clearcoat <= 0.0 {
        return base;
    }
    // The coat reflects the same incoming light (its own roughness and normal are not traced
    // apart), weighted by its own Fresnel term.
    let coat = s.clearcoat * coat_fresnel(dot(s.coat_normal, s.view));
    return base * (1.0 - coat) + coat * incoming;
}

// What a mirror shows without occluders: the sky along the mirror direction.
fn sky_reflection(s: ShadingPoint) -> vec3<f32> {
    return sky_color(reflect(-s.view, s.normal));
}

// The sky's specular reflection where no reflection ray is traced: the analytic sky along the
// mirror direction times the Fresnel term; an environment map by the split-sum approximation
// (the map prefiltered for the roughness times the lobe's directional albedo; a clear coat's
// own lobe by its roughness over the base's, as `reflected_radiance` weighs them).
fn sky_specular(s: ShadingPoint) -> vec3<f32> {
    if !has_environment() {
        return reflected_radiance(s, sky_reflection(s));
    }
    if s.unlit {
        return vec3<f32>(0.0);
    }
    let n_v = max(dot(s.normal, s.view), 1e-4);
    let ab = environment_brdf_scale_bias(n_v, s.roughness);
    let f0 = specular_f0(s.albedo, s.metallic, s.f0);
    let base = (f0 * ab.x + mix(s.f90, 1.0, s.metallic) * ab.y) * environment_prefiltered(reflect(-s.view, s.normal), s.roughness);
    if !SCENE_LOBES || s.clearcoat <= 0.0 {
        return base;
    }
    let coat_v = max(dot(s.coat_normal, s.view), 1e-4);
    let coat_ab = environment_brdf_scale_bias(coat_v, s.clearcoat_roughness);
    let coat = s.clearcoat * (0.04 * coat_ab.x + coat_ab.y) * environment_prefiltered(reflect(-s.view, s.coat_normal), s.clearcoat_roughness);
    return base * (1.0 - s.clearcoat * coat_fresnel(coat_v)) + coat;
}

// The whole shaded colour: sky ambient (x AO x material occlusion, diffuse part only), the
// direct light the mode summed over the lights with their visibility, and emission.
// An unlit point shows its albedo alone.
fn surface_radiance(s: ShadingPoint, direct: vec3<f32>, ao: f32) -> vec3<f32> {
    if s.unlit {
        return s.albedo;
    }
    // The Lambert term of the sky's light: the environment's irradiance / π, or the analytic
    // sky at the normal (exact for a sky of one colour).
    var sky = frame.ambient * sky_color(s.normal);
    if has_environment() {
        sky = environment_irradiance(s.normal) / PI;
    }
    let ambient = sky * s.albedo * (1.0 - s.metallic) * ao * s.occlusion;
    return ambient + direct + s.emissive;
}
