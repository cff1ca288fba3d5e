//! glTF import from documents the tests write themselves (every attribute type and index
//! width, node hierarchy, instancing, materials, samplers, external / embedded / GLB buffers),
//! export round trips of the built-in scenes, duplication, camera presets and tracks, and
//! every class of bad input (an error naming the file, or a counted warning; never a panic).

mod common;

use common::gltf_doc::{png, temp_dir, Doc, BYTE, SHORT_U};
use glam::{Mat4, Quat, Vec3};
use raygraph::scene::gltf_import::{self, SceneError};
use raygraph::scene::track::{Key, Track};
use raygraph::scene::{duplicate::duplicate, export, open, AlphaMode, Camera, LoadOptions, Scene};
use serde_json::json;
use std::path::Path;

fn load(path: &Path) -> (Scene, raygraph::scene::ImportReport) {
    gltf_import::load(path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The document covering every attribute and index type. `dir` receives its external images.
fn full_document(dir: &Path) -> Doc {
    std::fs::write(dir.join("red.png"), png(4, 4, [255, 0, 0, 255])).unwrap();
    std::fs::write(dir.join("mr.png"), png(2, 2, [0, 128, 255, 255])).unwrap();
    let mut d = Doc::new();
    // Textures: two external PNGs, one embedded in the buffer, one more external.
    let t_base = d.texture_uri("red.png");
    let t_mr = d.texture_uri("mr.png");
    let t_normal = d.texture_embedded(&png(2, 2, [128, 128, 255, 255]));
    let t_emissive = t_base; // one texture used twice: loaded once
    let m_full = d.material(json!({
        "name": "full",
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.25, 1.0, 1.0],
            "baseColorTexture": {"index": t_base},
            "metallicFactor": 0.75, "roughnessFactor": 0.125,
            "metallicRoughnessTexture": {"index": t_mr}
        },
        "normalTexture": {"index": t_normal, "scale": 0.5},
        "emissiveTexture": {"index": t_emissive},
        "emissiveFactor": [1.0, 0.5, 0.0],
        "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true
    }));
    let m_blend = d.material(json!({"name": "glass", "alphaMode": "BLEND"}));
    let m_plain = d.material(json!({"name": "plain", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.8, 0.2, 1.0]}}));

    // Mesh A: a quad with float normals, tangents and uvs, u8 indices.
    let pa = d.positions(&[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
    let na = d.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3", 4);
    let ta = d.floats(&[1.0, 0.0, 0.0, 1.0].repeat(4), "VEC4", 4);
    let ua = d.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 4);
    let ia = d.indices_u8(&[0, 1, 2, 0, 2, 3]);
    let mesh_a = d.mesh(&[("POSITION", pa), ("NORMAL", na), ("TANGENT", ta), ("TEXCOORD_0", ua)], Some(ia), Some(m_full), None);
    // Mesh B: a triangle with normalized u16 uvs, no normals (generated), u16 indices.
    let pb = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]);
    let uv16: [u16; 6] = [0, 0, 65535, 0, 0, 65535];
    let ub = d.accessor(bytemuck::cast_slice(&uv16), SHORT_U, "VEC2", 3, true, None);
    let ib = d.indices_u16(&[0, 1, 2]);
    let mesh_b = d.mesh(&[("POSITION", pb), ("TEXCOORD_0", ub)], Some(ib), Some(m_blend), None);
    // Mesh C: normalized u8 uvs, u32 indices, a normal map but no tangents (generated).
    let pc = d.positions(&[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
    let uv8: [u8; 6] = [0, 0, 255, 0, 0, 255];
    let uc = d.accessor(&uv8, BYTE, "VEC2", 3, true, None);
    let ic = d.indices_u32(&[0, 1, 2]);
    let mesh_c = d.mesh(&[("POSITION", pc), ("TEXCOORD_0", uc)], Some(ic), Some(m_full), None);
    // Mesh D: not indexed, no material (the default material).
    let pd = d.positions(&[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let mesh_d = d.mesh(&[("POSITION", pd)], None, None, None);
    // Mesh E: lines, skipped with a warning.
    let pe = d.positions(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let mesh_e = d.mesh(&[("POSITION", pe)], None, Some(m_plain), Some(1));

    // Hierarchy: root translated by (10, 0, 0) with two children sharing mesh A.
    let c1 = d.node(json!({"mesh": mesh_a, "scale": [2.0, 2.0, 2.0]}), false);
    let c2 = d.node(json!({"mesh": mesh_a, "rotation": [0.0, 0.70710677, 0.0, 0.70710677], "translation": [0.0, 3.0, 0.0]}), false);
    d.node(json!({"name": "root", "translation": [10.0, 0.0, 0.0], "children": [c1, c2]}), true);
    let m = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0)).to_cols_array();
    d.node(json!({"mesh": mesh_b, "matrix": m}), true);
    d.node(json!({"mesh": mesh_c}), true);
    d.node(json!({"mesh": mesh_d}), true);
    d.node(json!({"mesh": mesh_e}), true);
    d
}

fn check_full_document(s: &Scene, r: &raygraph::scene::ImportReport) {
    assert_eq!(s.meshes().len(), 4, "one mesh per triangle primitive (the lines primitive is skipped)");
    assert_eq!(r.skipped_primitives, 1);
    assert_eq!(s.instances().len(), 5, "mesh A is instanced twice, not copied");
    assert_eq!(s.triangle_count(), 2 + 2 + 1 + 1 + 1);
    assert_eq!(s.textures().len(), 3, "three distinct images (one used twice)");
    assert_eq!(s.materials().len(), 4, "three materials and the default");

    // Transforms through the hierarchy.
    let a: Vec<_> = s.instances().iter().filter(|i| s.meshes()[i.mesh].triangle_count() == 2).collect();
    assert_eq!(a.len(), 2);
    assert_eq!(a[0].mesh, a[1].mesh);
    let corner = |t: &Mat4| t.transform_point3(Vec3::new(1.0, 1.0, 0.0));
    let expect1 = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(2.0));
    let expect2 = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0))
        * Mat4::from_rotation_translation(Quat::from_rotation_y(std::f32::consts::FRAC_PI_2), Vec3::new(0.0, 3.0, 0.0));
    let got: Vec<Vec3> = a.iter().map(|i| corner(&i.transform)).collect();
    for want in [corner(&expect1), corner(&expect2)] {
        assert!(got.iter().any(|g| g.distance(want) < 1e-5), "want {want}, got {got:?}");
    }
    let b = s.instances().iter().find(|i| s.materials()[i.material].name == "glass").unwrap();
    assert!(b.transform.transform_point3(Vec3::ZERO).distance(Vec3::new(0.0, 0.0, -5.0)) < 1e-6);

    // Materials.
    let full = s.materials().iter().find(|m| m.name == "full").unwrap();
    assert_eq!(full.base_color, [0.5, 0.25, 1.0, 1.0]);
    assert_eq!((full.metallic, full.roughness, full.normal_scale), (0.75, 0.125, 0.5));
    assert_eq!(full.emissive, [1.0, 0.5, 0.0]);
    assert_eq!(full.alpha_mode, AlphaMode::Mask(0.3));
    assert!(full.double_sided);
    assert_eq!(full.texture, full.emissive_texture, "one image, one texture");
    let base = &s.textures()[full.texture.unwrap()];
    assert_eq!((base.width, base.height), (4, 4));
    assert_eq!(&base.rgba[0..4], &[255, 0, 0, 255]);
    let mr = &s.textures()[full.metallic_roughness_texture.unwrap()];
    assert_eq!(&mr.rgba[0..4], &[0, 128, 255, 255]);
    let normal = &s.textures()[full.normal_texture.unwrap()];
    assert_eq!(&normal.rgba[0..4], &[128, 128, 255, 255], "the embedded image decodes");
    assert_eq!(s.materials().iter().find(|m| m.name == "glass").unwrap().alpha_mode, AlphaMode::Blend);

    // Attributes.
    let mesh_of = |mat: &str, tris: usize| {
        let i = s.instances().iter().find(|i| s.materials()[i.material].name == mat && s.meshes()[i.mesh].triangle_count() == tris).unwrap();
        &s.meshes()[i.mesh]
    };
    let ma = mesh_of("full", 2);
    assert_eq!(ma.tangents.as_ref().unwrap()[0], [1.0, 0.0, 0.0, 1.0], "tangents read as given");
    assert_eq!(ma.vertices[1].uv, [1.0, 1.0]);
    let mb = mesh_of("glass", 1);
    assert_eq!(mb.vertices[1].uv, [1.0, 0.0], "normalized u16 uv");
    for v in &mb.vertices {
        assert!(Vec3::from(v.normal).distance(Vec3::Y) < 1e-6, "generated normal {:?} of a ccw triangle in the xz plane facing +y", v.normal);
    }
    assert!(mb.tangents.is_none(), "no normal map, no tangents");
    let mc = mesh_of("full", 1);
    assert_eq!(mc.vertices[2].uv, [0.0, 1.0], "normalized u8 uv");
    let tc = mc.tangents.as_ref().expect("tangents generated for a normal-mapped mesh");
    assert!(Vec3::new(tc[0][0], tc[0][1], tc[0][2]).distance(Vec3::X) < 1e-5, "tangent follows +u: {:?}", tc[0]);
    let md = s.meshes().iter().find(|m| m.indices == vec![0, 1, 2] && m.vertices[1].position == [0.0, 1.0, 0.0]).expect("non-indexed mesh D");
    assert!(Vec3::from(md.vertices[0].normal).distance(Vec3::X) < 1e-6);
    let default_mat = s.instances().iter().find(|i| i.mesh == s.meshes().iter().position(|m| std::ptr::eq(m, md)).unwrap()).unwrap().material;
    assert_eq!(s.materials()[default_mat].name, "default");
}

#[test]
fn imports_every_attribute_and_index_type_from_gltf_gltf_embedded_and_glb() {
    let dir = temp_dir("gltf-full");
    let doc = full_document(&dir);
    for path in [doc.write_gltf_external(&dir, "external"), doc.write_gltf_embedded(&dir, "embedded"), doc.write_glb(&dir, "binary")] {
        let (s, r) = load(&path);
        println!("{}: {} warnings: {:?}", path.display(), r.warnings.len(), r.warnings);
        check_full_document(&s, &r);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_graph_without_textures_loads_none() {
    let dir = temp_dir("gltf-notex");
    let path = full_document(&dir).write_glb(&dir, "doc");
    let (s, r) = gltf_import::load(&path, &LoadOptions { textures: false, ..Default::default() }).unwrap();
    assert!(s.textures().is_empty());
    assert!(s.materials().iter().all(|m| m.texture.is_none() && m.normal_texture.is_none()));
    assert_eq!(r.textures_not_loaded, 4, "base, metallic-roughness, normal and emissive references");
    let (atrium, r) = open("box", &LoadOptions { textures: false, ..Default::default() }).unwrap();
    assert!(atrium.textures().is_empty() && r.textures_not_loaded > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// World-space triangles of a scene, sorted, as bit patterns rounded to 1e-5.
fn world_triangles(s: &Scene) -> Vec<[i64; 9]> {
    let mut out = Vec::new();
    for inst in s.instances().iter() {
        let m = &s.meshes()[inst.mesh];
        for t in m.indices.chunks_exact(3) {
            let mut tri = [0i64; 9];
            for (k, &i) in t.iter().enumerate() {
                let p = inst.transform.transform_point3(Vec3::from(m.vertices[i as usize].position));
                for c in 0..3 {
                    tri[k * 3 + c] = (p[c] as f64 * 1e5).round() as i64;
                }
            }
            out.push(tri);
        }
    }
    out.sort_unstable();
    out
}

#[test]
fn built_in_scenes_export_and_import_back_to_the_same_triangles() {
    let dir = temp_dir("export");
    for name in ["default", "box", "organic", "atrium"] {
        let (s, _) = open(name, &LoadOptions::default()).unwrap();
        let path = dir.join(format!("{name}.glb"));
        export::write_glb(&s, &path).unwrap();
        let (back, report) = load(&path);
        println!(
            "{name}: {} triangles, {} meshes, {} textures -> {} bytes",
            s.triangle_count(),
            s.meshes().len(),
            s.textures().len(),
            std::fs::metadata(&path).unwrap().len()
        );
        assert_eq!(back.triangle_count(), s.triangle_count(), "{name}");
        assert_eq!(back.textures().len(), s.textures().len(), "{name}");
        assert_eq!(back.instances().len(), s.instances().len(), "{name}");
        assert_eq!(report.non_finite_triangles + report.skipped_primitives + report.missing_images, 0);
        assert!(world_triangles(&back) == world_triangles(&s), "{name}: triangles differ after the round trip");
        for (a, b) in s.textures().iter().zip(back.textures()) {
            assert!(a.rgba == b.rgba, "{name}: texture {} changed", a.name);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn duplication_copies_the_scene_on_a_grid_with_and_without_shared_meshes() {
    let (s, _) = open("organic", &LoadOptions { textures: false, ..Default::default() }).unwrap();
    let shared = duplicate(&s, 3, true);
    let owned = duplicate(&s, 3, false);
    for d in [&shared, &owned] {
        assert_eq!(d.instances().len(), 27 * s.instances().len());
        assert_eq!(d.triangle_count(), 27 * s.triangle_count());
    }
    assert_eq!(shared.meshes().len(), s.meshes().len(), "de-duplication on: copies share meshes");
    assert_eq!(owned.meshes().len(), 27 * s.meshes().len(), "de-duplication off: every copy owns its meshes");
    assert_eq!(world_triangles(&shared), world_triangles(&owned));
    // Copies do not overlap: the grid spans 3 extents plus gaps on every axis.
    let (b, g) = (s.bounds(), shared.bounds());
    let ratio = (g.max - g.min) / (b.max - b.min);
    assert!(ratio.min_element() > 3.0 && ratio.max_element() < 3.4, "{ratio}");
    assert_eq!(duplicate(&s, 1, true).triangle_count(), s.triangle_count());
}

#[test]
fn camera_presets_are_named_and_unknown_ones_are_listed() {
    for name in raygraph::scene::load::BUILTIN_NAMES {
        let (s, _) = open(name, &LoadOptions { textures: false, ..Default::default() }).unwrap();
        assert!(s.presets().len() >= 3, "{name}");
        assert_eq!(s.presets()[0].1, *s.camera(), "{name}: the first preset is the default camera");
        for (n, c) in s.presets() {
            assert!(c.position.is_finite() && c.position.distance(c.target) > 1e-3, "{name}/{n}");
        }
        let err = s.preset("nowhere").unwrap_err();
        assert!(err.contains(&s.presets()[0].0), "{err}");
    }
}

#[test]
fn camera_tracks_round_trip_and_play_back_by_frame_index() {
    let dir = temp_dir("track");
    let base = Camera::default();
    let mut t = Track::new(30.0);
    for (i, x) in [0.0f32, 2.0, 4.0, 4.0].iter().enumerate() {
        let c = Camera { position: Vec3::new(*x, 1.0, 5.0 - i as f32), target: Vec3::new(*x, 0.0, 0.0), ..base };
        t.record(i as f32 * 0.5, &c);
    }
    let path = dir.join("t.ron");
    t.save(&path).unwrap();
    assert!(std::fs::read_dir(&dir).unwrap().count() == 1, "no temporary file left behind");
    let back = Track::load(&path).unwrap();
    assert_eq!(back, t);
    assert_eq!(back.frame_count(), 46);
    // Key-frames are hit exactly at their times; playback is a pure function of the index.
    for (i, k) in t.keys.iter().enumerate() {
        let c = back.camera_at_frame(i as u32 * 15, &base);
        assert!(c.position.distance(Vec3::from(k.position)) < 1e-5, "key {i}");
    }
    let a: Vec<Camera> = (0..46).map(|f| back.camera_at_frame(f, &base)).collect();
    let b: Vec<Camera> = (0..46).map(|f| back.camera_at_frame(f, &base)).collect();
    assert_eq!(a, b);
    // Between keys 0 and 1 the camera moves forward in x; past the end it holds the last key.
    assert!(a[7].position.x > 0.5 && a[7].position.x < 1.5, "{}", a[7].position);
    assert_eq!(back.camera_at_frame(1000, &base).position, Vec3::from(t.keys[3].position));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn malformed_tracks_are_errors_naming_the_file() {
    let dir = temp_dir("badtrack");
    let cases = [
        ("syntax.ron", "Track(fps: 30.0, keys: [Key(time: 0.0,,]"),
        ("empty.ron", "Track(fps: 30.0, keys: [])"),
        ("backwards.ron", "Track(fps: 30.0, keys: [Key(time: 1.0, position: (0,0,1), target: (0,0,0), fov_y_deg: 50), Key(time: 0.5, position: (0,0,1), target: (0,0,0), fov_y_deg: 50)])"),
        ("nan.ron", "Track(fps: 30.0, keys: [Key(time: 0.0, position: (NaN,0,1), target: (0,0,0), fov_y_deg: 50)])"),
        ("fov.ron", "Track(fps: 30.0, keys: [Key(time: 0.0, position: (0,0,1), target: (0,0,0), fov_y_deg: 0)])"),
        ("fps.ron", "Track(fps: 0.0, keys: [Key(time: 0.0, position: (0,0,1), target: (0,0,0), fov_y_deg: 50)])"),
    ];
    for (name, text) in cases {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let e = Track::load(&p).expect_err(name).to_string();
        println!("{e}");
        assert!(e.contains(&p.display().to_string()), "{e}");
    }
    let e = Track::load(&dir.join("missing.ron")).unwrap_err().to_string();
    assert!(e.contains("missing.ron"), "{e}");
    // Saving into a directory that does not exist fails and leaves nothing.
    let t = Track { fps: 30.0, keys: vec![Key { time: 0.0, position: (0.0, 0.0, 1.0), target: (0.0, 0.0, 0.0), fov_y_deg: 50.0 }] };
    assert!(t.save(&dir.join("no/such/dir/t.ron")).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

// ------------------------------------------------------------------------------------------
// Bad input
// ------------------------------------------------------------------------------------------

fn triangle_doc(positions: &[[f32; 3]], indices: &[u16]) -> Doc {
    let mut d = Doc::new();
    let p = d.positions(positions);
    let i = d.indices_u16(indices);
    let m = d.mesh(&[("POSITION", p)], Some(i), None, None);
    d.node(json!({"mesh": m}), true);
    d
}

fn load_err(path: &Path) -> String {
    match gltf_import::load(path, &LoadOptions::default()) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => {
            let msg = e.to_string();
            println!("{msg}");
            assert!(msg.contains(&path.display().to_string()), "the error names the file: {msg}");
            msg
        }
    }
}

#[test]
fn truncated_and_non_gltf_files_are_errors() {
    let dir = temp_dir("bad-files");
    let glb = full_document(&dir).glb_bytes();
    for cut in [10, glb.len() / 3, glb.len() - 7] {
        let p = dir.join(format!("cut{cut}.glb"));
        std::fs::write(&p, &glb[..cut]).unwrap();
        load_err(&p);
    }
    let p = dir.join("text.gltf");
    std::fs::write(&p, "this is not json").unwrap();
    load_err(&p);
    let p = dir.join("empty.glb");
    std::fs::write(&p, []).unwrap();
    load_err(&p);
    load_err(&dir.join("does-not-exist.glb"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_buffer_is_an_error_naming_its_uri() {
    let dir = temp_dir("bad-buffer");
    let path = triangle_doc(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2]).write_gltf_external(&dir, "doc");
    std::fs::remove_file(dir.join("doc.bin")).unwrap();
    let e = load_err(&path);
    assert!(e.contains("doc.bin"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_or_undecodable_images_warn_and_use_a_visible_fallback() {
    let dir = temp_dir("bad-image");
    std::fs::write(dir.join("garbage.png"), b"not a png at all").unwrap();
    let mut d = triangle_doc(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2]);
    let t1 = d.texture_uri("nowhere.png");
    let t2 = d.texture_uri("garbage.png");
    d.material(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": t1}, "metallicRoughnessTexture": {"index": t2}}}));
    d.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    let path = d.write_gltf_external(&dir, "doc");
    let (s, r) = load(&path);
    assert_eq!(r.missing_images, 2);
    assert_eq!(r.warnings.iter().filter(|w| w.contains("fallback")).count(), 2, "{:?}", r.warnings);
    assert_eq!(s.triangle_count(), 1, "loading went on");
    let fallback = &s.textures()[s.materials()[0].texture.unwrap()];
    assert_eq!(&fallback.rgba[0..4], &[255, 0, 255, 255], "magenta marks the missing texture");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn out_of_range_indices_are_an_error_with_the_numbers() {
    let dir = temp_dir("bad-index");
    let path = triangle_doc(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 7]).write_glb(&dir, "doc");
    let e = load_err(&path);
    assert!(e.contains("index 7") && e.contains("3 vertices"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn nan_and_infinite_positions_drop_their_triangles_and_zero_area_ones_are_counted() {
    let dir = temp_dir("bad-nan");
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 0.0], [2.0, 0.0, 0.0]];
    // Triangles: good, NaN, Inf, zero-area (collinear), good again.
    let path = triangle_doc(&p, &[0, 1, 2, 0, 3, 1, 4, 1, 2, 0, 1, 5, 2, 1, 5]).write_glb(&dir, "doc");
    let (s, r) = load(&path);
    assert_eq!(r.non_finite_triangles, 2);
    assert_eq!(r.degenerate_triangles, 1);
    assert_eq!(s.triangle_count(), 3, "NaN/Inf triangles dropped, the zero-area one kept for drawing");
    for m in s.meshes() {
        for v in &m.vertices {
            assert!(v.position.iter().chain(&v.normal).chain(&v.uv).all(|c| c.is_finite()), "a non-finite value would be uploaded: {v:?}");
        }
    }
    assert!(r.warnings.iter().any(|w| w.contains("dropped 2 triangles")), "{:?}", r.warnings);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn non_triangle_primitives_are_skipped_with_a_warning_and_strips_and_fans_kept() {
    let dir = temp_dir("bad-mode");
    let mut d = Doc::new();
    let p = d.positions(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    for mode in [0, 1, 2, 3] {
        let m = d.mesh(&[("POSITION", p)], None, None, Some(mode));
        d.node(json!({"mesh": m}), true);
    }
    // Triangles, a strip and a fan are all triangles.
    for mode in [4, 5, 6] {
        let m = d.mesh(&[("POSITION", p)], None, None, Some(mode));
        d.node(json!({"mesh": m}), true);
    }
    let (s, r) = load(&d.write_glb(&dir, "doc"));
    assert_eq!(r.skipped_primitives, 4);
    assert_eq!(r.warnings.iter().filter(|w| w.contains("not triangles")).count(), 4);
    assert_eq!(s.triangle_count(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_scene_names_list_the_built_in_ones() {
    let e = open("sponza", &LoadOptions::default()).unwrap_err();
    assert!(matches!(e, SceneError::UnknownScene(..)));
    let msg = e.to_string();
    assert!(msg.contains("atrium") && msg.contains("organic") && msg.contains("box"), "{msg}");
}
