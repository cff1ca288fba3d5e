//! `raygraph scene info`: counts, bounds, lights, cameras, and for a glTF file every repair,
//! texture fallback and feature that raygraph approximates or ignores.

use super::gltf_import::ImportReport;
use super::{AlphaMode, LightKind, Scene};
use std::fmt::Write;

/// The `scene info` report of `scene` (with what its import repaired, approximated or ignored).
pub fn describe(scene: &Scene, report: Option<&ImportReport>) -> String {
    let mut s = String::new();
    let b = scene.bounds();
    let unique: usize = scene.meshes.iter().map(|m| m.triangle_count()).sum();
    let _ = writeln!(s, "scene       {}", scene.name);
    if let Some(r) = report.filter(|r| !r.scenes.is_empty()) {
        list(&mut s, "gltf scenes", &r.scenes);
    }
    let _ = writeln!(s, "triangles   {} (over instances; {} in unique meshes)", scene.triangle_count(), unique);
    let closed = scene.meshes.iter().filter(|m| super::topology::is_closed_outward(m)).count();
    let _ = writeln!(s, "meshes      {} ({closed} closed and wound outwards)", scene.meshes.len());
    let _ = writeln!(s, "instances   {}", scene.instances.len());
    let default = if report.is_some_and(|r| r.default_material) { " (with `default`, for primitives that name none)" } else { "" };
    let _ = writeln!(s, "materials   {}{default}", scene.materials.len());
    let _ = writeln!(s, "alpha       {}", alpha_modes(scene));
    let _ = writeln!(s, "textures    {}", textures(scene, report));
    if b.is_empty() {
        let _ = writeln!(s, "bounds      empty");
    } else {
        let _ = writeln!(
            s,
            "bounds      min {:.3} {:.3} {:.3}  max {:.3} {:.3} {:.3}  (diagonal {:.3})",
            b.min.x,
            b.min.y,
            b.min.z,
            b.max.x,
            b.max.y,
            b.max.z,
            b.diagonal()
        );
    }
    if let Some((row, tris, meshes, textures)) = paper_row(&scene.name) {
        let _ = writeln!(s, "paper       Table 1 `{row}`: {tris} triangles, {meshes} meshes, {textures} textures");
    }
    let _ = writeln!(s, "lights      {}", lights(scene));
    if let Some(rig) = &scene.rig {
        let clips: Vec<String> =
            rig.animations.iter().enumerate().map(|(i, a)| format!("{i}: `{}` {:.2} s, {} channels", a.name, a.duration, a.channels.len())).collect();
        list(&mut s, "animations", &clips);
        let skinned = rig.deformers.iter().filter(|d| d.skin.is_some()).count();
        let morphed = rig.deformers.iter().filter(|d| !d.targets.is_empty()).count();
        let _ = writeln!(s, "deforming   {} meshes ({skinned} skinned, {morphed} with morph targets), {} skins", rig.deformers.len(), rig.skins.len());
    }
    let presets: Vec<&str> = scene.presets.iter().map(|(n, _)| n.as_str()).collect();
    let presets = if presets.is_empty() { "none".to_string() } else { presets.join(", ") };
    match report.map_or(0, |r| r.file_cameras) {
        0 => _ = writeln!(s, "cameras     {presets}"),
        n => _ = writeln!(s, "cameras     {n} from the file, then the built-in presets: {presets} (the first is the default view)"),
    }
    if let Some(r) = report {
        list(
            &mut s,
            "fallbacks",
            &r.texture_fallbacks
                .iter()
                .map(|f| format!("material {} {} texture: image `{}` {}; {}", f.material, f.slot.name(), f.image, f.reason, f.slot.fallback()))
                .collect::<Vec<_>>(),
        );
        list(&mut s, "approximated", &r.approximated);
        list(&mut s, "ignored", &r.ignored_features);
        let _ = writeln!(
            s,
            "repairs     {} NaN/Inf triangles dropped, {} zero-area triangles, {} non-triangle primitives skipped, {} images replaced by fallbacks",
            r.non_finite_triangles, r.degenerate_triangles, r.skipped_primitives, r.missing_images
        );
        let rr = &r.rig_repairs;
        if rr.renormalised_weights + rr.dropped_channels + rr.decomposed_matrices > 0 {
            let _ = writeln!(
                s,
                "repairs     {} vertices' skin weights normalised, {} weights channels without morph targets dropped, {} animated matrix nodes decomposed",
                rr.renormalised_weights, rr.dropped_channels, rr.decomposed_matrices
            );
        }
        if r.textures_not_loaded > 0 {
            let _ = writeln!(s, "textures    {} references not loaded (the graph samples none)", r.textures_not_loaded);
        }
    }
    s
}

/// `label  nothing`, or `label  N` and one indented line per item.
fn list(s: &mut String, label: &str, items: &[String]) {
    if items.is_empty() {
        let _ = writeln!(s, "{label:<11} nothing");
    } else {
        let _ = writeln!(s, "{label:<11} {}", items.len());
        for i in items {
            let _ = writeln!(s, "  {i}");
        }
    }
}

fn alpha_modes(scene: &Scene) -> String {
    let count = |f: fn(&AlphaMode) -> bool| scene.materials.iter().filter(|m| f(&m.alpha_mode)).count();
    let (opaque, mask, blend) = (count(|a| *a == AlphaMode::Opaque), count(|a| matches!(a, AlphaMode::Mask(_))), count(|a| *a == AlphaMode::Blend));
    format!("{opaque} opaque, {mask} mask, {blend} blend (materials; MASK is a cutout at its alphaCutoff, BLEND blended: by ray tracing in hybrid and full RT, sorted by instance in raster)")
}

/// The number of images the materials use; for a file, with how many loaded and how many
/// took their slots' fallbacks.
fn textures(scene: &Scene, report: Option<&ImportReport>) -> String {
    match report.and_then(|r| r.images_used.map(|used| (used, r))) {
        Some((used, r)) if r.missing_images > 0 => {
            format!("{used} (images the materials use: {} loaded, {} missing; see fallbacks)", used - r.missing_images, r.missing_images)
        }
        Some((used, _)) => format!("{used} (images the materials use)"),
        None => scene.textures.len().to_string(),
    }
}

fn lights(scene: &Scene) -> String {
    if scene.lights.is_empty() {
        let point = if scene.point_light.is_some() { " and the built-in point light" } else { "" };
        let sun = if scene.light.intensity == 0.0 && scene.light.ambient == 0.0 { "no sun and no sky (emissive surfaces only)" } else { "the default sun" };
        return format!("none in the scene: {sun}{point}");
    }
    let each: Vec<String> = scene
        .lights
        .iter()
        .map(|l| {
            let kind = match l.kind {
                LightKind::Directional => "directional",
                LightKind::Point { .. } => "point",
                LightKind::Spot { .. } => "spot",
            };
            format!("{} ({kind})", l.name)
        })
        .collect();
    // A scene of many lights names the first few.
    const NAMED: usize = 8;
    let more = each.len().saturating_sub(NAMED);
    let rest = if more > 0 { format!(" and {more} more") } else { String::new() };
    format!("{} from the file: {}{rest}", scene.lights.len(), each[..each.len().min(NAMED)].join(", "))
}

/// The row of the paper's Table 1 a built-in scene stands in for.
fn paper_row(name: &str) -> Option<(&'static str, u32, u32, u32)> {
    match name {
        "box" => Some(("Box", 12, 1, 2)),
        "organic" => Some(("Suzanne", 3_936, 1, 2)),
        "atrium" => Some(("Sponza", 262_267, 103, 69)),
        _ => None,
    }
}
