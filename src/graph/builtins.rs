//! Bindings every pass may use without declaring them: frame uniforms, layer parameters,
//! the debug counters and the scene's resources. Their names are reserved.

use crate::scene::usage::SceneUsage;
use crate::uniforms::FrameUniforms;

pub(crate) const FRAME: &str = "frame";
pub(crate) const PARAMS: &str = "params";
pub(crate) const DEBUG_COUNTERS: &str = "debug_counters";
pub(crate) const SCENE_INSTANCES: &str = "scene_instances";
pub(crate) const SCENE_TEXTURES: &str = "scene_textures";
pub(crate) const SCENE_MATERIALS: &str = "scene_materials";
/// Every mesh's vertices (`array<SceneVertex>`), indices (`array<u32>`) and ranges
/// (`array<MeshRecord>`): what a trace pass reads to shade a hit.
pub(crate) const SCENE_VERTICES: &str = "scene_vertices";
pub(crate) const SCENE_INDICES: &str = "scene_indices";
pub(crate) const SCENE_MESHES: &str = "scene_meshes";
/// The lights (`array<Light>`, `shaders/common/lighting.wgsl`): `Scene::effective_lights()`,
/// `frame.light_count` of them, rewritten every frame.
pub(crate) const SCENE_LIGHTS: &str = "scene_lights";
/// The emissive triangles as lights (`array<u32>`, `scene::emitters`): uploaded with the scene.
pub(crate) const SCENE_EMITTERS: &str = "scene_emitters";
/// Every instance's model matrix of the previous frame (`array<mat4x4<f32>>`, one per
/// instance, its current one on a frame without history): what motion vectors are made from.
/// Rewritten only when it changes.
pub(crate) const SCENE_MOTION: &str = "scene_motion";
/// The environment map (`shaders/common/environment.wgsl`, bind group 3): its radiance
/// (`texture_2d<f32>`, equirectangular, with mips), its irradiance on a grid of normals, its
/// parameters (uniform), its importance sampler's alias table (`array<vec4<u32>>`,
/// `shaders/common/environment_sampling.wgsl`) and its sampler. 1x1 stand-ins where the scene
/// has no map.
pub(crate) const SCENE_ENVIRONMENT: &str = "scene_environment";
pub(crate) const SCENE_ENVIRONMENT_IRRADIANCE: &str = "scene_environment_irradiance";
pub(crate) const SCENE_ENVIRONMENT_PARAMS: &str = "scene_environment_params";
pub(crate) const SCENE_ENVIRONMENT_TABLE: &str = "scene_environment_table";
pub(crate) const ENVIRONMENT_SAMPLER: &str = "environment_sampler";
/// The bind group of the environment map's bindings.
pub(crate) const ENVIRONMENT_GROUP: u32 = 3;

/// Whether a binding is one of the environment map's (group 3).
pub(crate) fn is_environment_binding(name: &str) -> bool {
    matches!(name, SCENE_ENVIRONMENT | SCENE_ENVIRONMENT_IRRADIANCE | SCENE_ENVIRONMENT_PARAMS | SCENE_ENVIRONMENT_TABLE | ENVIRONMENT_SAMPLER)
}

/// The bind group `scene_textures` lives in (alone: a binding array may not share a group with
/// uniform buffers).
pub(crate) const SCENE_TEXTURES_GROUP: u32 = 1;
pub(crate) const LINEAR_SAMPLER: &str = "linear_sampler";
pub(crate) const NEAREST_SAMPLER: &str = "nearest_sampler";

/// The bind group of the trace module's bindings (`accel_*`, declared by the back-end's
/// `trace/*.wgsl`, never by a pass's own shader).
pub(crate) const ACCEL_GROUP: u32 = 2;

/// Whether a binding belongs to the trace module.
pub(crate) fn is_accel_binding(name: &str) -> bool {
    name.starts_with("accel_")
}

/// Number of u32 counters in the `debug_counters` buffer.
pub(crate) const DEBUG_COUNTER_COUNT: u32 = 16;

pub(crate) fn frame_uniform_size() -> u32 {
    std::mem::size_of::<FrameUniforms>() as u32
}

pub(crate) fn is_builtin(name: &str) -> bool {
    matches!(
        name,
        FRAME
            | PARAMS
            | DEBUG_COUNTERS
            | SCENE_INSTANCES
            | SCENE_MATERIALS
            | SCENE_TEXTURES
            | SCENE_VERTICES
            | SCENE_INDICES
            | SCENE_MESHES
            | SCENE_LIGHTS
            | SCENE_EMITTERS
            | SCENE_MOTION
            | LINEAR_SAMPLER
            | NEAREST_SAMPLER
    ) || is_environment_binding(name)
}

impl SceneUsage {
    /// Adds what a binding needs.
    pub fn add_binding(&mut self, b: &crate::graph::reflect::ShaderBinding) {
        match b.name.as_str() {
            SCENE_INSTANCES => self.instances = true,
            SCENE_MATERIALS => self.materials = true,
            SCENE_LIGHTS => self.lights = true,
            SCENE_EMITTERS => self.emitters = true,
            SCENE_MOTION => self.motion = true,
            name if is_environment_binding(name) => self.environment = true,
            SCENE_VERTICES | SCENE_INDICES | SCENE_MESHES => self.geometry_storage = true,
            SCENE_TEXTURES => {
                self.textures = true;
                self.texture_binding_array |= b.kind == crate::graph::reflect::BindingKind::TextureBindingArray;
            }
            _ => {}
        }
    }
}
