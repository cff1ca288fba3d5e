//! Bindings every pass may use without declaring them: frame uniforms, layer parameters,
//! the debug counters and the scene's resources. Their names are reserved.

use crate::runtime::uniforms::FrameUniforms;

pub const FRAME: &str = "frame";
pub const PARAMS: &str = "params";
pub const DEBUG_COUNTERS: &str = "debug_counters";
pub const SCENE_INSTANCES: &str = "scene_instances";
pub const SCENE_TEXTURES: &str = "scene_textures";
pub const LINEAR_SAMPLER: &str = "linear_sampler";
pub const NEAREST_SAMPLER: &str = "nearest_sampler";

/// Number of u32 counters in the `debug_counters` buffer.
pub const DEBUG_COUNTER_COUNT: u32 = 16;

pub fn frame_uniform_size() -> u32 {
    std::mem::size_of::<FrameUniforms>() as u32
}

pub fn is_builtin(name: &str) -> bool {
    matches!(name, FRAME | PARAMS | DEBUG_COUNTERS | SCENE_INSTANCES | SCENE_TEXTURES | LINEAR_SAMPLER | NEAREST_SAMPLER)
}

/// Whether the binding needs the scene on the GPU.
pub fn is_scene_binding(name: &str) -> bool {
    matches!(name, SCENE_INSTANCES | SCENE_TEXTURES)
}
