// A visibility buffer texel (`Rg32Uint`, visibility/visibility.wgsl): x is the instance + 1
// (0: nothing drawn) with VISIBLE_FRONT_FACE set where the rasterizer saw the triangle's front
// (counter-clockwise in object space), y the triangle within the instance's mesh.

const VISIBLE_FRONT_FACE: u32 = 0x80000000u;

struct Visible {
    drawn: bool,
    instance: u32,
    primitive: u32,
    front_face: bool,
}

fn visible_decode(texel: vec2<u32>) -> Visible {
    let id = texel.x & ~VISIBLE_FRONT_FACE;
    return Visible(id != 0u, id - 1u, texel.y, (texel.x & VISIBLE_FRONT_FACE) != 0u);
}
