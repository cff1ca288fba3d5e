// The hit a visibility buffer stands for (visibility/visibility.wgsl: the instance and triangle
// the rasterizer kept at a pixel), rebuilt from the pixel's camera ray, for shading it as a
// traced hit is shaded (common/surface.wgsl). Needs the main shader to declare `frame`,
// `scene_instances`, `scene_meshes`, `scene_indices`, `scene_vertices` and to include
// common/frame.wgsl, common/scene.wgsl and common/surface.wgsl.
//#include "common/ray.wgsl"
//#include "common/camera.wgsl"
//#include "common/visibility_buffer.wgsl"

// Where `ray` meets the plane of the triangle `seen` names (world space), as a hit: its
// distance, barycentrics (outside [0, 1] only by rounding at the triangle's edges) and the side
// the rasterizer saw, as a traced hit's `front_face` (counter-clockwise in object space).
fn visible_hit(ray: Ray, seen: Visible) -> Hit {
    let instance = seen.instance;
    let primitive = seen.primitive;
    let inst = scene_instances[instance];
    let mesh = scene_meshes[inst.mesh];
    let first = mesh.first_index + 3u * primitive;
    let a = scene_vertex(mesh.base_vertex + scene_indices[first]);
    let b = scene_vertex(mesh.base_vertex + scene_indices[first + 1u]);
    let c = scene_vertex(mesh.base_vertex + scene_indices[first + 2u]);
    let pa = (inst.model * vec4<f32>(a.px, a.py, a.pz, 1.0)).xyz;
    let e1 = (inst.model * vec4<f32>(b.px - a.px, b.py - a.py, b.pz - a.pz, 0.0)).xyz;
    let e2 = (inst.model * vec4<f32>(c.px - a.px, c.py - a.py, c.pz - a.pz, 0.0)).xyz;
    let n = cross(e1, e2);
    let facing = dot(ray.dir, n);
    var hit: Hit;
    hit.instance = instance;
    hit.primitive = primitive;
    hit.t = select(dot(pa - ray.origin, n) / facing, 0.0, facing == 0.0);
    // The hit point in the triangle's edge basis (least squares: exact on the plane).
    let q = ray.origin + ray.dir * hit.t - pa;
    let d11 = dot(e1, e1);
    let d12 = dot(e1, e2);
    let d22 = dot(e2, e2);
    let det = d11 * d22 - d12 * d12;
    let q1 = dot(q, e1);
    let q2 = dot(q, e2);
    hit.bary = select(vec2<f32>(d22 * q1 - d12 * q2, d11 * q2 - d12 * q1) / det, vec2<f32>(1.0 / 3.0), det == 0.0);
    hit.front_face = seen.front_face;
    return hit;
}


// The surface pixel `p` shows, where the visibility buffer says it shows one (`seen.drawn`):
// the camera ray through its centre, met on the triangle `seen` names, read at the pixel's ray
// cone as primary rays read their hits.
fn visible_surface(p: vec2<u32>, seen: Visible) -> Surface {
    let ray = Ray(camera_origin(p), 0.0, camera_dir(p), 3.0e38);
    let hit = visible_hit(ray, seen);
    return surface_at_cone(ray, hit, camera_cone_width(p, hit.t));
}
