//! `scene export OUT.xml` (src/scene/export_mitsuba.rs): the Mitsuba 3 XML of the built-in
//! scenes is well formed (a small tag parser: the project has no XML reader), has one shape
//! per instance, one emitter per light, the sky where the ambient is not 0, the camera; its PLY
//! files hold each instance's vertices in world space and its triangles; what cannot be
//! exported is a clear error.

use glam::Vec3;
use raygraph::scene::export_mitsuba::write_mitsuba;
use raygraph::scene::{open, LoadOptions, Scene, SceneError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One element: its name and attributes.
#[derive(Debug)]
struct Element {
    name: String,
    attributes: BTreeMap<String, String>,
}

/// The elements of `xml` in document order, after checking that every tag is closed in order
/// and that there is one root, `scene`.
fn parse_xml(xml: &str) -> Vec<Element> {
    let mut elements = Vec::new();
    let mut open_tags: Vec<String> = Vec::new();
    let mut roots = 0;
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        assert!(rest[..start].trim().is_empty() || !open_tags.is_empty(), "text outside the root: {}", &rest[..start]);
        rest = &rest[start..];
        if let Some(after) = rest.strip_prefix("<!--") {
            let end = after.find("-->").expect("an unterminated comment");
            rest = &after[end + 3..];
            continue;
        }
        let end = rest.find('>').expect("an unterminated tag");
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(open_tags.pop().as_deref(), Some(name.trim()), "a closing tag that does not match");
            continue;
        }
        let self_closing = tag.ends_with('/');
        let element = parse_tag(tag.trim_end_matches('/'));
        if open_tags.is_empty() {
            roots += 1;
            assert_eq!(element.name, "scene", "the root element");
        }
        if !self_closing {
            open_tags.push(element.name.clone());
        }
        elements.push(element);
    }
    assert!(open_tags.is_empty(), "unclosed tags: {open_tags:?}");
    assert_eq!(roots, 1, "one root element");
    elements
}

/// `name a="x" b="y"` as an element; attribute values must not hold `<`, `&` or quotes.
fn parse_tag(tag: &str) -> Element {
    let (name, mut rest) = tag.split_once(char::is_whitespace).unwrap_or((tag, ""));
    let mut attributes = BTreeMap::new();
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].trim().to_string();
        let value_start = rest[eq + 1..].find('"').expect("a quoted attribute") + eq + 2;
        let value_end = rest[value_start..].find('"').expect("a closing quote") + value_start;
        let value = &rest[value_start..value_end];
        assert!(!value.contains(['<', '&']), "attribute {key} holds an unescaped character: {value}");
        attributes.insert(key, value.to_string());
        rest = &rest[value_end + 1..];
    }
    assert!(rest.trim().is_empty(), "left in tag `{tag}`: {rest}");
    Element { name: name.to_string(), attributes }
}

fn attr<'a>(e: &'a Element, key: &str) -> &'a str {
    e.attributes.get(key).map(String::as_str).unwrap_or_else(|| panic!("{} has no {key}", e.name))
}

/// A fresh empty folder under the system's temporary folder.
fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raygraph-mitsuba-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The vertex count, face count and data of a binary PLY as the exporter writes it.
fn read_ply(path: &Path) -> (usize, usize, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header_end = bytes.windows(11).position(|w| w == b"end_header\n").expect("a PLY header") + 11;
    let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"), "{header}");
    let count = |element: &str| -> usize {
        let line = header.lines().find(|l| l.starts_with(&format!("element {element} "))).unwrap_or_else(|| panic!("no {element} element"));
        line.rsplit(' ').next().unwrap().parse().unwrap()
    };
    (count("vertex"), count("face"), bytes[header_end..].to_vec())
}

/// Exports `scene` and checks the XML and the PLY files against it.
fn check_export(scene: &Scene, dir: &Path) -> Vec<Element> {
    let xml_path = dir.join(format!("{}.xml", scene.name()));
    let export = write_mitsuba(scene, &xml_path).unwrap_or_else(|e| panic!("{e}"));
    let elements = parse_xml(&std::fs::read_to_string(&xml_path).unwrap());
    let shapes: Vec<&Element> = elements.iter().filter(|e| e.name == "shape").collect();
    assert_eq!(shapes.len(), scene.instances().len(), "one shape per instance");
    assert_eq!(export.shapes, scene.instances().len());
    let light_types = ["directional", "point", "spot"];
    let lights = elements.iter().filter(|e| e.name == "emitter" && light_types.contains(&attr(e, "type"))).count();
    assert_eq!(lights, scene.effective_lights().len(), "one emitter per light");
    let envmaps = elements.iter().filter(|e| e.name == "emitter" && attr(e, "type") == "envmap").count();
    assert_eq!(envmaps, usize::from(scene.light().ambient > 0.0), "the sky where the ambient is not 0");
    let bsdfs = elements.iter().filter(|e| e.name == "bsdf" && attr(e, "type") == "raygraph").count();
    assert_eq!(bsdfs, scene.materials().len(), "one raygraph BSDF per material");
    check_camera(scene, &elements);
    let filenames: Vec<&str> = elements.iter().filter(|e| e.name == "string" && attr(e, "name") == "filename").map(|e| attr(e, "value")).collect();
    for file in &filenames {
        assert!(dir.join(file).is_file(), "{file} is named in the XML but was not written");
    }
    for i in 0..scene.instances().len() {
        let ply = filenames.iter().find(|f| f.starts_with(&format!("{}_instance{i}_", scene.name()))).expect("the instance's PLY");
        check_ply(&dir.join(ply), scene, i);
    }
    elements
}

/// The perspective sensor has raygraph's vertical field of view and look-at.
fn check_camera(scene: &Scene, elements: &[Element]) {
    let sensors: Vec<&Element> = elements.iter().filter(|e| e.name == "sensor").collect();
    assert_eq!(sensors.len(), 1);
    assert_eq!(attr(sensors[0], "type"), "perspective");
    let float = |name: &str| -> f32 { attr(elements.iter().find(|e| e.name == "float" && attr(e, "name") == name).unwrap(), "value").parse().unwrap() };
    assert!((float("fov") - scene.camera().fov_y.to_degrees()).abs() < 1e-4, "fov");
    let fov_axis = elements.iter().find(|e| e.name == "string" && attr(e, "name") == "fov_axis").expect("fov_axis");
    assert_eq!(attr(fov_axis, "value"), "y", "raygraph's field of view is vertical");
    let lookat = elements.iter().find(|e| e.name == "lookat").expect("a lookat");
    let vec = |key: &str| -> Vec3 {
        let v: Vec<f32> = attr(lookat, key).split(',').map(|x| x.trim().parse().unwrap()).collect();
        Vec3::from_slice(&v)
    };
    assert_eq!(vec("origin"), scene.camera().position);
    assert_eq!(vec("target"), scene.camera().target);
    assert_eq!(vec("up"), scene.camera().up);
}

/// Instance `i`'s PLY: its mesh's vertex and triangle counts, positions in world space.
fn check_ply(path: &Path, scene: &Scene, i: usize) {
    let inst = &scene.instances()[i];
    let mesh = &scene.meshes()[inst.mesh];
    let (vertices, faces, data) = read_ply(path);
    assert_eq!(vertices, mesh.vertices.len(), "{}: vertex count", path.display());
    assert_eq!(faces, mesh.triangle_count(), "{}: face count", path.display());
    assert_eq!(data.len(), vertices * 8 * 4 + faces * (1 + 3 * 4), "{}: data size", path.display());
    let f = |k: usize| f32::from_le_bytes(data[k * 4..k * 4 + 4].try_into().unwrap());
    let last = vertices - 1;
    let expected = inst.transform.transform_point3(Vec3::from(mesh.vertices[last].position));
    let written = Vec3::new(f(last * 8), f(last * 8 + 1), f(last * 8 + 2));
    assert!((written - expected).length() < 1e-5, "{}: last vertex {written} != {expected}", path.display());
    let face_data = &data[vertices * 32..];
    assert!(face_data.chunks_exact(13).all(|c| c[0] == 3), "triangles");
    let index = |t: usize, k: usize| i32::from_le_bytes(face_data[t * 13 + 1 + 4 * k..t * 13 + 5 + 4 * k].try_into().unwrap()) as u32;
    let mirrored = inst.transform.determinant() < 0.0;
    let first = if mirrored { [index(0, 0), index(0, 2), index(0, 1)] } else { [index(0, 0), index(0, 1), index(0, 2)] };
    assert_eq!(first.as_slice(), &mesh.indices[..3], "the first triangle");
}

fn builtin(name: &str) -> Scene {
    open(name, &LoadOptions { textures: true, ..Default::default() }).unwrap_or_else(|e| panic!("{e}")).0
}

#[test]
fn builtin_scenes_export_to_mitsuba() {
    for name in ["box", "default"] {
        let dir = temp_dir(name);
        let scene = builtin(name);
        let elements = check_export(&scene, &dir);
        let textures = elements.iter().filter(|e| e.name == "texture").count();
        let expected = scene.materials().iter().map(|m| [m.texture, m.metallic_roughness_texture, m.normal_texture].iter().flatten().count()).sum::<usize>();
        assert_eq!(textures, expected, "{name}: a bitmap per base-colour, metallic-roughness and normal texture");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn emissive_materials_become_area_emitters_and_ambient_zero_has_no_sky() {
    let dir = temp_dir("emissive");
    let mut scene = builtin("default");
    scene.light_mut().ambient = 0.0;
    scene.materials_mut()[2].emissive = [2.0, 1.0, 0.5];
    let elements = check_export(&scene, &dir);
    let areas: Vec<&Element> = elements.iter().filter(|e| e.name == "emitter" && attr(e, "type") == "area").collect();
    assert_eq!(areas.len(), scene.instances().iter().filter(|i| i.material == 2).count(), "one area emitter per emissive instance");
    let radiance = elements.iter().find(|e| e.name == "rgb" && attr(e, "name") == "radiance").expect("the area emitter's radiance");
    assert_eq!(attr(radiance, "value"), "2 1 0.5");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn light_units_are_converted_from_the_radiance_scale() {
    let dir = temp_dir("units");
    let scene = builtin("default");
    let elements = check_export(&scene, &dir);
    let irradiance = elements.iter().find(|e| e.name == "rgb" && attr(e, "name") == "irradiance").expect("the sun's irradiance");
    let light = scene.light();
    let expected = light.color * light.intensity * std::f32::consts::PI;
    let written: Vec<f32> = attr(irradiance, "value").split(' ').map(|x| x.parse().unwrap()).collect();
    assert!((Vec3::from_slice(&written) - expected).length() < 1e-5, "irradiance pi x colour x intensity: {written:?} vs {expected}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn what_cannot_be_exported_is_a_clear_error() {
    let dir = temp_dir("errors");
    let mut scene = builtin("box");
    scene.camera_mut().orthographic = Some(2.0);
    let path = dir.join("ortho.xml");
    let err = write_mitsuba(&scene, &path).expect_err("an orthographic camera");
    assert!(matches!(err, SceneError::Write { .. }));
    let message = err.to_string();
    assert!(message.contains("ortho.xml") && message.contains("orthographic"), "{message}");
    assert!(!path.exists(), "no XML is left behind");
    let missing = dir.join("no-such-folder").join("x.xml");
    let message = write_mitsuba(&builtin("box"), &missing).expect_err("a missing folder").to_string();
    assert!(message.contains("no-such-folder"), "{message}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn normal_maps_go_to_the_raygraph_bsdf_with_their_scale() {
    let dir = temp_dir("normals");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/khronos/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf");
    let scene = open(path.to_str().unwrap(), &LoadOptions { textures: true, ..Default::default() }).unwrap_or_else(|e| panic!("{e}")).0;
    let normal_mapped: Vec<f32> = scene.materials().iter().filter(|m| m.normal_texture.is_some()).map(|m| m.normal_scale).collect();
    assert!(!normal_mapped.is_empty(), "the asset has normal maps");
    let elements = check_export(&scene, &dir);
    // The plugin applies the map as raygraph's shaders do (mirrored uvs included), so Mitsuba's
    // own `normalmap` BSDF, which reads mirrored uvs with one axis flipped, is not used.
    assert!(!elements.iter().any(|e| e.name == "bsdf" && attr(e, "type") == "normalmap"), "no normalmap BSDF");
    let maps: Vec<usize> = (0..elements.len()).filter(|&i| elements[i].name == "texture" && attr(&elements[i], "name") == "normal_texture").collect();
    assert_eq!(maps.len(), normal_mapped.len(), "a normal_texture per normal-mapped material");
    for &i in &maps {
        let raw = elements[i..].iter().find(|e| e.name == "boolean" && attr(e, "name") == "raw").expect("the texture's raw flag");
        assert_eq!(attr(raw, "value"), "true", "a normal map is data, not sRGB");
    }
    let scales: Vec<f32> =
        elements.iter().filter(|e| e.name == "float" && attr(e, "name") == "normal_scale").map(|e| attr(e, "value").parse().expect("a number")).collect();
    assert_eq!(scales, normal_mapped, "each material's normal scale, in order");
    let _ = std::fs::remove_dir_all(&dir);
}
