// Shading data at a ray hit: interpolated position, normals and uv from the scene's vertex and
// index buffers, and the material's textures at the mip level of the ray cone's footprint
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
}

fn scene_vertex(i: u32) -> SceneVertex {
    return scene_vertices[i];
}

// `cone_width`: the width of the ray's cone at the hit (0: sample level 0).
fn surface_at_cone(ray: Ray, hit: Hit, cone_width: f32) -> Surface {
    let inst = scene_instances[hit.instance];
    let mesh = scene_meshes[inst.mesh];
    let first = mesh.first_index + 3u * hit.primitive;
    let a = scene_vertex(mesh.base_vertex + scene_indices[first]);
    let b = scene_vertex(mesh.base_vertex + scene_indices[first + 1u]);
    let c = scene_vertex(mesh.base_vertex + scene_indices[first + 2u]);
    let w = vec3<f32>(1.0 - hit.bary.x - hit.bary.y, hit.bary.x, hit.bary.y);
    let pa = vec3<f32>(a.px, a.py, a.pz);
    let pb = vec3<f32>(b.px, b.py, b.pz);
    let pc = vec3<f32>(c.px, c.py, c.pz);
    let local = pa * w.x + pb * w.y + pc * w.z;
    let n_obj = vec3<f32>(a.nx, a.ny, a.nz) * w.x + vec3<f32>(b.nx, b.ny, b.nz) * w.y + vec3<f32>(c.nx, c.ny, c.nz) * w.z;
    let uv = vec2<f32>(a.u, a.v) * w.x + vec2<f32>(b.u, b.v) * w.y + vec2<f32>(c.u, c.v) * w.z;
    let material = scene_materials[inst.material];
    // Mip level in uv units: half the log2 of uv area over world area, plus log2 of the cone's
    // footprint across the surface; each texture adds log2 of its size.
    let geo_front = normalize((inst.normal_matrix * vec4<f32>(cross(pb - pa, pc - pa), 0.0)).xyz);
    let dp1 = (inst.model * vec4<f32>(pb - pa, 0.0)).xyz;
    let dp2 = (inst.model * vec4<f32>(pc - pa, 0.0)).xyz;
    let duv1 = vec2<f32>(b.u, b.v) - vec2<f32>(a.u, a.v);
    let duv2 = vec2<f32>(c.u, c.v) - vec2<f32>(a.u, a.v);
    var lod_uv = -1.0e9;
    if cone_width > 0.0 {
        let world_area = length(cross(dp1, dp2));
        let uv_area = abs(duv1.x * duv2.y - duv1.y * duv2.x);
        let cosine = abs(dot(geo_front, normalize(ray.dir)));
        if world_area > 0.0 && uv_area > 0.0 && cosine > 0.0 {
            lod_uv = 0.5 * log2(uv_area / world_area) + log2(cone_width / cosine);
        }
    }
    // Every slot's own sampler and uv transform (common/texture_sampling.wgsl).
    let base = sample_material_level(material, SLOT_BASE, material.base_texture, uv, lod_uv);
    let mr = sample_material_level(material, SLOT_METALLIC_ROUGHNESS, material.metallic_roughness_texture, uv, lod_uv);
    let emissive = material.emissive * sample_material_level(material, SLOT_EMISSIVE, material.emissive_texture, uv, lod_uv).rgb;
    let occlusion = sample_material_level(material, SLOT_OCCLUSION, material.occlusion_texture, uv, lod_uv).r;
    // The normal map bends the front side's normal; a back face reverses the result. The face
    // normal is oriented by the ray's side of the vertex normal, as the rasterizer orients it.
    let n_front = normalize((inst.normal_matrix * vec4<f32>(n_obj, 0.0)).xyz);
    var n = n_front;
    if material.normal_texture != 0u {
        let map = sample_material_level(material, SLOT_NORMAL, material.normal_texture, uv, lod_uv).rgb;
        n = apply_normal_map(n_front, dp1, dp2, slot_uv_delta(material, SLOT_NORMAL, duv1), slot_uv_delta(material, SLOT_NORMAL, duv2), map, material.normal_scale);
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
    s.albedo = material.base_color.rgb * base.rgb;
    s.metallic = material.metallic * mr.b;
    s.roughness = clamp(material.roughness * mr.g, 0.02, 1.0);
    s.emissive = emissive;
    s.occlusion = material_occlusion(occlusion, material.occlusion_strength);
    s.unlit = (material.flags & MATERIAL_UNLIT) != 0u;
    return s;
}
