// Forward shading of the scene's meshes: textured Lambert under one directional light plus
// a hemisphere ambient term. Writes linear HDR colour; alpha 1 marks geometry.
//
// The directional light's direct term is multiplied by a shadow-map visibility (the
// `shadow_map` layer's depth, drawn through `frame.light_view_proj`):
// - the receiver point is moved along its geometric normal by `normal_offset` shadow-map
//   texels (world offset = normal_offset x the world size of one texel, derived from the
//   map's resolution and the light projection, so it follows the scene's size);
// - receiver-plane depth bias: the depth the receiver's own plane would have at each PCF tap
//   comes from screen-space derivatives of its shadow-map coordinates, so wide kernels do not
//   self-shadow tilted surfaces;
// - `shadow_bias` (shadow-map depth units, 0 = the light's near plane .. 1 = its far plane)
//   is subtracted from the receiver depth before each comparison;
// - `pcf` is the filter radius in texels: (2 pcf + 1)^2 `textureLoad` comparisons, averaged
//   (0 = one hard comparison);
// - `shadows` off: fully lit, the shadow map is not read.
//#include "common/frame.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/alpha.wgsl"

struct Params {
    shadow_bias: f32,
    normal_offset: f32,
    shadows: u32,
    pcf: i32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(5) var<uniform> params: Params;
@group(0) @binding(6) var shadow_map: texture_depth_2d;

// Largest receiver depth slope (shadow-map depth per texel) the plane bias extrapolates with:
// surfaces almost parallel to the light get no more (their direct term is ~0 anyway).
const MAX_DEPTH_SLOPE: f32 = 0.01;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) @interpolate(flat) instance: u32,
    @location(3) world_pos: vec3<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) instance: u32,
) -> VertexOut {
    let inst = scene_instances[instance];
    let world = inst.model * vec4<f32>(position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_normal = (inst.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    out.world_pos = world.xyz;
    return out;
}

// World size of one shadow-map texel: the light projection maps 2 NDC units onto the map's
// width; the length of its first row is NDC units per world unit.
fn shadow_texel_world(size: vec2<u32>) -> f32 {
    let m = frame.light_view_proj;
    let ndc_per_world = length(vec3<f32>(m[0].x, m[1].x, m[2].x));
    return 2.0 / (ndc_per_world * f32(size.x));
}

// Shadow-map coordinates of a world point: xy in texels, z depth (0..1).
fn shadow_coord(p: vec3<f32>, size: vec2<u32>) -> vec3<f32> {
    let c = frame.light_view_proj * vec4<f32>(p, 1.0);
    let ndc = c.xyz / c.w;
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    return vec3<f32>(uv * vec2<f32>(size), ndc.z);
}

// Fraction of the PCF taps that see the light, at shadow coordinates `sc` with receiver
// depth slope `slope` (depth per texel in x and y).
fn shadow_visibility(sc: vec3<f32>, slope: vec2<f32>, size: vec2<u32>) -> f32 {
    let isize = vec2<i32>(size);
    if sc.z >= 1.0 || any(sc.xy < vec2<f32>(0.0)) || any(sc.xy >= vec2<f32>(size)) {
        return 1.0;
    }
    let base = vec2<i32>(floor(sc.xy));
    let r = clamp(params.pcf, 0, 4);
    var lit = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let t = clamp(base + vec2<i32>(dx, dy), vec2<i32>(0), isize - vec2<i32>(1));
            // The receiver plane's depth at the tap's centre.
            let receiver = sc.z + dot(slope, vec2<f32>(t) + vec2<f32>(0.5) - sc.xy) - params.shadow_bias;
            lit += select(0.0, 1.0, receiver <= textureLoad(shadow_map, t, 0));
        }
    }
    let taps = f32((2 * r + 1) * (2 * r + 1));
    return lit / taps;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if !material_alpha_visible(scene_instances[in.instance].material, in.uv) {
        discard;
    }
    let material = scene_materials[scene_instances[in.instance].material];
    let tex = sample_scene_texture(material.base_texture, in.uv);
    let albedo = material.base_color.rgb * tex.rgb;
    let n = normalize(in.world_normal);
    let l = frame.light_dir.xyz;

    // Shadow-map coordinates and their screen derivatives, in uniform control flow. The
    // geometric normal (from the interpolated position) decides the offset direction, so
    // smooth shading normals do not push points into neighbouring geometry.
    let size = textureDimensions(shadow_map);
    let dpx = dpdx(in.world_pos);
    let dpy = dpdy(in.world_pos);
    var ng = cross(dpy, dpx);
    ng = select(n, normalize(ng) * sign(dot(ng, n)), dot(ng, ng) > 0.0);
    let sc = shadow_coord(in.world_pos + ng * (params.normal_offset * shadow_texel_world(size)), size);
    let dsx = dpdx(sc);
    let dsy = dpdy(sc);

    let ndl = dot(n, l);
    var visibility = 1.0;
    if params.shadows != 0u && ndl > 0.0 {
        // Receiver-plane depth slope: solve [dsx.xy dsy.xy]^T g = (dsx.z, dsy.z).
        let det = dsx.x * dsy.y - dsx.y * dsy.x;
        var slope = vec2<f32>(0.0);
        if abs(det) > 1e-12 {
            slope = vec2<f32>(dsy.y * dsx.z - dsx.y * dsy.z, dsx.x * dsy.z - dsy.x * dsx.z) / det;
            slope = clamp(slope, vec2<f32>(-MAX_DEPTH_SLOPE), vec2<f32>(MAX_DEPTH_SLOPE));
        }
        visibility = shadow_visibility(sc, slope, size);
    }

    let direct = max(ndl, 0.0) * visibility * frame.light_dir.w * frame.light_color.rgb;
    let sky = mix(vec3<f32>(0.35, 0.3, 0.25), vec3<f32>(0.6, 0.75, 1.0), 0.5 + 0.5 * n.y);
    let ambient = frame.light_color.a * sky;
    return vec4<f32>(albedo * (direct + ambient), 1.0);
}
