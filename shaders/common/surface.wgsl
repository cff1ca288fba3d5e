// Shading data at a ray hit: interpolated position, normals and uv from the scene's vertex and
// index buffers, and the material's textures at the mip level of the ray cone's footprint
// (`surface_at_cone`, Akenine-Möller et al., "Texture Level of Detail Strategies for Real-Time
// Ray Tracing", Ray Tracing Gems ch. 20; width 0 samples level 0): compute shaders have no
// derivatives.
// Needs the main shader to declare `scene_instances`, `scene_materials`, `scene_meshes`,
// `scene_indices`, `scene_vertices`, `scene_textures`, `linear_sampler`, and to include
// common/scene.wgsl, common/scene_textures.wgsl and trace/trace.wgsl.

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
    var geo = normalize((inst.normal_matrix * vec4<f32>(cross(pb - pa, pc - pa), 0.0)).xyz);
    if dot(geo, ray.dir) > 0.0 {
        geo = -geo;
    }
    var n = normalize((inst.normal_matrix * vec4<f32>(n_obj, 0.0)).xyz);
    if dot(n, geo) < 0.0 {
        n = -n;
    }
    let material = scene_materials[inst.material];
    // Mip level in uv units: half the log2 of uv area over world area, plus log2 of the cone's
    // footprint across the surface; each texture adds log2 of its size.
    var lod_uv = -1.0e9;
    if cone_width > 0.0 {
        let world_area = length(cross((inst.model * vec4<f32>(pb - pa, 0.0)).xyz, (inst.model * vec4<f32>(pc - pa, 0.0)).xyz));
        let ea = vec2<f32>(b.u, b.v) - vec2<f32>(a.u, a.v);
        let eb = vec2<f32>(c.u, c.v) - vec2<f32>(a.u, a.v);
        let uv_area = abs(ea.x * eb.y - ea.y * eb.x);
        let cosine = abs(dot(geo, normalize(ray.dir)));
        if world_area > 0.0 && uv_area > 0.0 && cosine > 0.0 {
            lod_uv = 0.5 * log2(uv_area / world_area) + log2(cone_width / cosine);
        }
    }
    let lod = vec3<f32>(
        max(lod_uv + scene_texture_log2_size(material.base_texture), 0.0),
        max(lod_uv + scene_texture_log2_size(material.metallic_roughness_texture), 0.0),
        max(lod_uv + scene_texture_log2_size(material.emissive_texture), 0.0),
    );
    let base = sample_scene_texture_level(material.base_texture, uv, lod.x);
    let mr = sample_scene_texture_level(material.metallic_roughness_texture, uv, lod.y);
    let emissive = material.emissive * sample_scene_texture_level(material.emissive_texture, uv, lod.z).rgb;
    var s: Surface;
    s.position = (inst.model * vec4<f32>(local, 1.0)).xyz;
    s.normal = n;
    s.geo_normal = geo;
    s.albedo = material.base_color.rgb * base.rgb;
    s.metallic = material.metallic * mr.b;
    s.roughness = clamp(material.roughness * mr.g, 0.02, 1.0);
    s.emissive = emissive;
    return s;
}
