// What the forward layers' scene draws share (forward/forward.wgsl: the opaque and
// alpha-tested surfaces; forward/translucent.wgsl: the translucent ones, blended): the
// bindings of the scene and its lights, the vertex stage, and the radiance of a fragment with
// the shading model of every mode (common/lighting.wgsl: every light of `scene_lights`, sky
// ambient x material occlusion, the sky's specular reflection, emission; every material input
// and texture). A light with a shadow slot (`Light::shadow_map`, the first four directional
// or spot lights and the two most powerful point lights) has its direct term multiplied by its
// shadow-map visibility (common/forward_shading.wgsl); other lights are unshadowed.
//#include "common/frame.wgsl"
//#include "common/camera.wgsl"
//#include "common/scene.wgsl"
//#include "common/scene_textures.wgsl"
//#include "common/lighting.wgsl"
//#include "common/material_inputs.wgsl"
//#include "common/forward_shading.wgsl"
//#include "common/scene_fragment.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> scene_instances: array<Instance>;
@group(0) @binding(3) var linear_sampler: sampler;
@group(0) @binding(4) var<storage, read> scene_materials: array<Material>;
@group(0) @binding(5) var<uniform> params: Params;
@group(0) @binding(6) var shadow_map: texture_depth_2d_array;
@group(0) @binding(10) var<storage, read> scene_lights: array<Light>;
@group(0) @binding(11) var<storage, read> scene_meshes: array<MeshRecord>;
@group(0) @binding(12) var<storage, read> scene_vertices: array<SceneVertex>;
@group(0) @binding(14) var shadow_cube: texture_depth_2d_array;

// The linear HDR radiance of fragment `in` with surface `r`. The geometric normal decides the
// shadow offset direction, so smooth shading normals do not push points into neighbouring
// geometry.
fn fragment_radiance(in: VertexOut, r: RasterSurface) -> vec3<f32> {
    var s: ShadingPoint;
    s.position = in.world;
    s.normal = r.normal;
    s.view = camera_view_dir(in.world);
    s.albedo = r.albedo;
    s.metallic = r.metallic;
    s.roughness = r.roughness;
    s.occlusion = r.occlusion;
    s.emissive = r.emissive;
    s.unlit = r.unlit;
    shading_lobes(&s, r.lobes);
    return forward_radiance(s, r.geo_normal, r.dp1, r.dp2);
}
