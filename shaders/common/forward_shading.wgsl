// Forward shading of a surface point (`forward_radiance`), in the fragment stage
// (forward/forward.wgsl) and in a compute pass over the visibility buffer (forward/shade.wgsl):
// the shading model of every mode (common/lighting.wgsl: every light of `scene_lights`, sky
// ambient x material occlusion, the sky's specular reflection, emission).
// A light with a shadow slot (`Light::shadow_map`: the first four directional or spot lights,
// a layer of `shadow_map` each, and the two most powerful point lights, a layer of
// `shadow_cube` each, a cube map's six faces in tiles three a row) is seen through the
// `shadow_map` layer's depth textures, drawn through `frame.shadow_view_proj[slot]`:
// - the receiver point is moved along its geometric normal by `normal_offset` shadow-map
//   texels (world offset = normal_offset x the world size of one texel at the receiver,
//   derived from the map's resolution and the light projection, so it follows the scene's size);
// - receiver-plane depth bias: the depth the receiver's own plane would have at each PCF tap
//   comes from the screen-space derivatives of the world position carried through the light's
//   projection, so wide kernels do not self-shadow tilted surfaces;
// - `shadow_bias` (a fraction of the light's depth range: for the orthographic map of a
//   directional light, shadow-map depth units, 0 = near plane .. 1 = far plane) moves the
//   receiver towards the light before each comparison;
// - `pcf` is the filter radius in texels: (2 pcf + 1)^2 `textureLoad` comparisons, averaged
//   (0 = one hard comparison);
// - `shadows` off: fully lit, the shadow maps are not read.
// Needs the main shader to declare `frame`, `params: Params` (the `forward` layer's parameters),
// `shadow_map` and `shadow_cube` (texture_depth_2d_array), `scene_lights`, and to include
// common/lighting.wgsl.

// The `forward` layer's parameters (layers/forward.ron).
struct Params {
    shadow_bias: f32,
    normal_offset: f32,
    shadows: u32,
    pcf: i32,
}

// Largest receiver depth slope (shadow-map depth per texel) the plane bias extrapolates with:
// surfaces almost parallel to the light get no more (their direct term is ~0 anyway).
const MAX_DEPTH_SLOPE: f32 = 0.01;

// Shadow-map coordinates (xy texels, z depth 0..1) of the clip-space point c, and their
// differential for the clip-space differential dc.
fn shadow_coord(c: vec4<f32>, size: vec2<f32>) -> vec3<f32> {
    let ndc = c.xyz / c.w;
    return vec3<f32>((ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5)) * size, ndc.z);
}

fn shadow_coord_delta(c: vec4<f32>, dc: vec4<f32>, size: vec2<f32>) -> vec3<f32> {
    let d = (dc.xyz - c.xyz / c.w * dc.w) / c.w;
    return vec3<f32>(d.xy * vec2<f32>(0.5, -0.5) * size, d.z);
}

// Fraction of the PCF taps of the `size` texels from `origin` of layer `layer` of shadow
// texture `map` (a slot's map or tile) that see the light, at shadow coordinates `sc` (texels of
// the tile) with receiver depth slope `slope` (depth per texel in x and y) and depth bias `bias`.
fn shadow_pcf(map: texture_depth_2d_array, layer: i32, origin: vec2<i32>, sc: vec3<f32>, slope: vec2<f32>, bias: f32, size: vec2<u32>) -> f32 {
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
            let receiver = sc.z + dot(slope, vec2<f32>(t) + vec2<f32>(0.5) - sc.xy) - bias;
            lit += select(0.0, 1.0, receiver <= textureLoad(map, origin + t, layer, 0));
        }
    }
    let taps = f32((2 * r + 1) * (2 * r + 1));
    return lit / taps;
}

// The first shadow slot of the point lights' cube maps (src/uniforms.rs SHADOW_MAP_SLOTS).
const FIRST_CUBE_SLOT: i32 = 4;
// A cube map's faces are tiles of its layer of `shadow_cube`, CUBE_COLUMNS a row
// (layers/shadow_map.ron's `shadow_tiles`).
const CUBE_COLUMNS: u32 = 3u;
const CUBE_ROWS: u32 = 2u;

// The shadow slot of `light` that sees world point p: its map's, or the face of its cube map
// along p's major axis from the light (faces +x, -x, +y, -y, +z, -z; each reaches a little
// past 90 degrees, so filter taps near a face's edge stay in it).
fn shadow_slot_at(light: Light, p: vec3<f32>) -> i32 {
    if light.shadow_map < FIRST_CUBE_SLOT {
        return light.shadow_map;
    }
    let d = p - light.position;
    let a = abs(d);
    var face = select(5, 4, d.z >= 0.0);
    if a.x >= a.y && a.x >= a.z {
        face = select(1, 0, d.x >= 0.0);
    } else if a.y >= a.z {
        face = select(3, 2, d.y >= 0.0);
    }
    return light.shadow_map + face;
}

// Visibility of `light` (which has a shadow slot) at world point p with geometric normal ng
// and screen-space position differentials dpx, dpy.
fn light_visibility(light: Light, p: vec3<f32>, ng: vec3<f32>, dpx: vec3<f32>, dpy: vec3<f32>) -> f32 {
    let cube = light.shadow_map >= FIRST_CUBE_SLOT;
    let size = select(textureDimensions(shadow_map), textureDimensions(shadow_cube) / vec2<u32>(CUBE_COLUMNS, CUBE_ROWS), cube);
    let fsize = vec2<f32>(size);
    // World size of one texel at p: the projection maps 2 NDC units onto the map's width; the
    // length of the matrix's first row is clip units per world unit (divided by w in NDC).
    let m0 = frame.shadow_view_proj[shadow_slot_at(light, p)];
    let c0 = m0 * vec4<f32>(p, 1.0);
    let texel_world = 2.0 * c0.w / (length(vec3<f32>(m0[0].x, m0[1].x, m0[2].x)) * fsize.x);
    let q = p + ng * (params.normal_offset * texel_world);
    // The receiver offset may carry a point near a cube face's edge into the next face.
    let slot = shadow_slot_at(light, q);
    let m = frame.shadow_view_proj[slot];
    let c = m * vec4<f32>(q, 1.0);
    let sc = shadow_coord(c, fsize);
    let dsx = shadow_coord_delta(c, m * vec4<f32>(dpx, 0.0), fsize);
    let dsy = shadow_coord_delta(c, m * vec4<f32>(dpy, 0.0), fsize);
    // Receiver-plane depth slope: solve [dsx.xy dsy.xy]^T g = (dsx.z, dsy.z).
    let det = dsx.x * dsy.y - dsx.y * dsy.x;
    var slope = vec2<f32>(0.0);
    if abs(det) > 1e-12 {
        slope = vec2<f32>(dsy.y * dsx.z - dsx.y * dsy.z, dsx.x * dsy.z - dsy.x * dsx.z) / det;
        slope = clamp(slope, vec2<f32>(-MAX_DEPTH_SLOPE), vec2<f32>(MAX_DEPTH_SLOPE));
    }
    // The bias as a world distance towards the light, carried into depth.
    let towards = light_sample(light, q).l * (params.shadow_bias * light.shadow_depth_range);
    let bias = sc.z - shadow_coord(m * vec4<f32>(q + towards, 1.0), fsize).z;
    if cube {
        let face = u32(slot - light.shadow_map);
        let origin = vec2<i32>(vec2<u32>(face % CUBE_COLUMNS, face / CUBE_COLUMNS) * size);
        return shadow_pcf(shadow_cube, (light.shadow_map - FIRST_CUBE_SLOT) / i32(CUBE_COLUMNS * CUBE_ROWS), origin, sc, slope, bias, size);
    }
    return shadow_pcf(shadow_map, slot, vec2<i32>(0), sc, slope, bias, size);
}


// Radiance towards the viewer from shading point `s` with geometric normal `geo` (the shadow
// offset's direction) and world-space position differentials `dp1`, `dp2` per pixel in x and y
// (the receiver plane).
fn forward_radiance(s: ShadingPoint, geo: vec3<f32>, dp1: vec3<f32>, dp2: vec3<f32>) -> vec3<f32> {
    var direct = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let light = scene_lights[i];
        var radiance = light_radiance(s, light_sample(light, s.position));
        if params.shadows != 0u && light.shadow_map >= 0 && any(radiance > vec3<f32>(0.0)) {
            radiance *= light_visibility(light, s.position, geo, dp1, dp2);
        }
        direct += radiance;
    }
    return surface_radiance(s, direct, 1.0) + sky_specular(s);
}
