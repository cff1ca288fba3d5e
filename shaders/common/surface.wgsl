// Shading data at a ray hit: interpolated position, normals, both uv sets and the vertex colour
// from the scene's vertex and index buffers, and the material's textures at the mip level of the ray cone's footprint
// (`surface_at_cone`, Akenine-Möller et al., "Texture Level of Detail Strategies for Real-Time
// Ray Tracing", Ray Tracing Gems ch. 20; width 0 samples level 0): compute shaders have no
// derivatives.
// Every material input is read as the raster G-buffer (deferred/deferred.wgsl) reads it, through
// common/material_inputs.wgsl: normal maps in the tangent frame of the triangle's edges (the
// rasterizer's derivatives give the same frame), back faces (the ray hit the clockwise side)
// with reversed normals; only the texture level differs (ray cone against derivatives).
// Needs the main shader to declare `scene_instances`, `scene_materials`, `scene_meshes`,
// `scene_indices`, `scene_vertices`, `linear_sampler`, and to include
// common/scene.wgsl and common/scene_textures.wgsl.
//#include "common/ray.wgsl"
//#include "common/material_inputs.wgsl"
//#include "common/texture_sampling.wgsl"
//#include "common/surface_lobes.wgsl"

struct Surface {
    position: vec3<f32>,
    // Shading normal, world space, on the side the ray came from.
    normal: vec3<f32>,
    // Geometric normal, world space, on the side the ray came from.
    geo_normal: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
    // Material occlusion (occlusion texture and strength; 1 without one).
    occlusion: f32,
    // KHR_materials_unlit: shows `albedo` alone.
    unlit: bool,
    // Its material (scene_materials index).
    material: u32,
    // How far shadow rays leave above the surface along `geo_normal` (world units): the
    // shadow-terminator offset of a smooth-shaded triangle (common/material_inputs.wgsl), 0 on
    // a flat one.
    shadow_offset: f32,
    // The specular lobes (glTF's core material's, or the material's own with its textures).
    lobes: SurfaceLobes,
}

fn scene_vertex(i: u32) -> SceneVertex {
    return scene_vertices[i];
}

// A hit's two texture coordinate sets (TEXCOORD_0, and TEXCOORD_1 where the mesh has it, else
// the first set): each interpolated, its differentials along the triangle's edges (b - a, c - a), and the
// log2 of the ray cone's footprint in its units (-1e9: level 0).
struct HitTexCoords {
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    duv1_0: vec2<f32>,
    duv2_0: vec2<f32>,
    duv1_1: vec2<f32>,
    duv2_1: vec2<f32>,
    lod0: f32,
    lod1: f32,
    // The vertex colour (COLOR_0; exactly white without one).
    color: vec4<f32>,
}

// log2 of the footprint in uv units of a cone `cone_width` wide meeting a triangle of world area
// `world_area` at `cosine`, for uv edges `duv1`, `duv2`: half the log2 of uv area over world
// area, plus log2 of the cone's footprint across the surface (-1e9: level 0).
fn cone_footprint_log2(duv1: vec2<f32>, duv2: vec2<f32>, world_area: f32, cone_width: f32, cosine: f32) -> f32 {
    let uv_area = abs(duv1.x * duv2.y - duv1.y * duv2.x);
    if cone_width > 0.0 && world_area > 0.0 && uv_area > 0.0 && cosine > 0.0 {
        return 0.5 * log2(uv_area / world_area) + log2(cone_width / cosine);
    }
    return -1.0e9;
}

// Slot `slot` of material `m` (its texture `layer`) in the uv set the slot reads.
fn hit_slot_texture(m: u32, slot: u32, layer: u32, uvs: vec4<f32>, lods: vec2<f32>) -> vec4<f32> {
    let one = slot_uv_set(m, slot) == 1u;
    return sample_material_level(m, slot, layer, select(uvs.xy, uvs.zw, one), select(lods.x, lods.y, one));
}

// The uv edges of the set slot `slot` reads, through its transform's linear part.
fn hit_slot_uv_edges(m: u32, slot: u32, t: HitTexCoords) -> array<vec2<f32>, 2> {
    let one = slot_uv_set(m, slot) == 1u;
    return array<vec2<f32>, 2>(slot_uv_delta(m, slot, select(t.duv1_0, t.duv1_1, one)), slot_uv_delta(m, slot, select(t.duv2_0, t.duv2_1, one)));
}

// The texture coordinates and vertex colour of a hit at barycentric weights `w` on the triangle
// of mesh-local vertex indices `corners` (vertices `a`, `b`, `c`), for a cone `cone_width`
// wide meeting the triangle (world area `world_area`) at `cosine`.
fn hit_tex_coords(mesh: MeshRecord, corners: vec3<u32>, a: SceneVertex, b: SceneVertex, c: SceneVertex, w: vec3<f32>, world_area: f32, cone_width: f32, cosine: f32) -> HitTexCoords {
    var t: HitTexCoords;
    t.uv0 = vec2<f32>(a.u, a.v) * w.x + vec2<f32>(b.u, b.v) * w.y + vec2<f32>(c.u, c.v) * w.z;
    t.duv1_0 = vec2<f32>(b.u, b.v) - vec2<f32>(a.u, a.v);
    t.duv2_0 = vec2<f32>(c.u, c.v) - vec2<f32>(a.u, a.v);
    t.lod0 = cone_footprint_log2(t.duv1_0, t.duv2_0, world_area, cone_width, cosine);
    // Without extras (no COLOR_0, no TEXCOORD_1) the colour is exactly white and the second set
    // is the first; nothing more is read.
    t.uv1 = t.uv0;
    t.duv1_1 = t.duv1_0;
    t.duv2_1 = t.duv2_0;
    t.lod1 = t.lod0;
    t.color = vec4<f32>(1.0);
    if SCENE_VERTEX_EXTRAS && mesh.extras != MESH_NO_EXTRAS {
        let xa = scene_vertex(mesh.extras + corners.x);
        let xb = scene_vertex(mesh.extras + corners.y);
        let xc = scene_vertex(mesh.extras + corners.z);
        // The vertex colour (COLOR_0) multiplies the base colour.
        t.color = vec4<f32>(xa.pz, xa.nx, xa.ny, xa.nz) * w.x + vec4<f32>(xb.pz, xb.nx, xb.ny, xb.nz) * w.y + vec4<f32>(xc.pz, xc.nx, xc.ny, xc.nz) * w.z;
        t.uv1 = vec2<f32>(xa.px, xa.py) * w.x + vec2<f32>(xb.px, xb.py) * w.y + vec2<f32>(xc.px, xc.py) * w.z;
        t.duv1_1 = vec2<f32>(xb.px, xb.py) - vec2<f32>(xa.px, xa.py);
        t.duv2_1 = vec2<f32>(xc.px, xc.py) - vec2<f32>(xa.px, xa.py);
        // The second set's footprint: the first's, scaled by the ratio of the two sets' uv
        // areas (level 0 where the first set is degenerate). A second cone_footprint_log2 call
        // costs software WebGPU (SwiftShader) over 30 s more to compile the reflection pass.
        let area0 = abs(t.duv1_0.x * t.duv2_0.y - t.duv1_0.y * t.duv2_0.x);
        let area1 = abs(t.duv1_1.x * t.duv2_1.y - t.duv1_1.y * t.duv2_1.x);
        t.lod1 = t.lod0 + 0.5 * log2(max(area1, 1e-30) / max(area0, 1e-30));
    }
    return t;
}

// The lobes of material `m` at a hit (common/surface_lobes.wgsl): its lobe textures in their
// own uv sets, the coat's normal map bending `n_front` (the front side's normal before the
// base's normal map) in the frame of world edges `dp1`, `dp2`; `side`: -1 on a back face.
fn hit_lobes(m: u32, t: HitTexCoords, uvs: vec4<f32>, lods: vec2<f32>, n_front: vec3<f32>, dp1: vec3<f32>, dp2: vec3<f32>, side: f32) -> SurfaceLobes {
    let specular = hit_slot_texture(m, SLOT_SPECULAR, lobe_slot_layer(m, SLOT_SPECULAR), uvs, lods).a;
    let color = hit_slot_texture(m, SLOT_SPECULAR_COLOR, lobe_slot_layer(m, SLOT_SPECULAR_COLOR), uvs, lods).rgb;
    let coat = hit_slot_texture(m, SLOT_CLEARCOAT, lobe_slot_layer(m, SLOT_CLEARCOAT), uvs, lods).r;
    let rough = hit_slot_texture(m, SLOT_CLEARCOAT_ROUGHNESS, lobe_slot_layer(m, SLOT_CLEARCOAT_ROUGHNESS), uvs, lods).g;
    var coat_normal = n_front;
    let normal_layer = lobe_slot_layer(m, SLOT_CLEARCOAT_NORMAL);
    if normal_layer != 0u {
        let map = hit_slot_texture(m, SLOT_CLEARCOAT_NORMAL, normal_layer, uvs, lods).rgb;
        let edges = hit_slot_uv_edges(m, SLOT_CLEARCOAT_NORMAL, t);
        coat_normal = apply_normal_map(n_front, dp1, dp2, edges[0], edges[1], map, scene_materials[m].coat.x);
    }
    return lobes_from_texels(m, specular, color, coat, rough, coat_normal * side);
}

// `cone_width`: the width of the ray's cone at the hit (0: sample level 0).
fn surface_at_cone(ray: Ray, hit: Hit, cone_width: f32) -> Surface {
    let inst = scene_instances[hit.instance];
    let mesh = scene_meshes[inst.mesh];
    let first = mesh.first_index + 3u * hit.primitive;
    let ia = scene_indices[first];
    let ib = scene_indices[first + 1u];
    let ic = scene_indices[first + 2u];
    let a = scene_vertex(mesh.base_vertex + ia);
    let b = scene_vertex(mesh.base_vertex + ib);
    let c = scene_vertex(mesh.base_vertex + ic);
    let w = vec3<f32>(1.0 - hit.bary.x - hit.bary.y, hit.bary.x, hit.bary.y);
    let pa = vec3<f32>(a.px, a.py, a.pz);
    let pb = vec3<f32>(b.px, b.py, b.pz);
    let pc = vec3<f32>(c.px, c.py, c.pz);
    let local = pa * w.x + pb * w.y + pc * w.z;
    let n_obj = vec3<f32>(a.nx, a.ny, a.nz) * w.x + vec3<f32>(b.nx, b.ny, b.nz) * w.y + vec3<f32>(c.nx, c.ny, c.nz) * w.z;
    let material = &scene_materials[inst.material];
    let geo_front = normalize((inst.normal_matrix * vec4<f32>(cross(pb - pa, pc - pa), 0.0)).xyz);
    let dp1 = (inst.model * vec4<f32>(pb - pa, 0.0)).xyz;
    let dp2 = (inst.model * vec4<f32>(pc - pa, 0.0)).xyz;
    let world_area = length(cross(dp1, dp2));
    let cosine = abs(dot(geo_front, normalize(ray.dir)));
    let t = hit_tex_coords(mesh, vec3<u32>(ia, ib, ic), a, b, c, w, world_area, cone_width, cosine);
    let uvs = vec4<f32>(t.uv0, t.uv1);
    let lods = vec2<f32>(t.lod0, t.lod1);
    // Every slot's own uv set, sampler and uv transform (common/texture_sampling.wgsl).
    let base = hit_slot_texture(inst.material, SLOT_BASE, material.base_texture, uvs, lods);
    let mr = hit_slot_texture(inst.material, SLOT_METALLIC_ROUGHNESS, material.metallic_roughness_texture, uvs, lods);
    let emissive = material.emissive * hit_slot_texture(inst.material, SLOT_EMISSIVE, material.emissive_texture, uvs, lods).rgb;
    let occlusion = hit_slot_texture(inst.material, SLOT_OCCLUSION, material.occlusion_texture, uvs, lods).r;
    // The normal map bends the front side's normal; a back face reverses the result. The face
    // normal is oriented by the ray's side of the vertex normal, as the rasterizer orients it.
    let n_front = normalize((inst.normal_matrix * vec4<f32>(n_obj, 0.0)).xyz);
    var n = n_front;
    if material.normal_texture != 0u {
        let map = hit_slot_texture(inst.material, SLOT_NORMAL, material.normal_texture, uvs, lods).rgb;
        let edges = hit_slot_uv_edges(inst.material, SLOT_NORMAL, t);
        n = apply_normal_map(n_front, dp1, dp2, edges[0], edges[1], map, material.normal_scale);
    }
    let side = select(-1.0, 1.0, hit.front_face);
    n = n * side;
    var geo = geo_front;
    if dot(geo, n_front * side) < 0.0 {
        geo = -geo;
    }
    var s: Surface;
    s.position = (inst.model * vec4<f32>(local, 1.0)).xyz;
    s.normal = n;
    s.geo_normal = geo;
    s.albedo = material.base_color.rgb * base.rgb * t.color.rgb;
    s.metallic = material.metallic * mr.b;
    s.roughness = clamp(material.roughness * mr.g, 0.02, 1.0);
    s.emissive = emissive;
    s.occlusion = material_occlusion(occlusion, material.occlusion_strength);
    s.unlit = SCENE_UNLIT && (material.flags & MATERIAL_UNLIT) != 0u;
    s.material = inst.material;
    let na = normalize(vec3<f32>(a.nx, a.ny, a.nz)) * side;
    let nb = normalize(vec3<f32>(b.nx, b.ny, b.nz)) * side;
    let nc = normalize(vec3<f32>(c.nx, c.ny, c.nz)) * side;
    let lift = (inst.model * vec4<f32>(terminator_offset(local, pa, pb, pc, na, nb, nc, w), 0.0)).xyz;
    s.shadow_offset = max(dot(lift, geo), 0.0);
    s.lobes = core_lobes(n_front * side);
    if material_has_lobes(inst.material) {
        s.lobes = hit_lobes(inst.material, t, uvs, lods, n_front, dp1, dp2, side);
    }
    return s;
}
