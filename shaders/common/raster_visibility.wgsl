// Which rasterized fragments of the scene are kept, the same visibility the rays have: texels
// the alpha test cuts are discarded (common/alpha.wgsl). Back faces of single-sided materials
// (glTF doubleSided false) never reach the fragment stage: the executor culls them in the
// rasterizer (`cull_back_faces`, src/runtime/raster.rs). Also the surface inputs a kept fragment
// shades with, read alike by the G-buffer (deferred/deferred.wgsl) and forward shading
// (forward/forward.wgsl).
// Needs common/scene.wgsl and `scene_materials`, like common/alpha.wgsl, and
// common/scene_textures.wgsl.
//#include "common/material_inputs.wgsl"
//#include "common/alpha.wgsl"
//#include "common/texture_sampling.wgsl"

// `pixel`: the fragment's position (BLEND materials are drawn screen-door).
fn raster_fragment_kept(inst: Instance, uv: vec2<f32>, pixel: vec2<f32>) -> bool {
    return material_alpha_visible(inst.material, uv, pixel);
}

// The material and geometry of a kept fragment. Normals face the viewer.
struct RasterSurface {
    // Shading normal (normal-mapped) and geometric (face) normal, world space.
    normal: vec3<f32>,
    geo_normal: vec3<f32>,
    // World-space screen differentials of the position (the shadow maps' receiver plane).
    dp1: vec3<f32>,
    dp2: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
    occlusion: f32,
    // KHR_materials_unlit: shows `albedo` alone.
    unlit: bool,
}

// Surface inputs of a fragment of instance `inst` at object-space position `local`, with
// texture coordinates `uv` and interpolated world-space vertex normal `vertex_normal`. Takes
// derivatives: call in uniform control flow (before any non-uniform branch).
fn raster_surface(inst: Instance, front_facing: bool, local: vec3<f32>, uv: vec2<f32>, vertex_normal: vec3<f32>) -> RasterSurface {
    let material = scene_materials[inst.material];
    // Object-space derivatives, transformed, keep their precision far from the origin.
    let dp1 = (inst.model * vec4<f32>(dpdx(local), 0.0)).xyz;
    let dp2 = (inst.model * vec4<f32>(dpdy(local), 0.0)).xyz;
    let duv1 = dpdx(uv);
    let duv2 = dpdy(uv);
    let face = cross(dpdx(local), dpdy(local));
    // Every slot's own sampler and uv transform, with the uv's screen-space gradients.
    let base = sample_material_grad(inst.material, SLOT_BASE, material.base_texture, uv, duv1, duv2);
    let mr = sample_material_grad(inst.material, SLOT_METALLIC_ROUGHNESS, material.metallic_roughness_texture, uv, duv1, duv2);
    let emission = sample_material_grad(inst.material, SLOT_EMISSIVE, material.emissive_texture, uv, duv1, duv2).rgb;
    let occlusion = sample_material_grad(inst.material, SLOT_OCCLUSION, material.occlusion_texture, uv, duv1, duv2).r;
    let map = sample_material_grad(inst.material, SLOT_NORMAL, material.normal_texture, uv, duv1, duv2).rgb;
    // The normal map bends the front side's normal; a back face (double-sided) reverses the
    // result. The face normal is oriented by the viewer-side vertex normal, not by a test
    // against positions (which lose precision far from the origin) nor by the sign of the
    // derivatives (which flips in quads that straddle the horizon).
    var n = normalize(vertex_normal);
    if material.normal_texture != 0u {
        n = apply_normal_map(n, dp1, dp2, slot_uv_delta(inst.material, SLOT_NORMAL, duv1), slot_uv_delta(inst.material, SLOT_NORMAL, duv2), map, material.normal_scale);
    }
    let side = select(-1.0, 1.0, raster_front_face(front_facing, inst.model));
    var geo = normalize((inst.normal_matrix * vec4<f32>(face, 0.0)).xyz);
    if dot(geo, normalize(vertex_normal) * side) < 0.0 {
        geo = -geo;
    }
    var s: RasterSurface;
    s.normal = n * side;
    s.geo_normal = geo;
    s.dp1 = dp1;
    s.dp2 = dp2;
    s.albedo = material.base_color.rgb * base.rgb;
    s.metallic = material.metallic * mr.b;
    s.roughness = clamp(material.roughness * mr.g, 0.02, 1.0);
    s.emissive = material.emissive * emission;
    s.occlusion = material_occlusion(occlusion, material.occlusion_strength);
    s.unlit = (material.flags & MATERIAL_UNLIT) != 0u;
    return s;
}
