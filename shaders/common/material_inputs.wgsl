// Material inputs read the same way by every producer of shading data (the raster G-buffer,
// primary rays, reflection hits, forward shading): facing, tangent-space normal maps and
// occlusion.
//
// Normal maps. The tangent frame comes from two independent differentials of the position (`dp1`,
// `dp2`, world space) and of the uv (`duv1`, `duv2`): screen-space derivatives in a fragment
// shader, two triangle edges at a ray hit. On a flat triangle both give the same frame (position
// and uv are affine in the barycentrics), so meshes need no tangents.
// glTF conventions: tangent along +u; bitangent towards -v (the texture's +Y is "up" and glTF's
// v grows downwards), on the side given by the uv winding (mirrored uvs keep it right); texel
// rgb in [0, 1] linear (a data texture, no sRGB decode); xy scaled by `normal_scale`.

// The normal `n` (unit, world space, on the triangle's front side) perturbed by the normal map
// texel `texel`; `n` itself where the uv map is degenerate.
fn apply_normal_map(n: vec3<f32>, dp1: vec3<f32>, dp2: vec3<f32>, duv1: vec2<f32>, duv2: vec2<f32>, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    let det = duv1.x * duv2.y - duv2.x * duv1.y;
    // Relative test: uv differentials that (nearly) coincide in direction have no frame.
    if abs(det) <= 1e-6 * max(dot(duv1, duv1), dot(duv2, duv2)) {
        return n;
    }
    // dp/du and dp/dv (the inverse of the uv differentials applied to the position's).
    let dpdu = (dp1 * duv2.y - dp2 * duv1.y) / det;
    let dpdv = (dp2 * duv1.x - dp1 * duv2.x) / det;
    let t_raw = dpdu - n * dot(n, dpdu);
    if dot(t_raw, t_raw) <= 1e-12 * dot(dpdu, dpdu) || dot(dpdu, dpdu) == 0.0 {
        return n;
    }
    let t = normalize(t_raw);
    // Bitangent towards decreasing v.
    let b = select(1.0, -1.0, dot(cross(n, t), dpdv) > 0.0) * cross(n, t);
    let m = texel * 2.0 - vec3<f32>(1.0);
    let perturbed = t * (m.x * scale) + b * (m.y * scale) + n * m.z;
    let len2 = dot(perturbed, perturbed);
    if !(len2 > 0.0) {
        return n;
    }
    return perturbed * inverseSqrt(len2);
}

// The shadow-terminator offset of a hit on a smooth-shaded triangle (Hanika, "Hacking the
// Shadow Terminator", Ray Tracing Gems II ch. 4, 2021): the point `p` moved onto the blend, by
// its barycentric weights `w`, of its projections onto the tangent planes of the vertices
// (positions `a`, `b`, `c`, unit normals `na`, `nb`, `nc` on the hit's side, one space); only
// planes that `p` lies below push it. Returned as the offset vector: zero on a flat triangle,
// outwards where a low-poly surface bulges past its flat triangle, so that shadow rays leave
// from where the smooth surface would be and do not hit the neighbouring triangles.
fn terminator_offset(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, na: vec3<f32>, nb: vec3<f32>, nc: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    let da = min(0.0, dot(p - a, na));
    let db = min(0.0, dot(p - b, nb));
    let dc = min(0.0, dot(p - c, nc));
    return -(w.x * da * na + w.y * db * nb + w.z * dc * nc);
}

// Material occlusion (glTF occlusionTexture): 1 + strength x (texel red - 1); 1 without a
// texture (layer 0 is white).
fn material_occlusion(red: f32, strength: f32) -> f32 {
    return 1.0 + strength * (red - 1.0);
}

// Whether a rasterized fragment shows its triangle's front side (counter-clockwise in object
// space, as a ray hit's `front_face`): the screen winding, reversed for a mirrored instance
// (a model matrix of negative determinant).
fn raster_front_face(front_facing: bool, model: mat4x4<f32>) -> bool {
    let mirrored = determinant(mat3x3<f32>(model[0].xyz, model[1].xyz, model[2].xyz)) < 0.0;
    return front_facing != mirrored;
}
