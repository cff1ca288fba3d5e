// Which rasterized fragments of the scene are kept, the same visibility the rays have: texels
// the alpha test cuts are discarded (common/raster_alpha_test.wgsl). Back faces of single-sided
// materials (glTF doubleSided false) never reach the fragment stage: the executor culls them in
// the rasterizer (`cull_back_faces`, src/runtime/raster.rs). Also the surface inputs a kept
// fragment shades with, read alike by the G-buffer (deferred/deferred.wgsl) and forward shading
// (forward/forward.wgsl), through common/scene_fragment.wgsl.
// Needs common/scene.wgsl and `scene_materials`, like common/raster_alpha_test.wgsl, and
// common/scene_textures.wgsl.
//#include "common/material_inputs.wgsl"
//#include "common/raster_alpha_test.wgsl"
//#include "common/texture_sampling.wgsl"
//#include "common/surface_lobes.wgsl"

// `pixel`: the fragment's position (BLEND materials are drawn screen-door); `vertex_alpha`: the
// interpolated vertex colours' alpha (COLOR_0; 1 without).
fn raster_fragment_kept(inst: Instance, uv: vec2<f32>, pixel: vec2<f32>, vertex_alpha: f32) -> bool {
    return material_alpha_visible(inst.material, uv, pixel, vertex_alpha);
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
    // The specular lobes (glTF's core material's, or the material's own with its textures).
    lobes: SurfaceLobes,
}

// The lobes of material `m` at a fragment (common/surface_lobes.wgsl): its lobe textures in
// their own uv sets, the coat's normal map bending `n` (the viewer-side normal before the
// base's normal map) in the frame of world differentials `dp1`, `dp2`.
fn raster_lobes(m: u32, set0: mat3x2<f32>, set1: mat3x2<f32>, n: vec3<f32>, dp1: vec3<f32>, dp2: vec3<f32>) -> SurfaceLobes {
    let specular = raster_slot(m, SLOT_SPECULAR, lobe_slot_layer(m, SLOT_SPECULAR), set0, set1).a;
    let color = raster_slot(m, SLOT_SPECULAR_COLOR, lobe_slot_layer(m, SLOT_SPECULAR_COLOR), set0, set1).rgb;
    let coat = raster_slot(m, SLOT_CLEARCOAT, lobe_slot_layer(m, SLOT_CLEARCOAT), set0, set1).r;
    let rough = raster_slot(m, SLOT_CLEARCOAT_ROUGHNESS, lobe_slot_layer(m, SLOT_CLEARCOAT_ROUGHNESS), set0, set1).g;
    var coat_normal = n;
    let normal_layer = lobe_slot_layer(m, SLOT_CLEARCOAT_NORMAL);
    if normal_layer != 0u {
        let map = raster_slot(m, SLOT_CLEARCOAT_NORMAL, normal_layer, set0, set1).rgb;
        var coat_set = set0;
        if slot_uv_set(m, SLOT_CLEARCOAT_NORMAL) == 1u {
            coat_set = set1;
        }
        let duv1 = slot_uv_delta(m, SLOT_CLEARCOAT_NORMAL, coat_set[1]);
        let duv2 = slot_uv_delta(m, SLOT_CLEARCOAT_NORMAL, coat_set[2]);
        coat_normal = apply_normal_map(n, dp1, dp2, duv1, duv2, map, scene_materials[m].coat.x);
    }
    return lobes_from_texels(m, specular, color, coat, rough, coat_normal);
}

// A slot's texture of a fragment: its own uv set (`uv` and its gradients for set 0, `uv1` for
// set 1), sampler and uv transform.
fn raster_slot(m: u32, slot: u32, layer: u32, uv: mat3x2<f32>, uv1: mat3x2<f32>) -> vec4<f32> {
    var coords = uv;
    if slot_uv_set(m, slot) == 1u {
        coords = uv1;
    }
    return sample_material_grad(m, slot, layer, coords[0], coords[1], coords[2]);
}

// Surface inputs of a fragment of instance `inst` at object-space position `local`, with
// texture coordinates `uv` (TEXCOORD_0) and `uv1` (TEXCOORD_1, or `uv` without one), vertex
// colour `color` (COLOR_0, times the base colour) and interpolated world-space vertex normal
// `vertex_normal`. Takes derivatives: call in uniform control flow (before any non-uniform
// branch).
fn raster_surface(inst: Instance, front_facing: bool, local: vec3<f32>, uv: vec2<f32>, uv1: vec2<f32>, color: vec4<f32>, vertex_normal: vec3<f32>) -> RasterSurface {
    let material = &scene_materials[inst.material];
    // Object-space derivatives, transformed, keep their precision far from the origin.
    let dp1 = (inst.model * vec4<f32>(dpdx(local), 0.0)).xyz;
    let dp2 = (inst.model * vec4<f32>(dpdy(local), 0.0)).xyz;
    let set0 = mat3x2<f32>(uv, dpdx(uv), dpdy(uv));
    let set1 = mat3x2<f32>(uv1, dpdx(uv1), dpdy(uv1));
    let face = cross(dpdx(local), dpdy(local));
    // Every slot's own uv set, sampler and uv transform, with its screen-space gradients.
    let m = inst.material;
    let base = raster_slot(m, SLOT_BASE, material.base_texture, set0, set1);
    let mr = raster_slot(m, SLOT_METALLIC_ROUGHNESS, material.metallic_roughness_texture, set0, set1);
    let emission = raster_slot(m, SLOT_EMISSIVE, material.emissive_texture, set0, set1).rgb;
    let occlusion = raster_slot(m, SLOT_OCCLUSION, material.occlusion_texture, set0, set1).r;
    let map = raster_slot(m, SLOT_NORMAL, material.normal_texture, set0, set1).rgb;
    var normal_set = set0;
    if slot_uv_set(m, SLOT_NORMAL) == 1u {
        normal_set = set1;
    }
    // The normal map bends the front side's normal; a back face (double-sided) reverses the
    // result. The face normal is oriented by the viewer-side vertex normal, not by a test
    // against positions (which lose precision far from the origin) nor by the sign of the
    // derivatives (which flips in quads that straddle the horizon).
    var n = normalize(vertex_normal);
    if material.normal_texture != 0u {
        n = apply_normal_map(n, dp1, dp2, slot_uv_delta(m, SLOT_NORMAL, normal_set[1]), slot_uv_delta(m, SLOT_NORMAL, normal_set[2]), map, material.normal_scale);
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
    s.albedo = material.base_color.rgb * base.rgb * color.rgb;
    s.metallic = material.metallic * mr.b;
    s.roughness = clamp(material.roughness * mr.g, 0.02, 1.0);
    s.emissive = material.emissive * emission;
    s.occlusion = material_occlusion(occlusion, material.occlusion_strength);
    s.unlit = SCENE_UNLIT && (material.flags & MATERIAL_UNLIT) != 0u;
    s.lobes = core_lobes(normalize(vertex_normal) * side);
    if material_has_lobes(m) {
        // The coat's normal map bends the front side's normal, as the base's does.
        var lobes = raster_lobes(m, set0, set1, normalize(vertex_normal), dp1, dp2);
        lobes.coat_normal *= side;
        s.lobes = lobes;
    }
    return s;
}
