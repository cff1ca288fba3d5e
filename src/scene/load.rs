//! Opening a scene by name or path: the built-in scenes (`default`, `box`, `organic`,
//! `atrium`, the animated `organic-skinned` and `atrium-moving`, the Cornell box `cornell` and
//! the many-lights `atrium-lights`)
//! or a glTF/GLB file, with only the parts the active graph needs.

use super::gltf_import::{self, ImportReport, LoadOptions, SceneError};
use super::{builtin, procedural, Scene};
use std::path::Path;

/// Names of the built-in scenes.
pub const BUILTIN_NAMES: &[&str] = &["default", "box", "organic", "atrium", "organic-skinned", "atrium-moving", "cornell", "atrium-lights"];

/// The built-in scene called `name`.
pub fn builtin(name: &str, seed: u64) -> Option<Scene> {
    match name {
        "default" => Some(builtin::default_scene()),
        "atrium" => Some(procedural::atrium(seed)),
        "atrium-moving" => Some(procedural::animated::atrium_moving(seed)),
        "atrium-lights" => Some(procedural::atrium_lights(seed)),
        other => procedural::by_name(other),
    }
}

/// Opens `spec`: a built-in scene name, or a path to a `.gltf` / `.glb` file. The report is
/// empty for built-in scenes.
pub fn open(spec: &str, options: &LoadOptions) -> Result<(Scene, ImportReport), SceneError> {
    let path = Path::new(spec);
    let looks_like_file = path.extension().is_some() || spec.contains('/') || path.exists();
    let loaded = if let (false, Some(scene)) = (looks_like_file, builtin(spec, options.seed)) {
        if let Some(asked) = &options.gltf_scene {
            return Err(SceneError::SceneOfBuiltin { scene: spec.to_string(), asked: asked.clone() });
        }
        let mut report = ImportReport::default();
        let referenced = scene.materials.iter().flat_map(|m| m.slot_textures()).flatten().count();
        if !options.textures {
            report.textures_not_loaded = referenced;
        }
        (scene, report)
    } else if looks_like_file {
        gltf_import::load(path, options)?
    } else {
        return Err(SceneError::UnknownScene(spec.to_string(), BUILTIN_NAMES.join(", ")));
    };
    Ok(without_unused_textures(loaded, options))
}

/// The scene without its textures where `options` does not load them.
fn without_unused_textures((mut scene, report): (Scene, ImportReport), options: &LoadOptions) -> (Scene, ImportReport) {
    if !options.textures {
        scene.strip_textures();
    }
    (scene, report)
}

/// Opens the bytes of a glTF or GLB file called `name` (what a browser's file picker gives),
/// as [`open`] opens a file; errors name `name`.
pub fn open_bytes(name: &str, bytes: &[u8], options: &LoadOptions) -> Result<(Scene, ImportReport), SceneError> {
    gltf_import::load_bytes(Path::new(name), bytes, options).map(|loaded| without_unused_textures(loaded, options))
}
