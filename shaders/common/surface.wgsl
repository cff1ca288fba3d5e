// Shading data at a ray hit: interpolated position, normals and uv from the scene's vertex and
// index buffers, and the material's textures (level 0: compute shaders have no derivatives).
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

fn surface_at(ray: Ray, hit: Hit) -> Surface {
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
    let base = sample_scene_texture_level(material.base_texture, uv, 0.0);
    let mr = sample_scene_texture_level(material.metallic_roughness_texture, uv, 0.0);
    let emissive = material.emissive * sample_scene_texture_level(material.emissive_texture, uv, 0.0).rgb;
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
