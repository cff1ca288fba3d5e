//! The specular lobes of KHR_materials_ior, KHR_materials_specular and KHR_materials_clearcoat
//! against closed-form answers (KHR_materials_transmission's compositing: tests/blend.rs).
//!
//! A black dielectric plate (base colour 0, so neither diffuse nor ambient light) seen head-on
//! under a light of intensity 0 shows only the sky reflected along the view axis: its HDR colour
//! at the image centre is F x sky, F the Fresnel reflectance at normal incidence:
//! - the core material: 0.04; `ior` n: ((n - 1) / (n + 1))²;
//! - with KHR_materials_specular: min(that x specularColorFactor, 1) x specularFactor;
//! - with a clear coat of weight c: F_base x (1 - 0.04 c) + 0.04 c.
//!
//! Checked in raster, hybrid and full RT (the hybrid and full-RT G-buffer marks the plate as
//! having its own lobes and keeps them in its `lobes` channel), with the factors alone and with
//! a texture in every lobe slot (the coat's normal map included). Also: the importer reads the
//! factors and textures, and the export writes them back.

mod common;

use common::{channel, gpu};
use glam::{Mat4, Vec3};
use raygraph::backend::Backend;
use raygraph::scene::{builtin, Camera, Instance, LightKind, Lobes, Material, Mesh, PunctualLight, Scene, TextureImage, Vertex};

const SIZE: (u32, u32) = (33, 33);

fn plate_scene(lobes: Lobes) -> Scene {
    let mut s = builtin::default_scene();
    s.set_name("plate");
    let v = |x: f32, y: f32| Vertex { position: [x, y, 0.0], normal: [0.0, 0.0, 1.0], uv: [0.0, 0.0] };
    s.set_meshes([Mesh {
        name: "plate".into(),
        vertices: vec![v(-4.0, -4.0), v(4.0, -4.0), v(4.0, 4.0), v(-4.0, 4.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    }]);
    *s.materials_mut() = vec![Material { roughness: 0.05, lobes, ..Material::diffuse("plate", [0.0, 0.0, 0.0, 1.0], None) }];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }];
    s.textures_mut().clear();
    *s.lights_mut() = vec![PunctualLight {
        name: "off".into(),
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Z,
        color: Vec3::ONE,
        intensity: 0.0,
    }];
    *s.camera_mut() = Camera {
        position: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 0.5,
        near: 0.05,
        far: 100.0,
        orthographic: None,
        aspect_ratio: None,
    };
    s
}

/// F at normal incidence, in f64 from the factors.
fn expected_reflectance(l: &Lobes) -> [f64; 3] {
    let r = ((l.ior as f64 - 1.0) / (l.ior as f64 + 1.0)).powi(2);
    let c = l.clearcoat as f64;
    l.specular_color.map(|k| (r * k as f64).min(1.0) * l.specular as f64 * (1.0 - 0.04 * c) + 0.04 * c)
}

#[test]
fn a_black_plate_reflects_the_sky_by_its_fresnel_reflectance_in_every_mode() {
    let gpu = gpu();
    // The sky along the view axis (dir.y = 0): common/lighting.wgsl's sky_color.
    let sky = [0.475f64, 0.525, 0.625];
    let cases = [
        ("core", Lobes::default()),
        ("ior 2", Lobes { ior: 2.0, ..Default::default() }),
        ("specular", Lobes { ior: 1.8, specular: 0.5, specular_color: [1.0, 0.5, 2.0], ..Default::default() }),
        ("clear coat", Lobes { ior: 2.2, clearcoat: 0.8, clearcoat_roughness: 0.1, ..Default::default() }),
    ];
    for (name, lobes) in cases {
        let scene = plate_scene(lobes);
        let f = expected_reflectance(&lobes);
        for (graph, resource) in [("graph/raster.ron", "forward.color"), ("graph/hybrid.ron", "resolve.hdr"), ("graph/full_rt.ron", "resolve.hdr")] {
            let exec = common::modes::render_graph(&gpu, graph, Backend::Compute, &scene, SIZE);
            let centre = channel(&gpu, &exec, resource)[(SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize];
            let got: Vec<f64> = (0..3).map(|k| centre[k] as f64 / sky[k]).collect();
            println!("{name}, {graph}: reflectance {got:.5?}, expected {f:.5?}");
            for k in 0..3 {
                // f16 output: 2^-11 relative, plus the Fresnel term's (1 - cos)^5 off the
                // exact centre (the centre pixel's ray is on the axis: 0).
                assert!((got[k] - f[k]).abs() <= 1e-3 * f[k].max(0.04), "{name}, {graph}, channel {k}: {} against {}", got[k], f[k]);
            }
        }
    }
}

/// A 2x2 texture of one texel value.
fn flat_texture(name: &str, rgba: [u8; 4]) -> TextureImage {
    TextureImage { name: name.into(), width: 2, height: 2, rgba: std::sync::Arc::new(rgba.repeat(4)) }
}

#[test]
fn the_lobe_textures_multiply_their_factors_and_the_coat_follows_its_normal_map_in_every_mode() {
    // The plate of the test above with a uv frame (u along x, v along y) and one texture per
    // lobe slot, each of one texel value: specularTexture's alpha and clearcoatTexture's red
    // 128/255 scale their factors; specularColorTexture (sRGB) multiplies the specular colour
    // by its decoded rgb; clearcoatNormalTexture tilts the coat's normal by about 60 degrees
    // about the v axis, so the coat reflects by its Fresnel term at that angle:
    // F = F_base x (1 - c Fc) + c Fc, Fc = 0.04 + 0.96 (1 - cos)^5.
    let gpu = gpu();
    let sky = [0.475f64, 0.525, 0.625];
    let factors = Lobes { ior: 1.8, specular: 0.9, specular_color: [1.0, 0.8, 1.5], clearcoat: 0.8, clearcoat_roughness: 0.5, ..Default::default() };
    let mut scene = plate_scene(factors);
    for v in &mut scene.mesh_mut(0).vertices {
        v.uv = [(v.position[0] + 4.0) / 8.0, (4.0 - v.position[1]) / 8.0];
    }
    let (half, colour, normal_texel) = (128u8, [255u8, 188, 128], [238u8, 128, 191]);
    *scene.textures_mut() = vec![
        flat_texture("specular", [0, 0, 0, half]),
        flat_texture("specular colour", [colour[0], colour[1], colour[2], 255]),
        flat_texture("clearcoat", [half, 0, 0, 255]),
        flat_texture("clearcoat roughness", [0, 200, 0, 255]),
        flat_texture("clearcoat normal", [normal_texel[0], normal_texel[1], normal_texel[2], 255]),
    ];
    scene.materials_mut()[0].lobes.textures = [Some(0), Some(1), Some(2), Some(3), Some(4), None];
    let scale = half as f64 / 255.0;
    let linear = colour.map(|c| raygraph::util::srgb_to_linear(c) as f64);
    let n = normal_texel.map(|c| 2.0 * c as f64 / 255.0 - 1.0);
    let cos = n[2] / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let coat = factors.clearcoat as f64 * scale;
    let fc = 0.04 + 0.96 * (1.0 - cos).powi(5);
    let r = ((factors.ior as f64 - 1.0) / (factors.ior as f64 + 1.0)).powi(2);
    let f: Vec<f64> =
        (0..3).map(|k| (r * factors.specular_color[k] as f64 * linear[k]).min(1.0) * factors.specular as f64 * scale * (1.0 - coat * fc) + coat * fc).collect();
    for (graph, resource) in [("graph/raster.ron", "forward.color"), ("graph/hybrid.ron", "resolve.hdr"), ("graph/full_rt.ron", "resolve.hdr")] {
        let exec = common::modes::render_graph(&gpu, graph, Backend::Compute, &scene, SIZE);
        let centre = channel(&gpu, &exec, resource)[(SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize];
        let got: Vec<f64> = (0..3).map(|k| centre[k] as f64 / sky[k]).collect();
        println!("lobe textures, {graph}: reflectance {got:.5?}, expected {f:.5?} (coat normal cosine {cos:.4})");
        for k in 0..3 {
            // Twice the bound above: the specular colour texel goes through the sampler's sRGB
            // decode, not the f64 formula (measured on lavapipe: 1.5e-3 relative at most, in
            // blue, hybrid and full RT; 1.0e-3 in raster).
            assert!((got[k] - f[k]).abs() <= 2e-3 * f[k].max(0.04), "{graph}, channel {k}: {} against {}", got[k], f[k]);
        }
    }
}

#[test]
fn the_importer_reads_the_lobe_factors_and_textures_and_the_export_writes_them_back() {
    use raygraph::scene::{LOBE_CLEARCOAT, LOBE_CLEARCOAT_NORMAL, LOBE_SPECULAR_COLOR, LOBE_TRANSMISSION};
    let dir = common::gltf_doc::temp_dir("lobes");
    let mut d = common::gltf_doc::Doc::new();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv = d.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 3);
    let t = d.texture_embedded(&common::gltf_doc::png(2, 2, [200, 100, 50, 255]));
    let material = d.material(serde_json::json!({
        "name": "lacquer",
        "extensions": {
            "KHR_materials_ior": {"ior": 1.7},
            "KHR_materials_specular": {"specularFactor": 0.6, "specularColorFactor": [1.0, 0.9, 0.8], "specularColorTexture": {"index": t}},
            "KHR_materials_clearcoat": {
                "clearcoatFactor": 0.9, "clearcoatRoughnessFactor": 0.3, "clearcoatTexture": {"index": t, "texCoord": 0},
                "clearcoatNormalTexture": {"index": t, "scale": 0.5}
            },
            "KHR_materials_transmission": {"transmissionFactor": 0.25, "transmissionTexture": {"index": t}}
        }
    }));
    let mesh = d.mesh(&[("POSITION", p), ("TEXCOORD_0", uv)], None, Some(material), None);
    d.node(serde_json::json!({"mesh": mesh}), true);
    d.json["extensionsUsed"] = serde_json::json!(["KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_transmission"]);
    let path = d.write_gltf_embedded(&dir, "lacquer");
    let (scene, report) = raygraph::scene::open(path.to_str().unwrap(), &Default::default()).unwrap();
    let lobes = scene.materials()[0].lobes;
    let factors = Lobes {
        ior: 1.7,
        specular: 0.6,
        specular_color: [1.0, 0.9, 0.8],
        clearcoat: 0.9,
        clearcoat_roughness: 0.3,
        transmission: 0.25,
        clearcoat_normal_scale: 0.5,
        ..Default::default()
    };
    assert_eq!(Lobes { textures: [None; 6], ..lobes }, factors);
    let read: Vec<usize> = (0..6).filter(|&k| lobes.textures[k].is_some()).collect();
    assert_eq!(read, [LOBE_SPECULAR_COLOR, LOBE_CLEARCOAT, LOBE_CLEARCOAT_NORMAL, LOBE_TRANSMISSION], "the lobe textures are read");
    // The transmission texture reads the base colour's uv (TEXCOORD_0, no transform): drawn.
    assert!(scene.materials()[0].transmission_texture_drawn());
    assert!(report.ignored_features.is_empty(), "{:?}", report.ignored_features);
    // On TEXCOORD_1 it is kept but not drawn, and said so.
    d.json["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionTexture"]["texCoord"] = serde_json::json!(1);
    let other = d.write_gltf_embedded(&dir, "lacquer_uv1");
    let (uv1, uv1_report) = raygraph::scene::open(other.to_str().unwrap(), &Default::default()).unwrap();
    assert!(!uv1.materials()[0].transmission_texture_drawn());
    assert!(uv1_report.ignored_features.iter().any(|f| f.contains("transmissionTexture")), "{:?}", uv1_report.ignored_features);
    let out = dir.join("again.glb");
    raygraph::scene::export::write_glb(&scene, &out).unwrap();
    let (again, _) = raygraph::scene::open(out.to_str().unwrap(), &Default::default()).unwrap();
    let back = again.materials()[0].lobes;
    assert_eq!(Lobes { textures: [None; 6], ..back }, factors, "the export writes the factors back");
    assert_eq!((0..6).filter(|&k| back.textures[k].is_some()).collect::<Vec<_>>(), read, "and the textures");
    let _ = std::fs::remove_dir_all(&dir);
}
