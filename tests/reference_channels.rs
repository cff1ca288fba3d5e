//! Every ray-traced channel of the full ray-tracing graph against the f64 reference renderer
//! (`accel::reference_render`), pixel by pixel, on the built-in `default` scene and a small
//! scene of a floor, a wall, a sphere and two cubes, one mirrored (each with a point light
//! added), at 64x48, on `compute` (merged layout, as the
//! graph ships, and two-level) and on `ray-query`.
//!
//! The secondary channels are rebuilt from the GPU's own G-buffer (position, geometric and
//! shading normal as stored), so each comparison checks one trace pass: the reference builds
//! the same f32 rays and traces them in f64. Metric and tolerance: a pixel's GPU answer must
//! equal the reference's, except where the reference's margin (the smallest relative
//! perturbation of the ray that could change its answer: a triangle edge passed within that
//! distance, a ray end, a second surface at nearly the same depth) is below `MARGIN`, 1e-5 of
//! the coordinate magnitude (about 80 f32 ulps: the GPU rounds its own camera directions,
//! normalisations, square roots, sines and cosines, and may fuse multiply-adds). Primary hits
//! must also lie where the reference's hit is (within 1e-4 of the depth). AO: per pixel the
//! number of unoccluded rays may differ from the reference's by at most the number of that
//! pixel's rays within the margin, and the mean absolute difference of the unoccluded fraction
//! over all pixels must stay below 1e-3. The mirror channel is a test-only trace pass that
//! writes the instance and triangle hit by the first ray of `rt_reflection` for a mirror.

mod common;

use glam::{Mat4, Quat, Vec3};
use raygraph::accel::reference_render::{AoSettings, ReferenceRenderer, SurfacePoint};
use raygraph::backend::Backend;
use raygraph::graph::compile::compile_with;
use raygraph::graph::Project;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{builtin, Camera, Instance, LoadOptions, PointLight, Scene};

/// The largest margin at which the GPU may disagree with the reference (module docs).
const MARGIN: f64 = 1e-5;
const SIZE: (u32, u32) = (64, 48);
const AO_RAYS: u32 = 8;

const MIRROR_LAYER: &str = r#"// Test only: the instance and triangle that the first ray of rt_reflection hits for a mirror.
Layer(
    inputs: {
        "position": Texture(format: Rgba32Float),
        "normal": Texture(format: Rgba16Float),
        "geo_normal": Texture(format: Rgba16Float),
        "tlas": Accel,
    },
    outputs: {
        // r: instance (-1: miss), g: triangle, b: t, a: 1 where a ray was traced
        "ids": Texture(format: Rgba32Float),
        // white where the mirror ray hit (a graph's output must be an 8-bit colour texture)
        "mask": Texture(format: Rgba8Unorm),
    },
    passes: [
        Pass(name: "mirror_ids", kind: Trace, shader: "test/mirror_ids.wgsl", reads: ["position", "normal", "geo_normal", "tlas"], writes: ["ids", "mask"]),
    ],
)
"#;

const MIRROR_SHADER: &str = r#"// The first ray of shaders/rt/reflection.wgsl for a mirror (roughness below 0.03), its hit ids.
//#include "common/frame.wgsl"
//#include "common/ray_offset.wgsl"
//#include "trace/trace.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var position: texture_2d<f32>;
@group(0) @binding(2) var normal: texture_2d<f32>;
@group(0) @binding(3) var geo_normal: texture_2d<f32>;
@group(0) @binding(4) var ids: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var mask: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ids);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = textureLoad(position, id.xy, 0);
    if p.w == 0.0 {
        textureStore(ids, id.xy, vec4<f32>(0.0));
        textureStore(mask, id.xy, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let n = normalize(textureLoad(normal, id.xy, 0).xyz);
    let geo = normalize(textureLoad(geo_normal, id.xy, 0).xyz);
    let v = normalize(frame.camera_pos.xyz - p.xyz);
    var dir = reflect(-v, n);
    if dot(dir, geo) <= 0.0 {
        dir = reflect(dir, geo);
    }
    let hit = trace_closest(Ray(offset_ray_origin(p.xyz, geo), 0.0, dir, 3.0e38));
    let instance = select(f32(hit.instance), -1.0, hit.instance == NO_HIT);
    textureStore(ids, id.xy, vec4<f32>(instance, f32(hit.primitive), hit.t, 1.0));
    textureStore(mask, id.xy, vec4<f32>(select(vec3<f32>(1.0), vec3<f32>(0.0), hit.instance == NO_HIT), 1.0));
    trace_flush_stats();
}
"#;

/// The scenes, untextured (textures play no part in what is traced), each with a point light:
/// the built-in `default` scene, and a small one built here (a floor, a wall behind, a sphere,
/// a cube and a mirrored cube: negative determinant).
fn scenes() -> Vec<Scene> {
    let (default, _) = raygraph::scene::open("default", &LoadOptions { textures: false, ..Default::default() }).unwrap();
    let mut small = default.clone();
    small.name = "small".into();
    small.meshes = vec![builtin::plane("floor", 8.0, 1.0), builtin::sphere("ball", 16, 32), builtin::cube("box")];
    let wall = Mat4::from_translation(Vec3::new(0.0, 2.0, -2.5)) * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let ball = Mat4::from_scale_rotation_translation(Vec3::splat(0.7), Quat::IDENTITY, Vec3::new(0.0, 0.7, 0.0));
    let cube = Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(-1.4, 0.5, -0.6));
    let mirrored = Mat4::from_scale_rotation_translation(Vec3::new(-0.8, 0.8, 0.8), Quat::from_rotation_y(-0.3), Vec3::new(1.3, 0.4, 0.8));
    small.instances = [(0, Mat4::IDENTITY), (0, wall), (1, ball), (2, cube), (2, mirrored)]
        .iter()
        .map(|&(mesh, transform)| Instance { mesh, material: 0, transform })
        .collect();
    small.camera = Camera::look(Vec3::new(2.5, 2.2, 4.0), Vec3::new(0.0, 0.5, 0.0), 50.0, 0.05, 100.0);
    small.light.direction = Vec3::new(-0.4, 0.8, 0.45).normalize();
    let mut scenes = vec![default, small];
    for s in &mut scenes {
        let b = s.bounds();
        s.point_light = Some(PointLight { position: b.center() + Vec3::new(0.3, 0.45, 0.2) * b.diagonal(), color: Vec3::ONE, intensity: 5.0 });
    }
    scenes
}

/// Counts of one channel's comparison.
#[derive(Debug, Default)]
struct Tally {
    compared: usize,
    /// Disagreements within the margin.
    excused: usize,
    /// Disagreements outside it.
    wrong: usize,
    /// The largest margin among the excused ones.
    largest_excused: f64,
}

impl Tally {
    fn add(&mut self, agree: bool, margin: f64) {
        self.compared += 1;
        if !agree {
            if margin < MARGIN {
                self.excused += 1;
                self.largest_excused = self.largest_excused.max(margin);
            } else {
                self.wrong += 1;
            }
        }
    }
}

/// One frame of `graph`, without texture reuse so every channel can be read back.
fn render(gpu: &Gpu, backend: Backend, graph: &std::path::Path, scene: &Scene) -> Executor {
    let options = raygraph::graph::compile::CompileOptions { reuse: false, ..gpu.compile_options_for(backend) };
    let plan = compile_with(graph, &Project::beside_graph(graph), SIZE, &options).unwrap();
    let mut exec = Executor::new(gpu, plan, scene).unwrap();
    exec.render(gpu, &scene.camera, scene).unwrap();
    exec
}

fn read(gpu: &Gpu, exec: &Executor, name: &str) -> Vec<[f32; 4]> {
    let r = exec.plan().resource_by_name(name).unwrap_or_else(|| panic!("no resource {name}"));
    exec.read_texture_f32(gpu, r).unwrap().2
}

fn xyz(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

#[test]
fn every_ray_traced_channel_matches_the_f64_reference_per_pixel() {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe in CI) is required");
    assert!(gpu.backends.contains(&Backend::RayQuery), "lavapipe >= 24.1 has ray queries; CI must test both back-ends");
    assert!(gpu.backends.contains(&Backend::RtPipeline), "lavapipe >= 24.1 has ray-tracing pipelines; CI must test the rt-pipeline back-end");
    let p = common::TempProject::with_repo_files();
    p.write("layers/test_mirror_ids.ron", MIRROR_LAYER);
    p.write("shaders/test/mirror_ids.wgsl", MIRROR_SHADER);
    // AO rays of 0.2 times the scene's bounding radius, the radius as the executor takes it.
    let range_scale = 0.2f32;
    let full_rt = std::fs::read_to_string(common::repo().join("graph/full_rt.ron"))
        .unwrap()
        .replace(r#"params: {"rays": 8, "range_scale": 0.05}"#, &format!(r#"params: {{"rays": {AO_RAYS}, "range": 0.0, "range_scale": {range_scale:?}, "sampling": 1}}"#))
        .replace(
            r#""resolve": Layer("#,
            r#""mirror": Layer(layer: "test_mirror_ids", inputs: {"position": "gbuffer.position", "normal": "gbuffer.normal", "geo_normal": "gbuffer.geo_normal", "tlas": "accel.tlas"}),
        "resolve": Layer("#,
        );
    assert!(full_rt.contains(r#""range_scale": 0.2"#) && full_rt.contains("test_mirror_ids"), "graph/full_rt.ron changed: update the test's edits");
    // The graph's output decides which passes run: the mirror pass's mask is a second graph's
    // output (the same G-buffer, then only the mirror pass).
    let mirror_graph_of = |g: &str| {
        let m = g.replace(r#"output: "tonemap.color""#, r#"output: "mirror.mask""#);
        assert!(m != g, "graph/full_rt.ron's output changed: update the test");
        m
    };
    let two_level = |g: &str| g.replace("Accel(merge: true)", "Accel()");
    let graphs = |name: &str, g: &str| (p.write(&format!("graph/{name}.ron"), g), p.write(&format!("graph/{name}_mirror.ron"), &mirror_graph_of(g)));
    let merged = graphs("merged", &full_rt);
    let two = graphs("two_level", &two_level(&full_rt));
    let variants = [
        ("compute, merged", Backend::Compute, &merged),
        ("compute, two levels", Backend::Compute, &two),
        ("ray-query", Backend::RayQuery, &two),
        ("rt-pipeline, merged", Backend::RtPipeline, &merged),
        ("rt-pipeline, two levels", Backend::RtPipeline, &two),
    ];
    for scene in scenes() {
        let renderer = ReferenceRenderer::new(&scene);
        let settings = AoSettings { rays: AO_RAYS, range: range_scale * (0.5 * scene.bounds().diagonal()).max(1e-6), sampling: 1, seed: 0 };
        let rays = ReferenceRenderer::camera_rays(&scene.camera, SIZE);
        let visibility = renderer.visibility(&rays);
        let own_surfaces = renderer.surfaces(&rays, &visibility);
        println!("{}: {} triangles, {} of {} pixels hit", scene.name, renderer.reference.triangle_count(), own_surfaces.iter().flatten().count(), rays.len());
        for (variant, backend, graph) in variants {
            let exec = render(&gpu, backend, &graph.0, &scene);
            let (pos, normal, geo) = (read(&gpu, &exec, "gbuffer.position"), read(&gpu, &exec, "gbuffer.normal"), read(&gpu, &exec, "gbuffer.geo_normal"));
            let (shadow, ao) = (read(&gpu, &exec, "shadow.shadow"), read(&gpu, &exec, "ao.ao"));
            let mirror_exec = render(&gpu, backend, &graph.1, &scene);
            let mirror = read(&gpu, &mirror_exec, "mirror.ids");
            assert_eq!(read(&gpu, &mirror_exec, "gbuffer.position"), pos, "both graphs make the same G-buffer");

            // Primary visibility against the reference's own camera rays; where both hit, the
            // G-buffer's point is the reference's and its geometric normal the triangle's.
            let mut primary = Tally::default();
            let mut worst_normal = 0.0f32;
            for i in 0..rays.len() {
                let r = &visibility[i];
                let agree = match (pos[i][3] != 0.0, r.value) {
                    (false, None) => true,
                    (true, Some(h)) => {
                        let at = rays[i].origin.as_dvec3() + h.t * rays[i].dir.as_dvec3();
                        let close = (xyz(pos[i]).as_dvec3() - at).length() <= 1e-4 * h.t;
                        if close && r.margin >= MARGIN {
                            let own = own_surfaces[i].unwrap();
                            worst_normal = worst_normal.max(1.0 - xyz(geo[i]).normalize().dot(own.geo_normal));
                        }
                        close
                    }
                    _ => false,
                };
                primary.add(agree, r.margin);
            }

            // Shadow, AO and the mirror ray from the GPU's G-buffer.
            let surfaces: Vec<Option<SurfacePoint>> = (0..pos.len())
                .map(|i| (pos[i][3] != 0.0).then(|| SurfacePoint { position: xyz(pos[i]), geo_normal: xyz(geo[i]), normal: xyz(normal[i]) }))
                .collect();
            let (mut sun, mut point, mut mirrored, mut ao_rays) = (Tally::default(), Tally::default(), Tally::default(), Tally::default());
            for (i, s) in renderer.shadow(&surfaces, &scene.light, scene.point_light.as_ref()).iter().enumerate() {
                let Some(s) = s else { continue };
                sun.add((shadow[i][0] == 1.0) == s.sun.value, s.sun.margin);
                let lit = s.point.expect("the scene has a point light");
                point.add((shadow[i][1] == 1.0) == lit.value, lit.margin);
            }
            let mut ao_difference = 0.0;
            let mut ao_pixels = 0usize;
            for (i, rays_of_pixel) in renderer.ao(&surfaces, SIZE.0, &settings).iter().enumerate() {
                let Some(rays_of_pixel) = rays_of_pixel else { continue };
                let open = rays_of_pixel.iter().filter(|c| c.value).count() as i64;
                let within_margin = rays_of_pixel.iter().filter(|c| c.margin < MARGIN).count() as i64;
                let gpu_open = (ao[i][0] * AO_RAYS as f32).round() as i64;
                let diff = (gpu_open - open).abs();
                ao_rays.compared += rays_of_pixel.len();
                ao_rays.excused += diff.min(within_margin) as usize;
                ao_rays.wrong += (diff - within_margin).max(0) as usize;
                ao_difference += diff as f64 / AO_RAYS as f64;
                ao_pixels += 1;
            }
            for (i, m) in renderer.mirror(scene.camera.position, &surfaces).iter().enumerate() {
                let Some(m) = m else { continue };
                let gpu_hit = (mirror[i][0] >= 0.0).then(|| (mirror[i][0] as u32, mirror[i][1] as u32));
                mirrored.add(gpu_hit == m.value.map(|h| (h.instance_id, h.prim)), m.margin);
            }
            let ao_mean = ao_difference / ao_pixels.max(1) as f64;
            let in_shadow = (0..pos.len()).filter(|&i| pos[i][3] != 0.0 && shadow[i][0] == 0.0).count();
            let occluded: f64 = (0..pos.len()).filter(|&i| pos[i][3] != 0.0).map(|i| 1.0 - ao[i][0] as f64).sum::<f64>() * AO_RAYS as f64;
            let mirror_hits = mirror.iter().filter(|m| m[3] != 0.0 && m[0] >= 0.0).count();
            println!("{:8} {variant:20} {in_shadow} pixels in the sun's shadow, {occluded:.0} AO rays occluded, {mirror_hits} mirror rays hit", scene.name);
            assert!(in_shadow > 50 && occluded > 500.0 && mirror_hits > 50, "{}: the view holds shadows, occlusion and reflected geometry", scene.name);
            for (channel, t) in [("primary", &primary), ("sun shadow", &sun), ("point shadow", &point), ("AO rays", &ao_rays), ("mirror", &mirrored)] {
                println!(
                    "{:8} {variant:20} {channel:12}: {:6} compared, {:3} differ within the margin (largest {:.1e}), {} outside",
                    scene.name, t.compared, t.excused, t.largest_excused, t.wrong
                );
                assert!(t.compared > 0, "{}, {variant}, {channel}: nothing compared", scene.name);
                assert_eq!(t.wrong, 0, "{}, {variant}, {channel}: disagreements outside the margin", scene.name);
            }
            println!(
                "{:8} {variant:20} AO: mean |V - V_ref| {ao_mean:.2e} over {ao_pixels} pixels; geometric normals within {worst_normal:.1e} (1 - cos)",
                scene.name
            );
            assert!(ao_pixels > 1000 && ao_mean <= 1e-3, "{}, {variant}: AO mean difference {ao_mean}", scene.name);
            assert!(worst_normal <= 2e-3, "{}, {variant}: geometric normal 1 - cos {worst_normal}", scene.name);
        }
    }
}
