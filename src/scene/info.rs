//! `raygraph scene info`: counts, bounds and what the file uses that raygraph ignores.

use super::gltf_import::ImportReport;
use super::Scene;
use std::fmt::Write;

pub fn describe(scene: &Scene, report: Option<&ImportReport>) -> String {
    let mut s = String::new();
    let b = scene.bounds();
    let unique: usize = scene.meshes.iter().map(|m| m.triangle_count()).sum();
    let _ = writeln!(s, "scene       {}", scene.name);
    let _ = writeln!(s, "triangles   {} (over instances; {} in unique meshes)", scene.triangle_count(), unique);
    let _ = writeln!(s, "meshes      {}", scene.meshes.len());
    let _ = writeln!(s, "instances   {}", scene.instances.len());
    let _ = writeln!(s, "materials   {}", scene.materials.len());
    let _ = writeln!(s, "textures    {}", scene.textures.len());
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
    let presets: Vec<&str> = scene.presets.iter().map(|(n, _)| n.as_str()).collect();
    let _ = writeln!(s, "cameras     {}", if presets.is_empty() { "none".to_string() } else { presets.join(", ") });
    if let Some(r) = report {
        let _ = writeln!(s, "ignored     {}", if r.ignored_features.is_empty() { "nothing".to_string() } else { r.ignored_features.join(", ") });
        let _ = writeln!(
            s,
            "repairs     {} NaN/Inf triangles dropped, {} zero-area triangles, {} non-triangle primitives skipped, {} images replaced",
            r.non_finite_triangles, r.degenerate_triangles, r.skipped_primitives, r.missing_images
        );
        if r.textures_not_loaded > 0 {
            let _ = writeln!(s, "textures    {} references not loaded (the graph samples none)", r.textures_not_loaded);
        }
    }
    s
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
