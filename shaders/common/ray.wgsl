// A ray and the hit the trace interface returns (trace/common.wgsl), also what shading code
// reads at a hit found another way (the visibility buffer of forward/shade.wgsl).

struct Ray {
    origin: vec3<f32>,
    t_min: f32,
    dir: vec3<f32>,
    t_max: f32,
}

struct Hit {
    t: f32,
    // Index of the instance in the scene (Scene::instances), or NO_HIT.
    instance: u32,
    // Triangle index within the instance's mesh.
    primitive: u32,
    // Barycentric weights of the triangle's second and third vertices.
    bary: vec2<f32>,
    // Counter-clockwise seen from the ray origin (in object space).
    front_face: bool,
}

const NO_HIT: u32 = 0xffffffffu;
