//! Environment-map lighting (`--env`: scene::environment on the GPU through
//! runtime::environment_upload and shaders/common/environment.wgsl) against sums over the
//! map's texels, on every back-end the adapter has. The scene: one Lambert plane (no specular
//! lobe), tilted 35 degrees so that its normal is away from the map's poles, seen from above,
//! under a synthetic map turned by 40 degrees: a sky gradient, a warm band at the horizon and a
//! small sun (4 texels at 400 times the sky).
//!
//! - The path tracer (graph/reference.ron) draws directions from the map's alias table and
//!   from the BSDF, combined by MIS: the plane converges to albedo / π x the irradiance
//!   integrated over every texel's area.
//! - The three modes read the irradiance grid for the ambient term: the plane shows albedo / π x
//!   the grid's irradiance (`IrradianceMap::irradiance`, its CPU mirror), AO 1 (nothing
//!   occludes it), no direct light (the map replaces the sun).
//! - Glossy metal (roughness 0.7, above the reflection rays' limit) under a constant map: every
//!   mode reflects it by the split-sum approximation (the prefiltered map, exactly the constant
//!   here, times Karis's fit of the lobe's directional albedo); the path tracer integrates the
//!   BSDF itself. The fit's error against it is what this measures.
//! - Under a roof that hides the whole map, hybrid and full RT trace the map's visibility
//!   (rt_shadow's `direct`, a = 2 + visibility) as about 0 and show the floor black; raster, which
//!   traces no rays, lights it unshadowed (as its own ambient term always has).
//! - ReSTIR DI (graph/hybrid_restir.ron) has the map among its lights: the open plane converges
//!   to the path tracer's sum over texel areas, the roofed floor is black.

mod common;

use common::{channel, gpu, judge};
use glam::{Mat4, Vec3};
use raygraph::runtime::environment_upload::IRRADIANCE_GRID_WIDTH;
use raygraph::scene::builtin::{default_scene, plane};
use raygraph::scene::environment::Environment;
use raygraph::scene::{Camera, Instance, Material, Scene};
use std::f32::consts::PI;

const SIZE: (u32, u32) = (32, 24);
const ALBEDO: f32 = 0.6;
const TILT_DEGREES: f32 = 35.0;
const ROTATION_DEGREES: f32 = 40.0;

/// The synthetic map: 128 x 64 texels, the sun 30 degrees from the plane's normal.
fn map() -> Environment {
    let (width, height) = (128usize, 64usize);
    // The sun 30 degrees from the plane's normal, towards -Z, well above its horizon.
    let sun = map_frame(Mat4::from_rotation_x(-30f32.to_radians()).transform_vector3(normal()));
    let (u, v) = (0.5 + sun.x.atan2(-sun.z) / (2.0 * PI), sun.y.acos() / PI);
    let (sun_x, sun_y) = ((u.rem_euclid(1.0) * width as f32) as usize, (v * height as f32) as usize);
    let texels = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let up = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
            let sky = [0.25 + 0.1 * up, 0.3 + 0.2 * up, 0.4 + 0.35 * up.max(0.0)];
            let band = if (30..36).contains(&y) && x < 64 { 0.8 } else { 0.0 };
            let sun = if (sun_y..sun_y + 2).contains(&y) && (sun_x..sun_x + 2).contains(&x) { 400.0 * 0.5 } else { 0.0 };
            [sky[0] + band + sun, sky[1] + 0.5 * band + sun, sky[2] + sun]
        })
        .collect();
    let mut env = Environment::from_texels(width, height, texels, "synthetic map".as_ref()).unwrap();
    env.rotation = ROTATION_DEGREES.to_radians();
    env
}

/// World direction `d` in the map's frame (turned back about +Y).
fn map_frame(d: Vec3) -> Vec3 {
    Mat4::from_rotation_y(-ROTATION_DEGREES.to_radians()).transform_vector3(d)
}

/// The irradiance at normal `n` from the map, each texel's radiance integrated over its area by
/// 16 x 16 points: what the GPU's per-texel sampling converges to. (A sum over texel centres,
/// `Environment::irradiance_exact`, errs by about 0.1% where the horizon cuts texels, and by
/// far more for a small bright source near it.)
fn irradiance_by_texel_areas(env: &Environment, n: Vec3) -> Vec3 {
    const SUB: usize = 16;
    let (width, height) = env.size();
    let mut sum = [0.0f64; 3];
    for (i, t) in env.texels().iter().enumerate() {
        let (x, y) = (i % width, i / width);
        let mut w = 0.0f64;
        for (a, b) in (0..SUB * SUB).map(|k| (k % SUB, k / SUB)) {
            let u = (x as f32 + (a as f32 + 0.5) / SUB as f32) / width as f32;
            let v = (y as f32 + (b as f32 + 0.5) / SUB as f32) / height as f32;
            let (phi, theta) = ((u - 0.5) * 2.0 * PI, v * PI);
            let d = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
            let world = Mat4::from_rotation_y(ROTATION_DEGREES.to_radians()).transform_vector3(d);
            let solid_angle = (2.0 * PI / width as f32) * (PI / height as f32) * theta.sin() / (SUB * SUB) as f32;
            w += (n.dot(world).max(0.0) * solid_angle * env.intensity) as f64;
        }
        for c in 0..3 {
            sum[c] += t[c] as f64 * w;
        }
    }
    Vec3::new(sum[0] as f32, sum[1] as f32, sum[2] as f32)
}

/// The plane's normal: up, tilted about +X.
fn normal() -> Vec3 {
    Mat4::from_rotation_x(TILT_DEGREES.to_radians()).transform_vector3(Vec3::Y)
}

fn scene() -> Scene {
    let mut s = default_scene();
    s.set_name("plane under an environment map");
    s.set_meshes(vec![plane("ground", 200.0, 1.0)]);
    *s.textures_mut() = Vec::new();
    let mut m = Material::diffuse("ground", [ALBEDO, ALBEDO, ALBEDO, 1.0], None);
    m.roughness = 1.0;
    m.lobes.specular = 0.0;
    *s.materials_mut() = vec![m];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::from_rotation_x(TILT_DEGREES.to_radians()) }];
    // Looking down the normal: every pixel sees the plane.
    let n = normal();
    *s.camera_mut() = Camera::look(2.0 * n, -n + Vec3::new(0.0, 0.0, 0.1), 50.0, 0.01, 100.0);
    s.set_environment(Some(map()));
    s
}

#[test]
fn the_path_tracer_converges_to_the_irradiance_summed_over_the_map() {
    let gpu = gpu();
    let scene = scene();
    let exact = irradiance_by_texel_areas(&map(), normal()) * ALBEDO / PI;
    println!("albedo / pi x irradiance: by texel areas {exact}, by texel centres {}", map().irradiance_exact(normal()) * ALBEDO / PI);
    for &backend in gpu.backends() {
        let texels = common::modes::path_traced(&gpu, backend, &scene, SIZE, 4, 16);
        assert!(texels.iter().all(|t| t[3] == 1.0), "{backend}: every pixel shows the plane");
        for c in 0..3 {
            let (mean, worst) = judge(&texels, c, exact[c]);
            println!("{backend}: channel {c}: mean {mean} (expected {}), largest pixel deviation {worst}", exact[c]);
            // 768 pixels of 64 paths; the half-float texels round by up to 0.05%. Measured on
            // lavapipe (Mesa 25.0.7), 2026-11-30: means 0.09-0.15% above, single pixels up to
            // 36% off (the sun drawn or not); the bound is 6x the mean's largest error.
            assert!((mean - exact[c]).abs() <= 0.01 * exact[c], "{backend}: channel {c}: mean {mean}, expected {}", exact[c]);
        }
    }
}

#[test]
fn every_mode_lights_the_plane_by_the_irradiance_grid() {
    let gpu = gpu();
    let scene = scene();
    let grid = map().irradiance_map(IRRADIANCE_GRID_WIDTH).irradiance(normal()) * ALBEDO / PI;
    let exact = map().irradiance_exact(normal()) * ALBEDO / PI;
    println!("albedo / pi x irradiance: grid {grid}, exact {exact}");
    for &backend in gpu.backends() {
        for (graph, output) in [("graph/raster.ron", "forward.color"), ("graph/hybrid.ron", "resolve.hdr"), ("graph/full_rt.ron", "resolve.hdr")] {
            let exec = common::modes::render_graph(&gpu, graph, backend, &scene, SIZE);
            let texels = channel(&gpu, &exec, output);
            for c in 0..3 {
                let (mean, worst) = judge(&texels, c, grid[c]);
                println!("{backend} {graph}: channel {c}: mean {mean} (expected {}), largest pixel deviation {worst}", grid[c]);
                // Half-float grid and target (0.1% each) and the sampler's bilinear weights
                // (8 fraction bits on lavapipe): 1% of the value.
                assert!(worst <= 0.01 * grid[c], "{backend} {graph}: channel {c}: a pixel is {worst} from {}", grid[c]);
            }
        }
    }
}

/// The plane under a parallel roof 1 above it that hides the whole map, seen from between them.
fn roofed_scene() -> Scene {
    let mut scene = scene();
    scene.set_meshes(vec![plane("ground", 2000.0, 1.0), plane("roof", 2000.0, 1.0)]);
    let mut roof = scene.materials()[0].clone();
    roof.double_sided = true;
    scene.materials_mut().push(roof);
    scene.instances_mut().push(Instance {
        mesh: 1,
        material: 1,
        transform: Mat4::from_rotation_x(TILT_DEGREES.to_radians()) * Mat4::from_translation(Vec3::Y),
    });
    let n = normal();
    *scene.camera_mut() = Camera::look(0.5 * n, -n + Vec3::new(0.0, 0.0, 0.1), 50.0, 0.01, 100.0);
    scene
}

#[test]
fn under_a_roof_the_ray_traced_modes_see_none_of_the_map() {
    let gpu = gpu();
    let scene = roofed_scene();
    let n = normal();
    let open_sky = map().irradiance_map(IRRADIANCE_GRID_WIDTH).irradiance(n) * ALBEDO / PI;
    for &backend in gpu.backends() {
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let exec = common::modes::render_graph(&gpu, graph, backend, &scene, SIZE);
            // rt_shadow's direct light: a = 2 + the map's visibility where it traced that.
            let direct = channel(&gpu, &exec, "shadow.direct");
            let texels = channel(&gpu, &exec, "resolve.hdr");
            let (mean, brightest) = judge(&texels, 1, 0.0);
            println!("{backend} {graph}: floor under the roof: mean {mean}, brightest {brightest} (open sky: {})", open_sky.y);
            assert!(direct.iter().all(|d| d[3] >= 2.0), "{backend} {graph}: the visibility is traced at every pixel");
            // The roof ends 1000 units away, 1 above the floor: a ray within 0.06 degrees of the
            // horizon passes under its edge (measured on lavapipe, 2026-11-30, with a roof of
            // 200: one pixel at 2% of the open sky, the mean at 0.005%).
            assert!(
                mean <= 1e-3 * open_sky.y && brightest <= 0.05 * open_sky.y,
                "{backend} {graph}: the floor shows {mean} (brightest {brightest}) under the roof"
            );
        }
    }
}

#[test]
fn glossy_metal_reflects_a_constant_map_by_the_split_sum_as_the_path_tracer_integrates_it() {
    const RADIANCE: f32 = 0.5;
    let gpu = gpu();
    let mut scene = scene();
    let m = &mut scene.materials_mut()[0];
    *m = Material { metallic: 1.0, roughness: 0.7, ..Material::diffuse("metal", [0.9, 0.6, 0.3, 1.0], None) };
    scene.set_environment(Some(Environment::from_texels(64, 32, vec![[RADIANCE; 3]; 64 * 32], "constant map".as_ref()).unwrap()));
    let backend = gpu.backends()[0];
    let reference = common::modes::path_traced(&gpu, backend, &scene, SIZE, 4, 16);
    for (graph, output) in [("graph/raster.ron", "forward.color"), ("graph/hybrid.ron", "resolve.hdr"), ("graph/full_rt.ron", "resolve.hdr")] {
        let exec = common::modes::render_graph(&gpu, graph, backend, &scene, SIZE);
        let texels = channel(&gpu, &exec, output);
        for c in 0..3 {
            let (expected, _) = judge(&reference, c, 0.0);
            let (mean, _) = judge(&texels, c, 0.0);
            let error = (mean - expected) / expected;
            println!("{backend} {graph}: channel {c}: split sum {mean}, path tracer {expected} ({:+.2}%)", 100.0 * error);
            // Measured on lavapipe, 2026-11-30: -0.3% to -1.1% (the fit, the G-buffer's 8-bit
            // roughness and colour, 64 paths a pixel); 5% bounds it at 4x.
            assert!(error.abs() <= 0.05, "{backend} {graph}: channel {c}: split sum {mean} against the path tracer's {expected}");
        }
    }
}

#[test]
fn a_scene_uploaded_again_keeps_its_prefiltered_map_until_the_map_changes() {
    use raygraph::runtime::scene_upload::GpuScene;
    use raygraph::scene::usage::SceneUsage;
    let gpu = gpu();
    let usage = SceneUsage { environment: true, ..Default::default() };
    let upload = |s: &Scene, before: Option<&GpuScene>| GpuScene::upload(gpu.device(), gpu.queue(), s, usage, before).unwrap();
    let mut s = scene();
    let first = upload(&s, None);
    // The same map (shared): its levels, grid and table are the first upload's.
    let again = upload(&s, Some(&first));
    assert!(std::ptr::eq(first.environment().unwrap(), again.environment().unwrap()), "the map was prefiltered again");
    // Another intensity: made anew.
    let mut brighter = map();
    brighter.intensity *= 2.0;
    s.set_environment(Some(brighter));
    let changed = upload(&s, Some(&again));
    assert!(!std::ptr::eq(again.environment().unwrap(), changed.environment().unwrap()), "a changed map kept the old levels");
}

/// `output` of `graph` averaged over `frames` frames of a still camera.
fn mean_over_frames(
    gpu: &raygraph::runtime::Gpu,
    graph: &str,
    backend: raygraph::backend::Backend,
    scene: &Scene,
    output: &str,
    frames: usize,
) -> Vec<[f32; 4]> {
    let mut exec = common::modes::render_graph(gpu, graph, backend, scene, SIZE);
    let mut mean = channel(gpu, &exec, output);
    for _ in 1..frames {
        exec.render(gpu, scene.camera(), scene).unwrap();
        for (m, t) in mean.iter_mut().zip(channel(gpu, &exec, output)) {
            for c in 0..4 {
                m[c] += t[c];
            }
        }
    }
    mean.iter().map(|m| m.map(|v| v / frames as f32)).collect()
}

/// ReSTIR DI (graph/hybrid_restir.ron) samples the map from its alias table among its lights:
/// the plane converges to the irradiance summed over the map's texels, as the path tracer's;
/// under the roof it is black.
#[test]
fn restir_samples_the_map_as_a_light() {
    let gpu = gpu();
    let exact = irradiance_by_texel_areas(&map(), normal()) * ALBEDO / PI;
    let roofed = roofed_scene();
    for &backend in gpu.backends() {
        let texels = mean_over_frames(&gpu, "graph/hybrid_restir.ron", backend, &scene(), "resolve.hdr", 16);
        for c in 0..3 {
            let (mean, worst) = judge(&texels, c, exact[c]);
            println!("{backend} restir: channel {c}: mean {mean} (expected {}), largest pixel deviation {worst}", exact[c]);
            // Measured on lavapipe (Mesa 25.0.7), 2026-11-30, every back-end alike: means +3.0%,
            // +1.3%, +0.1% (red, green, blue: the warm sun, 4 texels at 400 times the sky, is a
            // few samples carried over frames and neighbours, which 16 frames of a still camera
            // do not average out; tests/restir.rs measures that wander), single pixels up to 58%
            // off. Bound: twice the largest channel's.
            assert!((mean - exact[c]).abs() <= 0.06 * exact[c], "{backend}: channel {c}: mean {mean}, expected {}", exact[c]);
        }
        let under = mean_over_frames(&gpu, "graph/hybrid_restir.ron", backend, &roofed, "resolve.hdr", 4);
        let (dark, brightest) = judge(&under, 1, 0.0);
        println!("{backend} restir: under the roof mean {dark}, brightest {brightest}");
        // Measured: 0 and 0 (the map's samples all blocked, and no light of the map's own added
        // by the resolve); the bounds of the test above.
        assert!(dark <= 1e-3 * exact[1] && brightest <= 0.05 * exact[1], "{backend}: the floor shows {dark} (brightest {brightest}) under the roof");
    }
}
