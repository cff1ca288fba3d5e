// One (pixel, lane) item of the AO list (rt/ao_items.wgsl, rt/ao_persistent.wgsl): item i is
// lane i % AO_LANES of the pixel at list entry i / AO_LANES. The bindings below are the two
// schedules' shared group 0 (bindings 0-6); an includer adds its own from binding 7.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var position: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var list: texture_2d<u32>;
@group(0) @binding(5) var<storage, read> listed: array<u32>;
@group(0) @binding(6) var partial: texture_storage_2d<r32float, write>;

fn ao_trace_item(item: u32) {
    let entry = item / AO_LANES;
    let width = textureDimensions(list).x;
    let packed = textureLoad(list, vec2<u32>(entry % width, entry / width), 0).r;
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let lane = item % AO_LANES;
    let p = textureLoad(position, pixel, 0);
    let n = normalize(textureLoad(geo_normal, pixel, 0).xyz);
    let open = ao_lane_open(pixel, lane, p.xyz, n);
    textureStore(partial, ao_partial_texel(pixel, lane), vec4<f32>(open, 0.0, 0.0, 0.0));
}
