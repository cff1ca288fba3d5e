// The AO list (layers/rt_ao.ron, rt_ao_compacted.ron, rt_ao_persistent.ron): the pixels that
// have AO rays (a G-buffer position, not the sky), appended to `list` as x | y << 16, one texel
// each in row order (entry i at (i % width, i / width)); `listed[0]` counts them. A workgroup
// counts its pixels in workgroup memory and reserves their places with one atomic add on the
// counter, which the graph zeroes before the pass (`Buffer(zeroed: true)`). The order of the
// list depends on which workgroup gets there first; what a pixel's lanes compute does not
// depend on where it is listed.

@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var list: texture_storage_2d<r32uint, write>;
@group(0) @binding(4) var<storage, read_write> listed: array<atomic<u32>>;

var<workgroup> group_count: atomic<u32>;
var<workgroup> group_base: u32;

// 16x16: one atomic add on the global counter per 256 pixels.
@compute @workgroup_size(16, 16)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    let size = textureDimensions(position);
    let inside = id.x < size.x && id.y < size.y;
    var has_rays = false;
    if inside {
        has_rays = textureLoad(position, id.xy, 0).w != 0.0;
    }
    var slot = 0u;
    if has_rays {
        slot = atomicAdd(&group_count, 1u);
    }
    workgroupBarrier();
    if local == 0u {
        group_base = atomicAdd(&listed[0], atomicLoad(&group_count));
    }
    let index = workgroupUniformLoad(&group_base) + slot;
    if has_rays {
        let width = textureDimensions(list).x;
        textureStore(list, vec2<u32>(index % width, index / width), vec4<u32>(id.x | (id.y << 16u), 0u, 0u, 0u));
    }
}
