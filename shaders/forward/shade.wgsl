// Forward shading in a compute pass over the visibility buffer (forward/visibility.wgsl): per
// pixel, the camera ray through the pixel centre (the rasterizer's sample position) meets the
// triangle the rasterizer kept there; the surface at that hit is read as primary rays read it
// (common/surface.wgsl: every material input, textures at the mip level of the pixel's ray
// cone) and shaded as forward/forward.wgsl shades a fragment (common/forward_shading.wgsl), the shadow
// maps' receiver plane from where the neighbouring pixels' rays meet the triangle's plane (the
// rasterizer's screen derivatives, on a flat triangle). Writes linear HDR colour, alpha 1 where
// geometry was drawn and 0 elsewhere, as the fragment-stage pass does.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/lighting.wgsl"
//#include "common/surface.wgsl"
//#include "common/forward_shading.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(2) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(3) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(4) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(5) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(6) var linear_sampler: sampler;
@group(0) @binding(7) var<uniform> params: Params;
@group(0) @binding(8) var shadow_map: texture_depth_2d;
@group(0) @binding(9) var shadow_map_1: texture_depth_2d;
@group(0) @binding(10) var shadow_map_2: texture_depth_2d;
@group(0) @binding(11) var shadow_map_3: texture_depth_2d;
@group(0) @binding(12) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(13) var visibility: texture_2d<u32>;
@group(0) @binding(14) var color: texture_storage_2d<rgba16float, write>;

// Where `ray` meets the plane of triangle `primitive` of instance `instance` (world space), as
// a hit: its distance, barycentrics (outside [0, 1] only by rounding at the triangle's edges)
// and side, counter-clockwise seen from the ray's origin in object space as a traced hit's.
fn visible_hit(ray: Ray, instance: u32, primitive: u32) -> Hit {
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
    // World winding is object winding times the sign of the model's determinant.
    let mirrored = determinant(mat3x3<f32>(inst.model[0].xyz, inst.model[1].xyz, inst.model[2].xyz)) < 0.0;
    hit.front_face = (facing < 0.0) != mirrored;
    return hit;
}

// The world-space offset from `p` to where the camera ray `dir` meets the plane through `p`
// with normal `n` (zero where the ray runs along the plane).
fn plane_offset(dir: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let eye = frame.camera_pos.xyz;
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
    let seen = textureLoad(visibility, id.xy, 0).xy;
    if seen.x == 0u {
        textureStore(color, id.xy, vec4<f32>(0.0));
        return;
    }
    let ray = Ray(frame.camera_pos.xyz, 0.0, camera_dir(id.xy), 3.0e38);
    let hit = visible_hit(ray, seen.x - 1u, seen.y);
    let surface = surface_at_cone(ray, hit, camera_pixel_spread(id.xy) * hit.t);
    var s: ShadingPoint;
    s.position = surface.position;
    s.normal = surface.normal;
    s.view = -ray.dir;
    s.albedo = surface.albedo;
    s.metallic = surface.metallic;
    s.roughness = surface.roughness;
    s.occlusion = surface.occlusion;
    s.emissive = surface.emissive;
    let dp1 = plane_offset(camera_dir(id.xy + vec2<u32>(1u, 0u)), s.position, surface.geo_normal);
    let dp2 = plane_offset(camera_dir(id.xy + vec2<u32>(0u, 1u)), s.position, surface.geo_normal);
    textureStore(color, id.xy, vec4<f32>(forward_radiance(s, surface.geo_normal, dp1, dp2), 1.0));
}
