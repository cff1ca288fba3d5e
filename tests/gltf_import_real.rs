//! glTF import of what real files carry: per-slot texture fallbacks, occlusion, emissive
//! strength, `KHR_lights_punctual` lights and cameras (in world space through a rotated,
//! translated and scaled parent), what `scene info` lists as approximated or ignored, the
//! export round trip of all of it, and the exact report of the two real assets in
//! `assets/gltf`.

mod common;

use common::gltf_doc::{png, temp_dir, Doc};
use glam::{Mat4, Quat, Vec3};
use raygraph::scene::gltf_import::{self, ImportReport, TextureSlot};
use raygraph::scene::{export, info, AlphaMode, LightKind, LoadOptions, Material, Scene};
use serde_json::{json, Value};
use std::f32::consts::FRAC_1_SQRT_2;
use std::path::Path;

fn load(path: &Path) -> (Scene, ImportReport) {
    gltf_import::load(path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// One triangle (with uvs) drawn with material 0, which is `material`.
fn triangle_with(material: Value) -> Doc {
    let mut d = Doc::new();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv = d.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 3);
    let mesh = d.mesh(&[("POSITION", p), ("TEXCOORD_0", uv)], None, Some(0), None);
    d.material(material);
    d.node(json!({"mesh": mesh}), true);
    d
}

/// A material whose `slot` names a texture of a missing image (next to a loadable base colour
/// image where the slot is another one), loaded; with the one fallback it must report.
fn load_with_missing(slot: TextureSlot) -> (Material, ImportReport, Scene) {
    let dir = temp_dir("slot-fallback");
    std::fs::write(dir.join("white.png"), png(2, 2, [255, 255, 255, 255])).unwrap();
    let mut d = triangle_with(json!({}));
    let good = d.texture_uri("white.png");
    let missing = d.texture_uri("missing.png");
    let mut m = json!({"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": good}}, "emissiveFactor": [1.0, 0.5, 0.25]});
    match slot {
        TextureSlot::BaseColor => m["pbrMetallicRoughness"]["baseColorTexture"]["index"] = json!(missing),
        TextureSlot::MetallicRoughness => m["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({"index": missing}),
        TextureSlot::Normal => m["normalTexture"] = json!({"index": missing, "scale": 0.5}),
        TextureSlot::Occlusion => m["occlusionTexture"] = json!({"index": missing, "strength": 0.5}),
        TextureSlot::Emissive => m["emissiveTexture"] = json!({"index": missing}),
        lobe => {
            let path = lobe.json_path();
            m[path[0]][path[1]][path[2]] = json!({"index": missing});
        }
    }
    d.json["materials"][0] = m;
    let (s, r) = load(&d.write_gltf_external(&dir, "doc"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(r.missing_images, 1);
    assert_eq!(r.texture_fallbacks.len(), 1, "{:?}", r.texture_fallbacks);
    let f = &r.texture_fallbacks[0];
    assert_eq!((f.material.as_str(), f.slot, f.image.as_str()), ("`m`", slot, "missing.png"));
    let w = r.warnings.iter().find(|w| w.contains("missing.png")).expect("a warning for the slot");
    assert!(w.contains("doc.gltf") && w.contains("`m`") && w.contains(slot.name()) && w.contains(slot.fallback()), "{w}");
    assert_eq!(r.images_used, Some(if slot == TextureSlot::BaseColor { 1 } else { 2 }), "the missing image counts as used");
    (s.materials()[0].clone(), r, s)
}

#[test]
fn a_missing_base_colour_image_becomes_the_magenta_checker() {
    let (m, _, s) = load_with_missing(TextureSlot::BaseColor);
    let t = &s.textures()[m.texture.expect("the base colour slot keeps a texture")];
    assert_eq!(&t.rgba[0..4], &[255, 0, 255, 255], "magenta marks the missing texture");
    assert_eq!(m.emissive, [1.0, 0.5, 0.25], "other slots untouched");
}

#[test]
fn a_missing_metallic_roughness_image_leaves_the_factors_alone() {
    let (m, _, s) = load_with_missing(TextureSlot::MetallicRoughness);
    assert_eq!(m.metallic_roughness_texture, None);
    assert_eq!((m.metallic, m.roughness), (1.0, 1.0), "the glTF default factors");
    assert_eq!(s.textures().len(), 1, "only the base colour image; no checker was made");
}

#[test]
fn a_missing_normal_map_gives_the_flat_normal() {
    let (m, _, s) = load_with_missing(TextureSlot::Normal);
    assert_eq!(m.normal_texture, None);
    assert!(s.meshes()[0].tangents.is_none(), "no normal map, so no generated tangents");
    assert_eq!(s.textures().len(), 1);
}

#[test]
fn a_missing_occlusion_image_gives_occlusion_one() {
    let (m, _, s) = load_with_missing(TextureSlot::Occlusion);
    assert_eq!(m.occlusion_texture, None);
    assert_eq!(s.textures().len(), 1);
}

#[test]
fn a_missing_emissive_image_turns_the_emission_off() {
    let (m, _, s) = load_with_missing(TextureSlot::Emissive);
    assert_eq!((m.emissive_texture, m.emissive), (None, [0.0; 3]));
    assert_eq!(s.textures().len(), 1);
}

#[test]
fn a_missing_lobe_extension_image_leaves_its_factor_alone() {
    for (k, slot) in TextureSlot::ALL[5..].iter().enumerate() {
        let (m, _, s) = load_with_missing(*slot);
        assert_eq!(m.lobes.textures[k], None, "{slot:?}");
        assert_eq!(s.textures().len(), 1, "{slot:?}: only the base colour image; no checker was made");
    }
}

#[test]
fn one_missing_image_in_two_slots_is_one_missing_image_and_two_fallbacks() {
    let dir = temp_dir("shared-missing");
    let mut d = triangle_with(json!({}));
    let t = d.texture_uri("gone.png");
    d.json["materials"][0] = json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": t}}, "normalTexture": {"index": t}});
    let (s, r) = load(&d.write_gltf_external(&dir, "doc"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!((r.missing_images, r.texture_fallbacks.len(), r.images_used), (1, 2, Some(1)));
    assert_eq!(s.materials()[0].normal_texture, None);
    assert!(s.materials()[0].texture.is_some());
    says(&info::describe(&s, Some(&r)), &["textures    1 (images the materials use: 0 loaded, 1 missing", "fallbacks   2\n"]);
}

#[test]
fn occlusion_and_emissive_strength_are_imported() {
    let dir = temp_dir("occlusion");
    let mut d = triangle_with(json!({}));
    let t = d.texture_embedded(&png(2, 2, [200, 0, 0, 255])); // no sampler: nothing to list
    d.json["materials"][0] = json!({
        "occlusionTexture": {"index": t, "strength": 0.25},
        "emissiveFactor": [1.0, 0.5, 0.25],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}
    });
    d.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    let (s, r) = load(&d.write_gltf_external(&dir, "doc"));
    let _ = std::fs::remove_dir_all(&dir);
    let m = &s.materials()[0];
    assert_eq!(m.occlusion_strength, 0.25);
    assert_eq!(&s.textures()[m.occlusion_texture.unwrap()].rgba[0..4], &[200, 0, 0, 255]);
    assert_eq!(m.emissive, [4.0, 2.0, 1.0], "emissiveFactor x emissiveStrength");
    assert!(r.ignored_features.is_empty(), "both are read: {:?}", r.ignored_features);
}

/// A parent node translated by (1, 2, 3), turned 90 degrees about +y and scaled by 2, over a
/// directional light (no transform of its own), a point light at local (0, 0, -2) and a spot
/// light turned 90 degrees about +x.
fn lights_document() -> Doc {
    let mut d = triangle_with(json!({}));
    d.json["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    d.json["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "color": [1.0, 0.9, 0.8], "intensity": 3.0},
        {"type": "point", "intensity": 40.0},
        {"name": "cone", "type": "spot", "range": 10.0, "intensity": 100.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
    ]}});
    let ext = |i: usize| json!({"KHR_lights_punctual": {"light": i}});
    let sun = d.node(json!({"extensions": ext(0)}), false);
    let point = d.node(json!({"name": "bulb", "translation": [0.0, 0.0, -2.0], "extensions": ext(1)}), false);
    let spot = d.node(json!({"rotation": [FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2], "extensions": ext(2)}), false);
    d.node(
        json!({"translation": [1.0, 2.0, 3.0], "rotation": [0.0, FRAC_1_SQRT_2, 0.0, FRAC_1_SQRT_2], "scale": [2.0, 2.0, 2.0], "children": [sun, point, spot]}),
        true,
    );
    d
}

/// Asserts that `scene info` text says every one of `parts`.
fn says(text: &str, parts: &[&str]) {
    for part in parts {
        assert!(text.contains(part), "`{part}` missing from\n{text}");
    }
}

fn near(a: Vec3, b: Vec3) -> bool {
    a.distance(b) < 1e-5
}

#[test]
fn every_kind_of_punctual_light_is_imported_in_world_space() {
    let dir = temp_dir("lights");
    let (s, r) = load(&lights_document().write_glb(&dir, "lights"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(s.lights().len(), 3);
    assert!(r.ignored_features.is_empty(), "{:?}", r.ignored_features);
    // The parent turns -z into -x; the spot's own turn makes its -z +y first.
    let [sun, point, spot] = [&s.lights()[0], &s.lights()[1], &s.lights()[2]];
    assert_eq!((sun.name.as_str(), sun.kind), ("sun", LightKind::Directional));
    assert!(near(sun.direction, Vec3::NEG_X), "{}", sun.direction);
    assert_eq!((sun.color, sun.intensity), (Vec3::new(1.0, 0.9, 0.8), 3.0));
    assert_eq!((point.name.as_str(), point.kind), ("bulb", LightKind::Point { range: None }), "named after its node");
    assert!(near(point.position, Vec3::new(1.0 - 4.0, 2.0, 3.0)), "(1,2,3) + R(2 x (0,0,-2)): {}", point.position);
    assert_eq!((point.color, point.intensity), (Vec3::ONE, 40.0), "glTF's default colour");
    assert_eq!(spot.kind, LightKind::Spot { range: Some(10.0), inner_cone: 0.2, outer_cone: 0.6 });
    assert!(near(spot.position, Vec3::new(1.0, 2.0, 3.0)) && near(spot.direction, Vec3::Y), "{} {}", spot.position, spot.direction);
    assert_eq!(s.effective_lights(), s.lights(), "the file's lights replace the default sun");
    let text = info::describe(&s, Some(&r));
    says(&text, &["lights      3 from the file: sun (directional), bulb (point), cone (spot)"]);
}

#[test]
fn a_file_without_lights_keeps_the_default_sun() {
    let dir = temp_dir("no-lights");
    let (s, _) = load(&triangle_with(json!({})).write_glb(&dir, "plain"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(s.lights().is_empty());
    let sun = s.effective_lights();
    assert_eq!(sun.len(), 1);
    assert!(near(sun[0].direction, -s.light().direction));
}

/// Two perspective cameras and an orthographic one: `hero` at (0, 1, 5) looking down -z; an
/// unnamed camera on node `side` under a parent at (4, 0, 0) turned 90 degrees about +y (so
/// it looks down -x), with no far plane and an aspect ratio.
fn cameras_document() -> Doc {
    let mut d = triangle_with(json!({}));
    d.json["cameras"] = json!([
        {"name": "hero", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 50.0}},
        {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.2, "aspectRatio": 1.5}},
        {"name": "plan", "type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0}}
    ]);
    d.node(json!({"camera": 0, "translation": [0.0, 1.0, 5.0]}), true);
    let side = d.node(json!({"name": "side", "camera": 1}), false);
    d.node(json!({"translation": [4.0, 0.0, 0.0], "rotation": [0.0, FRAC_1_SQRT_2, 0.0, FRAC_1_SQRT_2], "children": [side]}), true);
    d.node(json!({"camera": 2}), true);
    d
}

#[test]
fn the_files_cameras_become_presets_and_the_first_is_the_default_view() {
    let dir = temp_dir("cameras");
    let (s, r) = load(&cameras_document().write_glb(&dir, "cams"));
    let _ = std::fs::remove_dir_all(&dir);
    let names: Vec<&str> = s.presets().iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["hero", "side", "plan", "front", "top"],
        "the file's cameras named by camera, then by node; then the built-in presets (the file's `side` takes the built-in one's place)"
    );
    assert_eq!(s.preset("plan").unwrap().orthographic, Some(1.0));
    assert_eq!(*s.camera(), s.presets()[0].1, "the first is the default view");
    let hero = s.preset("hero").unwrap();
    let want = Mat4::look_at_rh(Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 1.0, 4.0), Vec3::Y);
    assert!(hero.view().abs_diff_eq(want, 1e-5), "{:?}", hero.view());
    assert_eq!((hero.fov_y, hero.near, hero.far), (0.8, 0.1, 50.0));
    let side = s.preset("side").unwrap();
    let want = Mat4::look_at_rh(Vec3::new(4.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), Vec3::Y);
    assert!(side.view().abs_diff_eq(want, 1e-5), "{:?}", side.view());
    assert!(side.far > side.near && side.far.is_finite());
    assert_eq!((side.aspect_ratio, hero.aspect_ratio), (Some(1.5), None), "aspectRatio is kept for `render` to size its output by");
    assert_eq!(s.preset("plan").unwrap().aspect_ratio, Some(1.0), "an orthographic camera's xmag / ymag");
    assert_eq!(r.file_cameras, 3);
    says(
        &info::describe(&s, Some(&r)),
        &[
            "cameras     3 from the file, then the built-in presets: hero, side, plan, front, top (the first is the default view)",
            "camera `side`: infinite far plane",
        ],
    );
}

#[test]
fn camera_names_are_made_unique_and_unnamed_ones_numbered() {
    let dir = temp_dir("camera-names");
    let mut d = triangle_with(json!({}));
    d.json["cameras"] = json!([{"name": "a", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}, {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]);
    d.node(json!({"camera": 0}), true);
    d.node(json!({"camera": 0, "translation": [1.0, 0.0, 0.0]}), true);
    d.node(json!({"camera": 1}), true);
    let (s, _) = load(&d.write_glb(&dir, "names"));
    let _ = std::fs::remove_dir_all(&dir);
    let names: Vec<&str> = s.presets().iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["a", "a-2", "camera1", "front", "top", "side"]);
}

#[test]
fn a_file_without_cameras_keeps_the_automatic_presets() {
    let dir = temp_dir("no-cameras");
    let (s, r) = load(&triangle_with(json!({})).write_glb(&dir, "plain"));
    let _ = std::fs::remove_dir_all(&dir);
    let names: Vec<&str> = s.presets().iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["front", "top", "side"]);
    assert_eq!(r.file_cameras, 0);
}

#[test]
fn scene_info_lists_what_is_approximated_or_ignored_per_material_and_extension() {
    let dir = temp_dir("ignored");
    std::fs::write(dir.join("a.png"), png(2, 2, [255, 255, 255, 255])).unwrap();
    let mut d = triangle_with(json!({}));
    let t = d.texture_uri("a.png"); // its sampler: wrapT MIRRORED_REPEAT
    d.json["materials"][0] = json!({
        "name": "coat", "alphaMode": "BLEND",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": t, "texCoord": 2, "extensions": {"KHR_texture_transform": {"scale": [2.0, 2.0]}}}},
        "extensions": {"KHR_materials_sheen": {"sheenRoughnessFactor": 1.0}}
    });
    d.json["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_materials_sheen"]);
    let colour = d.floats(&[1.0; 12], "VEC4", 3);
    d.json["meshes"][0]["primitives"][0]["attributes"]["COLOR_1"] = json!(colour);
    d.json["meshes"][0]["name"] = json!("tri");
    let (s, r) = load(&d.write_gltf_external(&dir, "doc"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(s.materials()[0].sampling[0].wrap_t, raygraph::scene::Wrap::MirroredRepeat);
    assert_eq!(s.materials()[0].sampling[0].transform, Some([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]));
    assert_eq!(
        r.approximated,
        ["material `coat`: alphaMode BLEND is blended in hybrid and full RT (up to 8 surfaces a ray, in depth order), in raster after the opaque surfaces with instances sorted back to front (not the triangles of one mesh), screen-door in raster shadow maps"]
    );
    // KHR_texture_transform and the sampler's MIRRORED_REPEAT are read (tests/texture_sampling.rs).
    let want = [
        "extension KHR_materials_sheen (not read)",
        "material `coat`: KHR_materials_sheen",
        "material `coat` base colour texture: texCoord 2 (TEXCOORD_0 is read instead)",
        "vertex colours past COLOR_0 on mesh `tri`",
    ];
    assert_eq!(r.ignored_features, want);
    let text = info::describe(&s, Some(&r));
    says(&text, &["approximated 1\n", &format!("ignored     {}\n", want.len()), "alpha       0 opaque, 0 mask, 1 blend"]);
    says(&text, &want.map(|l| format!("  {l}\n")).iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(r.notes().len(), 1 + want.len(), "render prints each once");
}

#[test]
fn a_16_bit_image_is_rounded_to_8_bits_and_says_so() {
    let dir = temp_dir("deep-image");
    let img = image::ImageBuffer::<image::Rgba<u16>, _>::from_pixel(2, 2, image::Rgba([0x01ff, 0x8040, 0, 0xffff]));
    img.save(dir.join("deep.png")).unwrap();
    let mut d = triangle_with(json!({}));
    let t = d.texture_uri("deep.png");
    d.json["materials"][0] = json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": t}}});
    let (s, r) = load(&d.write_gltf_external(&dir, "doc"));
    let _ = std::fs::remove_dir_all(&dir);
    // 511 / 65535 x 255 = 1.99 (the high byte would give 1); 32832 / 65535 x 255 = 127.75.
    assert_eq!(&s.textures()[0].rgba[0..4], &[2, 128, 0, 255], "each channel rounded to the nearest 8-bit value");
    assert_eq!(r.approximated, ["image `deep.png`: 16-bit channels rounded to 8 bits (textures are stored as RGBA8)"]);
}

#[test]
fn a_required_extension_raygraph_cannot_read_is_an_error_naming_it() {
    let dir = temp_dir("required");
    let mut d = triangle_with(json!({}));
    d.json["extensionsUsed"] = json!(["KHR_draco_mesh_compression", "KHR_lights_punctual"]);
    d.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression", "KHR_lights_punctual"]);
    let path = d.write_glb(&dir, "draco");
    let e = gltf_import::load(&path, &LoadOptions::default()).expect_err("must be refused").to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(e.contains("draco.glb") && e.contains("requires KHR_draco_mesh_compression,") && e.contains("help:"), "{e}");
}

#[test]
fn export_round_trips_lights_cameras_occlusion_and_emissive_strength() {
    let dir = temp_dir("export-new");
    std::fs::write(dir.join("ao.png"), png(2, 2, [90, 0, 0, 255])).unwrap();
    let mut d = lights_document();
    let cams = cameras_document();
    d.json["cameras"] = cams.json["cameras"].clone();
    d.node(json!({"name": "eye", "camera": 0, "translation": [0.0, 1.0, 5.0], "rotation": Quat::from_rotation_x(-0.3).to_array()}), true);
    let t = d.texture_uri("ao.png");
    d.json["materials"][0] = json!({"occlusionTexture": {"index": t, "strength": 0.5}, "emissiveFactor": [1.0, 0.5, 0.0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8.0}}});
    d.json["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_materials_emissive_strength"]);
    let (s, _) = load(&d.write_gltf_external(&dir, "doc"));
    let out = dir.join("out.glb");
    export::write_glb(&s, &out).unwrap();
    let (back, r) = load(&out);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(r.ignored_features.is_empty() && r.warnings.is_empty(), "{r:?}");
    assert_eq!(back.lights().len(), s.lights().len());
    for (a, b) in s.lights().iter().zip(back.lights()) {
        assert_eq!((&a.name, a.kind, a.color, a.intensity), (&b.name, b.kind, b.color, b.intensity));
        assert!(near(a.direction, b.direction), "{}: {} vs {}", a.name, a.direction, b.direction);
        if a.kind != LightKind::Directional {
            assert!(near(a.position, b.position), "{}: {} vs {}", a.name, a.position, b.position);
        }
    }
    assert_eq!(s.presets().iter().map(|p| &p.0).collect::<Vec<_>>(), back.presets().iter().map(|p| &p.0).collect::<Vec<_>>());
    for ((name, a), (_, b)) in s.presets().iter().zip(back.presets()) {
        assert!(a.view().abs_diff_eq(b.view(), 1e-5), "{name}: {:?} vs {:?}", a.view(), b.view());
        assert_eq!((a.fov_y, a.near, a.far), (b.fov_y, b.near, b.far), "{name}");
    }
    let (m, mb) = (&s.materials()[0], &back.materials()[0]);
    assert_eq!(mb.emissive, [8.0, 4.0, 0.0]);
    assert_eq!((mb.emissive, mb.occlusion_strength), (m.emissive, m.occlusion_strength));
    assert_eq!(back.textures()[mb.occlusion_texture.unwrap()].rgba, s.textures()[m.occlusion_texture.unwrap()].rgba);
}

fn real_asset(rel: &str) -> (Scene, ImportReport, String) {
    let (s, r) = load(&common::repo().join("assets/gltf").join(rel));
    let text = info::describe(&s, Some(&r));
    println!("{text}");
    (s, r, text)
}

fn alpha_counts(s: &Scene) -> (usize, usize, usize) {
    let count = |f: fn(&AlphaMode) -> bool| s.materials().iter().filter(|m| f(&m.alpha_mode)).count();
    (count(|a| *a == AlphaMode::Opaque), count(|a| matches!(a, AlphaMode::Mask(_))), count(|a| *a == AlphaMode::Blend))
}

#[test]
fn smallpine_reports_its_missing_atlas_normal_map_and_its_blended_leaves() {
    let (s, r, text) = real_asset("smallpine/scene.gltf");
    assert_eq!((s.triangle_count(), s.meshes().len(), s.materials().len()), (1650, 2, 2));
    assert_eq!((r.images_used, r.missing_images, s.textures().len()), (Some(5), 1, 4), "5 images used, the normal map missing");
    assert_eq!(alpha_counts(&s), (1, 0, 1));
    let f = &r.texture_fallbacks;
    assert_eq!(f.len(), 1);
    assert_eq!((f[0].material.as_str(), f[0].slot, f[0].image.as_str()), ("`M_TreeAtlas`", TextureSlot::Normal, "textures/M_TreeAtlas_normal.png"));
    let atlas = s.materials().iter().find(|m| m.name == "M_TreeAtlas").unwrap();
    assert_eq!(atlas.normal_texture, None, "the flat normal, not the magenta checker read as a normal map");
    assert_eq!(atlas.occlusion_texture, atlas.metallic_roughness_texture, "one packed image in two slots");
    assert!(atlas.texture.is_some() && atlas.occlusion_texture.is_some());
    assert!(text.contains("ignored     nothing"), "TEXCOORD_1 is read: {text}");
    assert!(s.meshes().iter().all(|m| m.extras.is_some()), "both meshes carry TEXCOORD_1");
    says(
        &text,
        &[
            "textures    5 (images the materials use: 4 loaded, 1 missing",
            "alpha       1 opaque, 0 mask, 1 blend",
            "fallbacks   1\n  material `M_TreeAtlas` normal texture: image `textures/M_TreeAtlas_normal.png`",
            "; no normal map (the flat normal)\n",
            "approximated 1\n  material `M_TreeAtlas`: alphaMode BLEND is blended in hybrid and full RT",
            "lights      none in the scene: the default sun",
            "cameras     front, top, side",
        ],
    );
}

#[test]
fn damaged_helmet_reports_five_textures_and_imports_every_slot() {
    let (s, r, text) = real_asset("DamagedHelmet/DamagedHelmet.glb");
    assert_eq!((s.triangle_count(), s.meshes().len(), s.materials().len()), (15_452, 1, 1));
    assert_eq!((r.images_used, r.missing_images, s.textures().len()), (Some(5), 0, 5));
    assert_eq!(alpha_counts(&s), (1, 0, 0));
    let m = &s.materials()[0];
    let slots = [m.texture, m.metallic_roughness_texture, m.normal_texture, m.occlusion_texture, m.emissive_texture];
    let mut distinct: Vec<usize> = slots.iter().map(|t| t.expect("every slot filled")).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), 5, "five slots, five images");
    assert_eq!((m.emissive, m.occlusion_strength), ([1.0; 3], 1.0));
    assert!(r.texture_fallbacks.is_empty() && r.approximated.is_empty() && r.ignored_features.is_empty(), "{r:?}");
    says(&text, &["textures    5 (images the materials use)\n", "fallbacks   nothing", "approximated nothing", "ignored     nothing"]);
}

/// `render` of the pine over two frames logs each fallback and each approximated or ignored
/// feature once, and a file's camera is a `--camera` preset.
#[test]
fn render_prints_the_notes_once_and_takes_a_files_camera() {
    let dir = temp_dir("render-notes");
    let render = |scene: &str, extra: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_raygraph"))
            .current_dir(common::repo())
            .args(["render", "--scene", scene, "--width", "32", "--height", "24", "--frames", "2", "--out"])
            .arg(dir.join("out.png"))
            .args(extra)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        stderr
    };
    let stderr = render("assets/gltf/smallpine/scene.gltf", &[]);
    println!("{stderr}");
    for once in ["M_TreeAtlas_normal.png", "approximated: material `M_TreeAtlas`: alphaMode BLEND"] {
        assert_eq!(stderr.matches(once).count(), 1, "`{once}` once in\n{stderr}");
    }
    let cams = cameras_document().write_glb(&dir, "cams");
    let stderr = render(cams.to_str().unwrap(), &["--camera", "side"]);
    assert_eq!(stderr.matches("camera `side`: infinite far plane").count(), 1, "{stderr}");
    let stderr = render(cams.to_str().unwrap(), &["--camera", "plan"]);
    assert!(!stderr.contains("orthographic camera `plan`"), "the orthographic camera is drawn, not skipped: {stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
