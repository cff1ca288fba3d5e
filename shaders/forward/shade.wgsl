// Forward shading in a compute pass over the visibility buffer (visibility/visibility.wgsl): per
// pixel, the camera ray through the pixel centre (the rasterizer's sample position) meets the
// triangle the rasterizer kept there; the surface at that hit is read as primary rays read it
// (common/surface.wgsl: every material input, textures at the mip level of the pixel's ray
// cone) and shaded as forward/forward.wgsl shades a fragment (common/forward_shading.wgsl), the shadow
// maps' receiver plane from where the neighbouring pixels' rays meet the triangle's plane (the
// rasterizer's screen derivatives, on a flat triangle). Writes linear HDR colour, alpha 1 where
// geometry was drawn and 0 elsewhere, as the fragment-stage pass does, with the translucent
// layer (forward/translucent.wgsl) over it (common/translucent_over.wgsl).
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_bindings.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/lighting.wgsl"
//#include "common/surface.wgsl"
//#include "common/visible_hit.wgsl"
//#include "common/forward_shading.wgsl"
//#include "common/translucent_over.wgsl"

// Bindings 0 to 6: the frame and the scene (common/scene_bindings.wgsl).
@group(0) @binding(7) var<uniform> params: Params;
@group(0) @binding(8) var shadow_map: texture_depth_2d_array;
@group(0) @binding(12) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(13) var visibility: texture_2d<u32>;
@group(0) @binding(14) var color: texture_storage_2d<rgba16float, write>;
@group(0) @binding(15) var translucent: texture_2d<f32>;
@group(0) @binding(16) var translucent_filter: texture_2d<f32>;
@group(0) @binding(17) var shadow_cube: texture_depth_2d_array;

// The world-space offset from `p` to where the camera ray through pixel `q` meets the plane
// through `p` with normal `n` (zero where the ray runs along the plane).
fn plane_offset(q: vec2<u32>, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let eye = camera_origin(q);
    let dir = camera_dir(q);
    let along = dot(dir, n);
    if abs(along) < 1e-8 {
        return vec3<f32>(0.0);
    }
    return eye + dir * (dot(p - eye, n) / along) - p;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(color);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    textureStore(color, id.xy, composite_translucent(id.xy, opaque_color(id.xy)));
}

// The shaded opaque surface the rasterizer kept at pixel `q` (alpha 1), or 0 where none.
fn opaque_color(q: vec2<u32>) -> vec4<f32> {
    let seen = visible_decode(textureLoad(visibility, q, 0).xy);
    if !seen.drawn {
        return vec4<f32>(0.0);
    }
    let surface = visible_surface(q, seen);
    var s: ShadingPoint;
    s.position = surface.position;
    s.normal = surface.normal;
    s.view = camera_view_dir(surface.position);
    s.albedo = surface.albedo;
    s.metallic = surface.metallic;
    s.roughness = surface.roughness;
    s.occlusion = surface.occlusion;
    s.emissive = surface.emissive;
    s.unlit = surface.unlit;
    shading_lobes(&s, surface.lobes);
    let dp1 = plane_offset(q + vec2<u32>(1u, 0u), s.position, surface.geo_normal);
    let dp2 = plane_offset(q + vec2<u32>(0u, 1u), s.position, surface.geo_normal);
    return vec4<f32>(forward_radiance(s, surface.geo_normal, dp1, dp2), 1.0);
}
