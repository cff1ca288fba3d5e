//! The scene's features as pipeline constants: what the scene uses of the material and mesh
//! features a pass can compile out (the alpha test, BLEND, the specular lobes, non-default
//! samplers and texture transforms, the second uv set and vertex colours, unlit materials),
//! whether an environment map lights it and whether its emissive triangles are lights, the
//! frame camera's projection, and whether the scene is large enough for AO rays to start below
//! the root of its tree. Every pass whose module declares one of the constants gets its value;
//! the shaders' defaults keep every feature (and read the projection from the frame), so a
//! pipeline made without them is right for any scene. The passes are built again when the
//! features change.

use crate::graph::compile::PlannedPass;
use crate::runtime::raster::SHADOW_SLOT_CONSTANT;
use crate::scene::Scene;

/// The trace module's pipeline constant that compiles the alpha test into the traversal
/// (`shaders/trace/alpha.wgsl`).
pub const TRACE_ALPHA_CONSTANT: &str = "TRACE_ALPHA_TEST";

/// The compute trace module's pipeline constant that starts rays within a sphere below the root
/// (`trace_start_within`, `shaders/trace/compute.wgsl`).
pub(crate) const TRACE_START_CONSTANT: &str = "TRACE_START_BELOW_ROOT";

/// The compute trace module's pipeline constant that compiles each traversal as the merged
/// layout's one BLAS loop, without the two-level code (`shaders/trace/compute.wgsl`): set where
/// the plan's acceleration structure is the merged layout ([`crate::accel::cache::AccelCache::merged_layout`]),
/// which the scene's features do not decide.
pub(crate) const TRACE_MERGED_CONSTANT: &str = "TRACE_MERGED";

/// Triangles from which AO rays start below the root: between the two scenes measured (H200,
/// PERF.md step 24): the box's 12, whose AO pass the start's per-lane descent made 67% slower,
/// and the organic mesh's 3,920, 8% faster with it.
pub(crate) const START_BELOW_ROOT_TRIANGLES: usize = 1024;

/// `shaders/common/scene_features.wgsl`: some material is translucent. It compiles the passes'
/// handling of translucent surfaces in (`shaders/common/ray_blend.wgsl`: skipped by primary rays,
/// attenuating shadow rays, composited; the raster translucent layer's read).
pub(crate) const BLEND_CONSTANT: &str = "SCENE_BLEND";

/// `shaders/common/scene_features.wgsl`: some material has its own specular lobes
/// (`KHR_materials_ior`, `_specular`, `_clearcoat`).
pub(crate) const LOBES_CONSTANT: &str = "SCENE_LOBES";

/// `shaders/common/scene_features.wgsl`: some material has a sampler other than glTF's default
/// or a `KHR_texture_transform`.
pub(crate) const CUSTOM_SAMPLING_CONSTANT: &str = "SCENE_CUSTOM_SAMPLING";

/// `shaders/common/scene_features.wgsl`: some drawn mesh has COLOR_0 or TEXCOORD_1.
pub(crate) const VERTEX_EXTRAS_CONSTANT: &str = "SCENE_VERTEX_EXTRAS";

/// `shaders/common/scene_features.wgsl`: some material is unlit (`KHR_materials_unlit`).
pub(crate) const UNLIT_CONSTANT: &str = "SCENE_UNLIT";

/// `shaders/common/scene_features.wgsl`: the scene is lit by an environment map (`--env`).
pub(crate) const ENVIRONMENT_CONSTANT: &str = "SCENE_ENVIRONMENT";

/// `shaders/common/emitters.wgsl`: some material emits light (an emissive factor above 0, not
/// unlit): the emissive triangles are lights.
pub(crate) const EMITTERS_CONSTANT: &str = "SCENE_EMITTERS";

/// `shaders/common/camera.wgsl`: the frame camera's projection (1 perspective, 2 orthographic).
pub(crate) const CAMERA_PROJECTION_CONSTANT: &str = "CAMERA_PROJECTION";

/// What the scene's instances use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SceneFeatures {
    /// Some instance is alpha-tested (MASK, BLEND or transmissive).
    pub alpha_test: bool,
    /// Some instance is translucent (BLEND or transmissive).
    pub blend: bool,
    /// Some instance's material has its own specular lobes.
    pub lobes: bool,
    /// Some instance's material has a non-default sampler or a texture transform.
    pub custom_sampling: bool,
    /// Some instance's mesh has vertex colours or a second uv set.
    pub vertex_extras: bool,
    /// Some instance's material is unlit.
    pub unlit: bool,
    /// The frame's camera is orthographic (set by `SceneFeatures::with_camera`).
    pub orthographic: bool,
    /// The instances draw at least [`START_BELOW_ROOT_TRIANGLES`] triangles.
    pub start_below_root: bool,
    /// An environment map lights the scene.
    pub environment: bool,
    /// Some instance's material emits light (`scene::emitters`).
    pub emitters: bool,
}

impl SceneFeatures {
    /// The features of `scene`'s instances: each material's and mesh's found once, then one
    /// pass over the instances that stops when every feature is in use (made every frame).
    pub fn of(scene: &Scene) -> Self {
        let material_bits: Vec<u8> = scene.materials().iter().map(Self::material_bits).collect();
        let mesh_bits: Vec<u8> = scene.meshes().iter().map(|m| if m.extras.is_some() { Self::VERTEX_EXTRAS } else { 0 }).collect();
        let mut bits = 0u8;
        let mut triangles = 0usize;
        for inst in scene.instances().iter() {
            bits |= material_bits.get(inst.material).copied().unwrap_or(0) | mesh_bits.get(inst.mesh).copied().unwrap_or(0);
            triangles += scene.meshes().get(inst.mesh).map_or(0, |m| m.triangle_count());
            if bits == Self::ALL_BITS && triangles >= START_BELOW_ROOT_TRIANGLES {
                break;
            }
        }
        let on = |bit: u8| bits & bit != 0;
        Self {
            alpha_test: on(Self::ALPHA_TEST),
            blend: on(Self::BLEND),
            lobes: on(Self::LOBES),
            custom_sampling: on(Self::CUSTOM_SAMPLING),
            vertex_extras: on(Self::VERTEX_EXTRAS),
            unlit: on(Self::UNLIT),
            orthographic: scene.camera().orthographic.is_some(),
            start_below_root: triangles >= START_BELOW_ROOT_TRIANGLES,
            environment: scene.environment().is_some(),
            emitters: on(Self::EMITS),
        }
    }

    /// The same features with the projection of `camera`, the frame's.
    pub(crate) fn with_camera(self, camera: &crate::scene::Camera) -> Self {
        Self { orthographic: camera.orthographic.is_some(), ..self }
    }

    const ALPHA_TEST: u8 = 1;
    const BLEND: u8 = 2;
    const LOBES: u8 = 4;
    const CUSTOM_SAMPLING: u8 = 8;
    const VERTEX_EXTRAS: u8 = 16;
    const UNLIT: u8 = 32;
    const EMITS: u8 = 64;
    const ALL_BITS: u8 = 127;

    /// The features material `m` uses, as bits.
    fn material_bits(m: &crate::scene::Material) -> u8 {
        let flag = |on: bool, bit: u8| if on { bit } else { 0 };
        flag(m.alpha_cutoff().is_some(), Self::ALPHA_TEST)
            | flag(m.translucent(), Self::BLEND)
            | flag(m.lobes != crate::scene::Lobes::default(), Self::LOBES)
            | flag(m.sampling.iter().any(|s| s.transform.is_some() || s.sampler_bits() != 0), Self::CUSTOM_SAMPLING)
            | flag(m.unlit, Self::UNLIT)
            | flag(!m.unlit && crate::util::luminance(m.emissive) > 0.0, Self::EMITS)
    }

    /// Every constant with its value.
    fn all(&self) -> [(&'static str, bool); 9] {
        [
            (TRACE_ALPHA_CONSTANT, self.alpha_test),
            (TRACE_START_CONSTANT, self.start_below_root),
            (BLEND_CONSTANT, self.blend),
            (LOBES_CONSTANT, self.lobes),
            (CUSTOM_SAMPLING_CONSTANT, self.custom_sampling),
            (VERTEX_EXTRAS_CONSTANT, self.vertex_extras),
            (UNLIT_CONSTANT, self.unlit),
            (ENVIRONMENT_CONSTANT, self.environment),
            (EMITTERS_CONSTANT, self.emitters),
        ]
    }

    /// The constants `pass`'s module declares, with their values.
    pub(crate) fn constants(&self, pass: &PlannedPass) -> Vec<(&'static str, f64)> {
        let projection = (CAMERA_PROJECTION_CONSTANT, if self.orthographic { 2.0 } else { 1.0 });
        let switches = self.all().into_iter().map(|(name, on)| (name, if on { 1.0 } else { 0.0 }));
        let slot = pass.shadow_slot.map(|slot| (SHADOW_SLOT_CONSTANT, slot as f64));
        switches.chain([projection]).chain(slot).filter(|(name, _)| pass.shader.has_override(name)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ao_rays_start_below_the_root_only_in_scenes_of_many_triangles() {
        let box_scene = crate::scene::procedural::box_scene();
        let organic = crate::scene::procedural::organic();
        assert!(box_scene.triangle_count() < START_BELOW_ROOT_TRIANGLES && organic.triangle_count() >= START_BELOW_ROOT_TRIANGLES);
        assert!(!SceneFeatures::of(&box_scene).start_below_root);
        assert!(SceneFeatures::of(&organic).start_below_root);
    }
}
