//! What a compiled plan asks of a scene: which parts of it its passes read ([`SceneUsage`],
//! decided by the compiler, uploaded by the runtime), and the error when those parts do not fit
//! a device ([`SceneLimitError`]). Plain data: no GPU.

/// Which parts of the scene the kept passes of a plan use; only these are uploaded.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SceneUsage {
    /// Vertex and index buffers (a `SceneRaster` pass draws the meshes).
    pub geometry: bool,
    /// `scene_instances`.
    pub instances: bool,
    /// `scene_materials`.
    pub materials: bool,
    /// `scene_textures` (images are then decoded and uploaded).
    pub textures: bool,
    /// `scene_textures` is a binding array (of pooled array textures, `scene::texture_pool`)
    /// rather than one texture array.
    pub texture_binding_array: bool,
    /// `scene_vertices`, `scene_indices`, `scene_meshes` (geometry read in shaders).
    pub geometry_storage: bool,
    /// `scene_lights`.
    pub lights: bool,
    /// `scene_emitters`: the emissive triangles as lights (`scene::emitters`).
    pub emitters: bool,
    /// `scene_motion`: the previous frame's instance transforms.
    pub motion: bool,
    /// `scene_environment*`: the environment map (`runtime::environment_upload`; 1x1
    /// stand-ins without one).
    pub environment: bool,
    /// Which meshes are closed and wound outwards (`scene::topology`), for a pass with
    /// `cull_closed_back_faces`: found on the CPU at upload, not uploaded.
    pub closed_meshes: bool,
}

impl SceneUsage {
    /// Whether any pass reads the scene.
    pub fn any(&self) -> bool {
        self.geometry
            || self.instances
            || self.materials
            || self.textures
            || self.geometry_storage
            || self.lights
            || self.emitters
            || self.motion
            || self.environment
    }

    /// A short list for reports, e.g. `geometry, instances, textures`.
    pub fn describe(&self) -> String {
        let parts: Vec<&str> = [
            (self.geometry, "geometry"),
            (self.geometry_storage, "geometry for shading hits"),
            (self.instances, "instances"),
            (self.materials, "materials"),
            (self.textures, "textures"),
            (self.lights, "lights"),
            (self.emitters, "emissive triangles"),
            (self.motion, "previous transforms"),
            (self.environment, "environment map"),
            (self.closed_meshes, "closed meshes (found on the CPU)"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect();
        if parts.is_empty() {
            "nothing (no pass reads the scene)".into()
        } else {
            parts.join(", ")
        }
    }
}

/// The scene does not fit the device.
#[derive(Debug, thiserror::Error)]
#[error("scene `{scene}` does not fit the GPU: {what} needs {}, the device allows {}\n  help: {help}", amount(*.needed, *.bytes), amount(*.allowed, *.bytes))]
pub struct SceneLimitError {
    /// The scene's name.
    pub(crate) scene: String,
    /// What is too large.
    pub(crate) what: String,
    /// How much of it the scene needs.
    pub(crate) needed: u64,
    /// How much the device allows.
    pub(crate) allowed: u64,
    /// Whether `needed` and `allowed` are bytes (else a count).
    pub(crate) bytes: bool,
    /// What to change.
    pub(crate) help: String,
}

/// `n` as a count, or as bytes in MiB with the exact number.
fn amount(n: u64, bytes: bool) -> String {
    if bytes {
        format!("{:.2} MiB ({n} bytes)", n as f64 / (1u64 << 20) as f64)
    } else {
        n.to_string()
    }
}
