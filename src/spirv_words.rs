//! SPIR-V modules as words, for the two places raygraph changes what naga's writer made: the
//! `rt-pipeline` any-hit shader (`accel::rt_pipeline::any_hit`) and the compute back-end's
//! trace modules without the traversal stack's zero initialiser (`runtime::trace_spirv`).
//! It owns walking the instructions, reading names, writing an instruction's first word, and
//! the descriptor sets and bindings wgpu-hal's Vulkan back-end gives a pipeline layout's
//! entries.

use spirv::Op;

/// One instruction: its opcode and its words (the first included).
pub fn instructions(words: &[u32]) -> Result<Vec<(u16, &[u32])>, String> {
    if words.len() < 5 || words[0] != spirv::MAGIC_NUMBER {
        return Err("not a SPIR-V module".into());
    }
    let mut out = Vec::new();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Err(format!("a malformed instruction at word {at}"));
        }
        out.push((words[at] as u16, &words[at..at + count]));
        at += count;
    }
    Ok(out)
}

/// The string operand starting at `words[0]` (nul-terminated UTF-8, little-endian words).
pub fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).take_while(|&b| b != 0).collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// The first word of an instruction of `count` words.
pub(crate) fn word0(op: Op, count: usize) -> u32 {
    ((count as u32) << 16) | op as u32
}

/// The id an `OpName` gives `name` (naga writes names with `WriterFlags::DEBUG`).
pub fn named(list: &[(u16, &[u32])], name: &str) -> Result<u32, String> {
    list.iter().find(|(op, w)| *op == Op::Name as u16 && string(&w[2..]) == name).map(|(_, w)| w[1]).ok_or_else(|| format!("no variable `{name}`"))
}

/// The descriptor set and binding of every binding of `layouts` (group `g` is `layouts[g]`,
/// its entries in the order its hal layout was made from), as wgpu-hal maps them: its Vulkan
/// bind group layouts number bindings in the order of their entries, and binding arrays get
/// their layout's count (`wgpu-hal/src/vulkan/device.rs`, `create_bind_group_layout` and
/// `create_pipeline_layout`).
pub fn binding_map(layouts: &[Vec<wgpu::BindGroupLayoutEntry>]) -> naga::back::spv::BindingMap {
    let mut map = naga::back::spv::BindingMap::new();
    for (group, entries) in layouts.iter().enumerate() {
        for (index, entry) in entries.iter().enumerate() {
            map.insert(
                naga::ResourceBinding { group: group as u32, binding: entry.binding },
                naga::back::spv::BindingInfo { descriptor_set: group as u32, binding: index as u32, binding_array_size: entry.count.map(|c| c.get()) },
            );
        }
    }
    map
}
