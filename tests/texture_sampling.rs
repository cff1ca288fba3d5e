//! Texture slots sampled as glTF says: wrap modes per axis (REPEAT, CLAMP_TO_EDGE,
//! MIRRORED_REPEAT), NEAREST filtering and `KHR_texture_transform`, in the fragment stage, at
//! primary-ray hits and over the visibility buffer, with textures as a binding array and as the
//! resampled texture array; checked texel by texel against an independent CPU lookup. Also the
//! import of the Khronos TextureSettingsTest's samplers and TextureTransformTest's transforms.

mod common;

use common::{gpu, repo};
use glam::{Mat4, Vec3};
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions, Project};
use raygraph::runtime::Executor;
use raygraph::scene::{Camera, Instance, LoadOptions, Material, Mesh, Mipmaps, Scene, SlotSampling, TextureImage, Vertex, VertexExtra, Wrap};

/// 4 x 4 texels, each its own colour (sRGB bytes).
fn texel(i: usize, j: usize) -> [u8; 4] {
    [(30 + 60 * i) as u8, (30 + 60 * j) as u8, (220 - 25 * (i + j)) as u8, 255]
}

fn checker() -> TextureImage {
    let rgba: Vec<u8> = (0..4).flat_map(|j| (0..4).flat_map(move |i| texel(i, j))).collect();
    TextureImage { name: "4x4".into(), width: 4, height: 4, rgba: rgba.into() }
}

/// Uv range the quad spans on each axis: from -1 to 2, three copies of the texture.
const UV_MIN: f32 = -1.0;
const UV_SPAN: f32 = 3.0;

/// A unit quad in the xy plane facing +z, uv from (-1, -1) at its top left to (2, 2) at its
/// bottom right, textured with [`checker`] through `sampling`, seen by an orthographic camera
/// that it fills exactly.
fn quad_scene(sampling: SlotSampling) -> Scene {
    let vertex = |x: f32, y: f32| Vertex { position: [x, y, 0.0], normal: [0.0, 0.0, 1.0], uv: [UV_MIN + UV_SPAN * x, UV_MIN + UV_SPAN * (1.0 - y)] };
    let mesh = Mesh {
        name: "quad".into(),
        vertices: vec![vertex(0.0, 0.0), vertex(1.0, 0.0), vertex(1.0, 1.0), vertex(0.0, 1.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        tangents: None,
        extras: None,
    };
    let mut material = Material::diffuse("sampled", [1.0; 4], Some(0));
    material.sampling[0] = sampling;
    let mut scene = raygraph::scene::builtin::default_scene();
    scene.set_meshes([mesh]);
    *scene.materials_mut() = vec![material];
    *scene.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }];
    *scene.textures_mut() = vec![checker()];
    scene.set_rig(None);
    *scene.camera_mut() = Camera { orthographic: Some(0.5), ..Camera::look(Vec3::new(0.5, 0.5, 2.0), Vec3::new(0.5, 0.5, 0.0), 45.0, 0.5, 4.0) };
    scene
}

/// The texel index `t` (a texel coordinate, not yet whole) of a 4-texel axis wrapped by `wrap`,
/// or `None` within 0.05 texel of a texel edge (either neighbour may be read there in f32).
fn wrapped(t: f32, wrap: Wrap) -> Option<usize> {
    let f = t.floor();
    if t - f < 0.05 || t - f > 0.95 {
        return None;
    }
    let f = f as i64;
    Some(match wrap {
        Wrap::Repeat => f.rem_euclid(4),
        Wrap::ClampToEdge => f.clamp(0, 3),
        Wrap::MirroredRepeat => {
            let k = f.rem_euclid(8);
            if k >= 4 {
                7 - k
            } else {
                k
            }
        }
    } as usize)
}

/// The linear albedo each pixel of a `size` x `size` frame should show (`None`: near a texel
/// edge, not checked).
fn expected(sampling: &SlotSampling, size: u32) -> Vec<Option<[f32; 3]>> {
    let srgb = |b: u8| {
        let c = b as f64 / 255.0;
        (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as f32
    };
    (0..size * size)
        .map(|p| {
            let (x, y) = ((p % size) as f32 + 0.5, (p / size) as f32 + 0.5);
            let uv = sampling.apply([UV_MIN + UV_SPAN * x / size as f32, UV_MIN + UV_SPAN * y / size as f32]);
            let (i, j) = (wrapped(uv[0] * 4.0, sampling.wrap_s)?, wrapped(uv[1] * 4.0, sampling.wrap_t)?);
            let t = texel(i, j);
            Some([srgb(t[0]), srgb(t[1]), srgb(t[2])])
        })
        .collect()
}

/// The `gbuffer.albedo` channel of `graph` (with `layers` substituted) for `scene`.
fn albedo(gpu: &raygraph::runtime::Gpu, scene: &Scene, graph: &str, layers: &[(&str, &str)], size: u32) -> Vec<[f32; 4]> {
    let mut options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    options.layers.extend(layers.iter().map(|(a, b)| (a.to_string(), b.to_string())));
    let path = repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), (size, size), &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, scene.camera(), scene).unwrap();
    common::channel(gpu, &exec, "gbuffer.albedo")
}

/// The G-buffer producers: over the visibility buffer, in the fragment stage (the layer of
/// devices without primitive indices), from primary rays.
const PRODUCERS: [(&str, &[(&str, &str)]); 3] =
    [("graph/hybrid.ron", &[]), ("graph/hybrid.ron", &[("deferred", "deferred_fragment")]), ("graph/full_rt.ron", &[])];

/// Every G-buffer producer (fragment stage, visibility buffer, primary rays) on both texture
/// paths shows `sampling`'s texel at every pixel away from texel edges.
fn check(name: &str, sampling: SlotSampling) {
    check_scene(name, &quad_scene(sampling), &sampling, &PRODUCERS);
}

/// [`check`] of `scene` (a [`quad_scene`], perhaps changed) through `producers`.
fn check_scene(name: &str, scene: &Scene, sampling: &SlotSampling, producers: &[(&str, &[(&str, &str)])]) {
    let size = 48;
    let want = expected(sampling, size);
    assert!(want.iter().filter(|w| w.is_some()).count() > (size * size / 2) as usize, "{name}: most pixels are checked");
    let mut gpu = gpu();
    for bindless in [true, false] {
        gpu.set_texture_binding_arrays(bindless);
        for &(graph, layers) in producers {
            let got = albedo(&gpu, scene, graph, layers, size);
            // The G-buffer's albedo is 8-bit linear: half a step is 1/510.
            let wrong: Vec<usize> =
                (0..want.len()).filter(|&p| want[p].is_some_and(|w| (0..3).any(|c| (got[p][c] - w[c]).abs() > 1.0 / 510.0 + 1e-4))).collect();
            assert!(
                wrong.is_empty(),
                "{name}, {graph} {layers:?}, binding arrays {bindless}: {} pixels differ, first {:?}: got {:?}, want {:?}",
                wrong.len(),
                wrong.first(),
                wrong.first().map(|&p| got[p]),
                wrong.first().map(|&p| want[p])
            );
        }
    }
}

fn nearest(wrap_s: Wrap, wrap_t: Wrap) -> SlotSampling {
    SlotSampling { wrap_s, wrap_t, mag_nearest: true, min_nearest: true, mipmaps: Mipmaps::None, tex_coord: 0, transform: None }
}

#[test]
fn wrap_modes_per_axis_read_the_texels_gltf_names() {
    check("repeat x clamp", nearest(Wrap::Repeat, Wrap::ClampToEdge));
    check("clamp x mirror", nearest(Wrap::ClampToEdge, Wrap::MirroredRepeat));
    check("mirror x repeat", nearest(Wrap::MirroredRepeat, Wrap::Repeat));
}

#[test]
fn texture_transforms_move_rotate_and_scale_the_uv() {
    // KHR_texture_transform: offset (0.25, -0.5), rotation 90 degrees, scale (0.5, 2).
    let (sin, cos) = std::f32::consts::FRAC_PI_2.sin_cos();
    let (sx, sy, ox, oy) = (0.5, 2.0, 0.25, -0.5);
    let transform = Some([[sx * cos, sy * sin, ox], [-sx * sin, sy * cos, oy]]);
    check("transformed, mirror x clamp", SlotSampling { transform, ..nearest(Wrap::MirroredRepeat, Wrap::ClampToEdge) });
}

#[test]
fn the_khronos_samplers_and_transforms_are_imported() {
    let open = |name: &str| {
        let path = repo().join(format!("assets/khronos/{name}/glTF/{name}.gltf"));
        raygraph::scene::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap()
    };
    let (scene, report) = open("TextureSettingsTest");
    let base = |name: &str| scene.materials().iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}")).sampling[0];
    assert_eq!((base("TextureClampMaterialT").wrap_s, base("TextureClampMaterialT").wrap_t), (Wrap::Repeat, Wrap::ClampToEdge));
    assert_eq!((base("TextureMirrorMaterialS").wrap_s, base("TextureMirrorMaterialS").wrap_t), (Wrap::MirroredRepeat, Wrap::Repeat));
    // minFilter 9986, NEAREST_MIPMAP_LINEAR; magFilter 9729, LINEAR.
    let s = base("TextureMirrorMaterialT");
    assert_eq!((s.min_nearest, s.mipmaps, s.mag_nearest), (true, Mipmaps::Linear, false));
    assert!(!report.ignored_features.iter().any(|f| f.contains("sampler")), "{:?}", report.ignored_features);

    let (scene, _) = open("MultiUVTest");
    assert_eq!((scene.materials()[0].sampling[4].tex_coord, scene.materials()[0].sampling[0].tex_coord), (1, 0), "emissive reads TEXCOORD_1");
    assert!(scene.meshes()[0].extras.as_ref().is_some_and(|e| e.iter().any(|x| x.uv1 != [0.0; 2])), "the mesh's TEXCOORD_1");
    let (scene, _) = open("VertexColorTest");
    let coloured = scene.meshes().iter().filter_map(|m| m.extras.as_ref()).flatten().filter(|x| x.color != [1.0; 4]).count();
    assert!(coloured > 0, "COLOR_0 read");

    let (scene, report) = open("TextureTransformTest");
    assert!(!report.ignored_features.iter().any(|f| f.contains("KHR_texture_transform")), "{:?}", report.ignored_features);
    let transformed = scene.materials().iter().filter(|m| m.sampling[0].transform.is_some()).count();
    assert_eq!(transformed, 6, "Offset U, V, UV, Rotation, Scale, All");
    // `All`: offset (-0.2, -0.1), rotation 0.3, scale 1.5: translation x rotation x scale.
    let all = scene.materials().iter().find(|m| m.name == "All").unwrap().sampling[0].transform.unwrap();
    let (sin, cos) = 0.3f32.sin_cos();
    let want = [[1.5 * cos, 1.5 * sin, -0.2], [-1.5 * sin, 1.5 * cos, -0.1]];
    for (row, want_row) in all.iter().zip(want) {
        for (got, want) in row.iter().zip(want_row) {
            assert!((got - want).abs() < 1e-6, "{all:?} against {want:?}");
        }
    }
    // An offset moves the uv by itself.
    let moved = scene.materials().iter().find(|m| m.name == "Offset U").unwrap().sampling[0].apply([0.25, 0.5]);
    assert_eq!(moved, [0.75, 0.5]);
}

#[test]
fn export_keeps_samplers_transforms_and_unlit() {
    let (sin, cos) = 0.7f32.sin_cos();
    let transform = Some([[2.0 * cos, -0.5 * sin, 0.25], [-2.0 * sin, -0.5 * cos, -1.5]]);
    let mut scene = quad_scene(SlotSampling { transform, ..nearest(Wrap::MirroredRepeat, Wrap::ClampToEdge) });
    let m = &mut scene.materials_mut()[0];
    m.emissive = [1.0; 3];
    m.emissive_texture = Some(0);
    m.sampling[4] = SlotSampling { wrap_s: Wrap::ClampToEdge, mipmaps: Mipmaps::Nearest, tex_coord: 1, ..Default::default() };
    m.occlusion_texture = Some(0);
    m.sampling[3] = SlotSampling { transform: Some([[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]), ..Default::default() };
    m.unlit = true;
    let extras: Vec<VertexExtra> = (0..4).map(|i| VertexExtra { uv1: [i as f32, 0.5], color: [0.25 * i as f32, 1.0, 0.5, 1.0], _pad: [0.0; 2] }).collect();
    scene.mesh_mut(0).extras = Some(extras);
    let dir = std::env::temp_dir().join(format!("raygraph-export-sampling-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sampled.glb");
    raygraph::scene::export::write_glb(&scene, &path).unwrap();
    let (back, report) = raygraph::scene::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let (a, b) = (&scene.materials()[0], &back.materials()[0]);
    assert!(b.unlit);
    // The samplers and transforms are read; only what unlit leaves out is listed.
    assert_eq!(report.ignored_features, ["material `sampled`: occlusion, emission (KHR_materials_unlit draws the base colour only)"]);
    for slot in [0, 3, 4] {
        let (x, y) = (a.sampling[slot], b.sampling[slot]);
        assert_eq!(
            (x.wrap_s, x.wrap_t, x.mag_nearest, x.min_nearest, x.mipmaps, x.tex_coord),
            (y.wrap_s, y.wrap_t, y.mag_nearest, y.min_nearest, y.mipmaps, y.tex_coord),
            "slot {slot}"
        );
        let flat = |t: Option<[[f32; 3]; 2]>| t.map(|t| t.concat());
        match (flat(x.transform), flat(y.transform)) {
            (Some(p), Some(q)) => assert!(p.iter().zip(&q).all(|(p, q)| (p - q).abs() < 1e-5), "slot {slot}: {p:?} against {q:?}"),
            (p, q) => assert_eq!(p, q, "slot {slot}"),
        }
    }
    assert_eq!(scene.meshes()[0].extras, back.meshes()[0].extras, "COLOR_0 and TEXCOORD_1");
}

#[test]
fn a_slot_reads_the_second_texture_coordinates_it_names() {
    // TEXCOORD_0 is constant; TEXCOORD_1 spans the quad. Every producer, the fragment-stage
    // G-buffer too (its vertex stage reads the mesh's extras).
    let sampling = SlotSampling { tex_coord: 1, ..nearest(Wrap::MirroredRepeat, Wrap::Repeat) };
    let mut scene = quad_scene(sampling);
    let mesh = scene.mesh_mut(0);
    mesh.extras = Some(mesh.vertices.iter().map(|v| VertexExtra { uv1: v.uv, ..Default::default() }).collect());
    for v in &mut mesh.vertices {
        v.uv = [0.1, 0.1];
    }
    check_scene("TEXCOORD_1", &scene, &sampling, &PRODUCERS);
}

#[test]
fn vertex_colours_multiply_the_base_colour() {
    // An untextured white quad whose corners are red, green, blue and grey: the albedo is their
    // barycentric blend over each of its two triangles.
    let mut scene = quad_scene(SlotSampling::default());
    scene.materials_mut()[0].texture = None;
    scene.materials_mut()[0].base_color = [1.0, 0.5, 1.0, 1.0];
    let corners = [[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0], [0.5, 0.5, 0.5, 1.0]];
    scene.mesh_mut(0).extras = Some(corners.iter().map(|&color| VertexExtra { color, ..Default::default() }).collect());
    let size = 48u32;
    let mut gpu = gpu();
    gpu.set_texture_binding_arrays(true);
    for (graph, layers) in PRODUCERS {
        let got = albedo(&gpu, &scene, graph, layers, size);
        let mut worst = 0.0f32;
        for p in 0..(size * size) as usize {
            // The pixel's point on the quad: x right, y up (vertices 0..3 at (0,0), (1,0), (1,1), (0,1)).
            let (x, y) = (((p as u32 % size) as f32 + 0.5) / size as f32, 1.0 - ((p as u32 / size) as f32 + 0.5) / size as f32);
            // Triangle (0, 1, 2) below the diagonal x = y, (0, 2, 3) above; skip pixels on it.
            if (x - y).abs() < 0.03 {
                continue;
            }
            let (tri, w) = if x > y { ([0, 1, 2], [1.0 - x, x - y, y]) } else { ([0, 2, 3], [1.0 - y, x, y - x]) };
            for c in 0..3 {
                let want = scene.materials()[0].base_color[c] * (0..3).map(|k| w[k] * corners[tri[k]][c]).sum::<f32>();
                worst = worst.max((got[p][c] - want).abs());
            }
        }
        // The albedo is 8-bit linear: half a step is 1/510.
        assert!(worst <= 1.0 / 510.0 + 1e-4, "{graph}: worst albedo error {worst}");
    }
}
