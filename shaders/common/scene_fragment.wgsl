// The fragment side of the raster passes that draw the scene's materials (the G-buffer,
// deferred/deferred.wgsl, and forward shading, common/forward_draw.wgsl), read from their
// shared vertex stage's output (common/scene_vertex.wgsl): whether a fragment is kept, and the
// material inputs a kept one shades with (common/raster_visibility.wgsl). Needs what those two
// need declared by the pass.
//#include "common/scene_vertex.wgsl"
//#include "common/raster_visibility.wgsl"

// Whether fragment `in` is kept (the alpha test): the fragment stage discards it otherwise.
fn scene_fragment_kept(in: VertexOut) -> bool {
    return raster_fragment_kept(scene_instances[in.instance], in.uv, in.clip.xy, in.color.a);
}

// The material inputs of fragment `in` of instance `inst` (its record, read once by the
// caller): back faces of single-sided materials culled, those of
// double-sided ones with reversed normals. Takes derivatives (the normal map's frame, the face
// normal and the shadow maps' receiver plane): call in uniform control flow.
fn scene_fragment_surface(in: VertexOut, inst: Instance, front_facing: bool) -> RasterSurface {
    return raster_surface(inst, front_facing, in.local, in.uv, in.uv1, in.color, in.normal);
}
