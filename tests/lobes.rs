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
//! having its own lobes; the resolve reads them from its material). Also: the importer reads the
//! factors and names the textures it does not read, and the export writes them back.

mod common;

use common::{channel, gpu};
use glam::{Mat4, Vec3};
use raygraph::backend::Backend;
use raygraph::scene::{builtin, Camera, Instance, LightKind, Lobes, Material, Mesh, PunctualLight, Scene, Vertex};

const SIZE: (u32, u32) = (33, 33);

fn plate_scene(lobes: Lobes) -> Scene {
    let mut s = builtin::default_scene();
    s.name = "plate".into();
    let v = |x: f32, y: f32| Vertex { position: [x, y, 0.0], normal: [0.0, 0.0, 1.0], uv: [0.0, 0.0] };
    s.meshes = vec![Mesh {
        name: "plate".into(),
        vertices: vec![v(-4.0, -4.0), v(4.0, -4.0), v(4.0, 4.0), v(-4.0, 4.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    }];
    s.materials = vec![Material { roughness: 0.05, lobes, ..Material::diffuse("plate", [0.0, 0.0, 0.0, 1.0], None) }];
    s.instances = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }];
    s.textures.clear();
    s.lights = vec![PunctualLight {
        name: "off".into(),
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Z,
        color: Vec3::ONE,
        intensity: 0.0,
    }];
    s.camera = Camera {
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

#[test]
fn the_importer_reads_the_lobe_and_transmission_factors_names_their_textures_and_the_export_writes_them_back() {
    let dir = common::gltf_doc::temp_dir("lobes");
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_transmission"],
        "materials": [{
            "name": "lacquer",
            "extensions": {
                "KHR_materials_ior": {"ior": 1.7},
                "KHR_materials_specular": {"specularFactor": 0.6, "specularColorFactor": [1.0, 0.9, 0.8]},
                "KHR_materials_clearcoat": {"clearcoatFactor": 0.9, "clearcoatRoughnessFactor": 0.3, "clearcoatTexture": {"index": 0}},
                "KHR_materials_transmission": {"transmissionFactor": 0.25}
            }
        }],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    let path = dir.join("lacquer.gltf");
    std::fs::write(&path, serde_json::to_string(&gltf).unwrap()).unwrap();
    let (scene, report) = raygraph::scene::open(path.to_str().unwrap(), &Default::default()).unwrap();
    let want = Lobes { ior: 1.7, specular: 0.6, specular_color: [1.0, 0.9, 0.8], clearcoat: 0.9, clearcoat_roughness: 0.3, transmission: 0.25 };
    assert_eq!(scene.materials[0].lobes, want);
    assert_eq!(report.ignored_features, ["material `lacquer`: KHR_materials_clearcoat clearcoatTexture (its factor alone is read)"]);
    let out = dir.join("again.glb");
    raygraph::scene::export::write_glb(&scene, &out).unwrap();
    let (again, _) = raygraph::scene::open(out.to_str().unwrap(), &Default::default()).unwrap();
    assert_eq!(again.materials[0].lobes, want, "the export writes the factors back");
    let _ = std::fs::remove_dir_all(&dir);
}
