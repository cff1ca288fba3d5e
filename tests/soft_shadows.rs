//! Soft shadows (`rt_shadow`'s `light_radius` and `sun_angle`): with both 0 the image is the
//! hard-shadow one, byte for byte; under a sun of angular diameter 20 degrees straight above
//! a sphere, the fraction of frames in which a floor point's one shadow ray reaches the sun
//! (`per_frame`: a new point of the sun's disc every frame) matches the fraction of the disc
//! that the sphere leaves uncovered, integrated on the CPU; the umbra stays black and the floor
//! beyond the penumbra lit in every frame; 16 rays a frame (`rays`) over a sixteenth of the
//! frames gives the same penumbra.

mod common;

use common::{gpu, TempProject};
use glam::{Mat4, Vec3};
use raygraph::runtime::Executor;
use raygraph::scene::builtin::{default_scene, plane, sphere};
use raygraph::scene::{Camera, Instance, Light, Material, Scene};

const W: u32 = 96;
const H: u32 = 72;
const CENTRE: Vec3 = Vec3::new(0.0, 2.5, 0.0);
const SUN_ANGLE_DEG: f32 = 20.0;
const FRAMES: usize = 64;

fn scene(camera: Camera) -> Scene {
    let mut s = default_scene();
    s.set_name("soft shadow test");
    s.set_meshes(vec![plane("floor", 12.0, 1.0), sphere("ball", 64, 128)]);
    *s.textures_mut() = Vec::new();
    *s.materials_mut() = vec![Material::diffuse("grey", [0.8, 0.8, 0.8, 1.0], None)];
    *s.instances_mut() =
        vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 1, material: 0, transform: Mat4::from_translation(CENTRE) }];
    *s.light_mut() = Light { direction: Vec3::Y, color: Vec3::ONE, intensity: 3.0, ambient: 0.35 };
    *s.camera_mut() = camera;
    s
}

fn graph(params: &str) -> String {
    format!(
        r#"Graph(output: "shadow.shadow", nodes: {{
    "accel": Accel(),
    "gbuffer": Layer(layer: "deferred"),
    "shadow": Layer(
        layer: "rt_shadow",
        inputs: {{"position": "gbuffer.position", "geo_normal": "gbuffer.geo_normal", "normal": "gbuffer.normal", "albedo": "gbuffer.albedo", "material": "gbuffer.material", "lobes": "gbuffer.lobes", "tlas": "accel.tlas"}},
        params: {{{params}}},
    ),
}})"#
    )
}

/// The shadow masks (light 0, one byte per pixel) of `frames` frames of `graph_text`.
fn masks(graph_text: &str, scene: &Scene, frames: usize) -> Vec<Vec<u8>> {
    let gpu = gpu();
    let p = TempProject::with_repo_files();
    let path = p.write("graph/soft.ron", graph_text);
    let plan = raygraph::graph::compile::compile(&path, &p.project(), (W, H)).unwrap_or_else(|e| panic!("{e}"));
    let mut exec = Executor::new(&gpu, plan, scene).unwrap();
    (0..frames)
        .map(|_| {
            exec.render(&gpu, scene.camera(), scene).unwrap();
            exec.read_output(&gpu).unwrap().pixels().map(|p| p[0]).collect()
        })
        .collect()
}

#[test]
fn zero_sizes_give_the_hard_shadow_image() {
    let camera = Camera::look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO, 50.0, 0.05, 100.0);
    let s = scene(camera);
    let hard = masks(&graph(""), &s, 2);
    let zero = masks(&graph(r#""light_radius": 0.0, "sun_angle": 0.0, "per_frame": true"#), &s, 2);
    assert_eq!(hard, zero);
    assert!(hard[1].contains(&0) && hard[1].contains(&255), "the view shows a shadow and lit floor");
}

/// The fraction of the sun's disc (angular radius `alpha` around +y) that the sphere leaves
/// uncovered from floor point `x`: 64 x 64 directions, uniform in solid angle.
fn uncovered(x: Vec3, alpha: f32) -> f64 {
    let n = 64;
    let mut open = 0;
    for i in 0..n {
        for j in 0..n {
            let cos_t = 1.0 - (i as f32 + 0.5) / n as f32 * (1.0 - alpha.cos());
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            let phi = (j as f32 + 0.5) / n as f32 * std::f32::consts::TAU;
            let d = Vec3::new(sin_t * phi.cos(), cos_t, sin_t * phi.sin());
            let t = (CENTRE - x).dot(d);
            open += (t < 0.0 || (x + d * t).distance(CENTRE) >= 1.0) as usize;
        }
    }
    open as f64 / (n * n) as f64
}

#[test]
fn a_sun_disc_gives_the_penumbra_of_the_uncovered_fraction() {
    check_penumbra("", FRAMES);
}

/// `rays` 16 (16 shadow rays per pixel in a frame, the mask holding the visible fraction) over
/// FRAMES / 16 frames: the same 64 samples per pixel, the same error against the integral.
#[test]
fn sixteen_rays_a_frame_give_the_penumbra_of_sixteen_frames() {
    check_penumbra(r#", "rays": 16"#, FRAMES / 16);
}

/// The penumbra of FRAMES samples per pixel over `frames` frames of `rt_shadow` with `extra`
/// parameters, against the integral; the umbra black and the lit floor lit in every frame.
fn check_penumbra(extra: &str, frames_count: usize) {
    let camera = Camera::look(Vec3::new(0.0, 7.0, 5.0), Vec3::ZERO, 50.0, 0.05, 100.0);
    let s = scene(camera);
    let frames = masks(&graph(&format!(r#""sun_angle": {SUN_ANGLE_DEG}, "per_frame": true{extra}"#)), &s, frames_count);
    let alpha = (SUN_ANGLE_DEG * 0.5).to_radians();
    let dirs = camera.ray_dirs((W, H), 1);
    let (mut umbra, mut lit, mut penumbra, mut wrong_extremes) = (0, 0, 0, 0);
    let (mut sq_error, mut sq_expected) = (0.0, 0.0);
    for (i, d) in dirs.iter().enumerate() {
        // Floor pixels whose camera ray passes clear of the sphere.
        let t_floor = -camera.position.y / d.y;
        let t_centre = (CENTRE - camera.position).dot(*d);
        if d.y >= 0.0 || (camera.position + *d * t_centre).distance(CENTRE) < 1.1 {
            continue;
        }
        let x = camera.position + *d * t_floor;
        if x.x.abs() > 5.5 || x.z.abs() > 5.5 {
            continue;
        }
        let measured = frames.iter().map(|f| f[i] as f64 / 255.0).sum::<f64>() / frames_count as f64;
        // The analytic classes: gamma, the angle to the sphere's centre from the zenith, beta,
        // the sphere's angular radius, with a margin for the tessellation.
        let to_centre = CENTRE - x;
        let gamma = to_centre.normalize().dot(Vec3::Y).clamp(-1.0, 1.0).acos();
        let beta = (1.0 / to_centre.length()).asin();
        let margin = 0.01;
        if gamma + alpha < beta - margin {
            umbra += 1;
            wrong_extremes += (measured != 0.0) as usize;
        } else if gamma - alpha > beta + margin {
            lit += 1;
            wrong_extremes += (measured != 1.0) as usize;
        } else if gamma + alpha > beta + margin && gamma - alpha < beta - margin {
            let f = uncovered(x, alpha);
            penumbra += 1;
            sq_error += (measured - f).powi(2);
            sq_expected += f * (1.0 - f) / FRAMES as f64;
        }
    }
    let (rms, expected_rms) = ((sq_error / penumbra as f64).sqrt(), (sq_expected / penumbra as f64).sqrt());
    println!("{umbra} umbra, {lit} lit, {penumbra} penumbra pixels; {wrong_extremes} umbra or lit pixels not 0 or 1 in every frame; penumbra RMS against the integral {rms:.4} (Monte Carlo alone: {expected_rms:.4})");
    assert!(umbra > 50 && lit > 500 && penumbra > 200, "the view must show all three");
    assert_eq!(wrong_extremes, 0);
    // 64 samples: the error is the Monte Carlo error (binomial over the samples), within 20%
    // (the RMS over a few hundred pixels varies by about 5%; the tessellated sphere and the
    // mask's 8 bits, 0.002 at most, add a little).
    assert!(rms < 1.2 * expected_rms, "penumbra RMS {rms} against {expected_rms}");
}

/// A rectangle light (`light_width` x `light_height`) 6 units above the floor, pointing down
/// (its width along x, its height along z): the fraction of its area that the sphere leaves
/// uncovered from floor point `x`, on a 64 x 64 grid of the rectangle.
fn rectangle_uncovered(x: Vec3, light: Vec3, (w, h): (f32, f32)) -> f64 {
    let n = 64;
    let mut open = 0;
    for i in 0..n {
        for j in 0..n {
            let p = light + Vec3::new(((i as f32 + 0.5) / n as f32 - 0.5) * w, 0.0, ((j as f32 + 0.5) / n as f32 - 0.5) * h);
            let d = (p - x).normalize();
            let t = (CENTRE - x).dot(d).clamp(0.0, (p - x).length());
            open += ((x + d * t).distance(CENTRE) >= 1.0) as usize;
        }
    }
    open as f64 / (n * n) as f64
}

/// A rectangle light of 4 x 0.5 straight above the sphere: its penumbra, long along x and
/// short along z, matches the uncovered fraction of the rectangle (64 one-ray frames: within
/// 20% of the Monte Carlo error); no pixel is off by more than 0.5 (axes swapped or the light
/// facing the wrong way would be).
#[test]
fn a_rectangle_light_gives_the_penumbra_of_the_uncovered_area() {
    let light = Vec3::new(0.0, 6.0, 0.0);
    let size = (4.0, 0.5);
    let camera = Camera::look(Vec3::new(0.0, 7.0, 5.0), Vec3::ZERO, 50.0, 0.05, 100.0);
    let mut s = scene(camera);
    *s.lights_mut() = vec![raygraph::scene::PunctualLight {
        name: "panel".into(),
        kind: raygraph::scene::LightKind::Point { range: None },
        position: light,
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 40.0,
    }];
    let params = format!(r#""light_width": {}, "light_height": {}, "per_frame": true"#, size.0, size.1);
    let frames = masks(&graph(&params), &s, FRAMES);
    let dirs = camera.ray_dirs((W, H), 1);
    let (mut penumbra, mut gross, mut sq_error, mut sq_expected) = (0, 0, 0.0, 0.0);
    let (mut along_x, mut along_z) = (0.0f32, 0.0f32);
    for (i, d) in dirs.iter().enumerate() {
        let t_centre = (CENTRE - camera.position).dot(*d);
        if d.y >= 0.0 || (camera.position + *d * t_centre).distance(CENTRE) < 1.1 {
            continue;
        }
        let x = camera.position + *d * (-camera.position.y / d.y);
        if x.x.abs() > 5.5 || x.z.abs() > 5.5 {
            continue;
        }
        let measured = frames.iter().map(|f| f[i] as f64 / 255.0).sum::<f64>() / FRAMES as f64;
        let f = rectangle_uncovered(x, light, size);
        gross += ((measured - f).abs() > 0.5) as usize;
        if f > 0.0 && f < 1.0 {
            penumbra += 1;
            sq_error += (measured - f).powi(2);
            sq_expected += f * (1.0 - f) / FRAMES as f64;
            (along_x, along_z) = (along_x.max(x.x.abs()), along_z.max(x.z.abs()));
        }
    }
    let (rms, expected_rms) = ((sq_error / penumbra as f64).sqrt(), (sq_expected / penumbra as f64).sqrt());
    println!("{penumbra} penumbra pixels reaching |x| {along_x:.2}, |z| {along_z:.2}; {gross} off by more than 0.5; RMS {rms:.4} (Monte Carlo alone: {expected_rms:.4})");
    assert!(penumbra > 200 && along_x > along_z + 0.5, "a penumbra long along x");
    assert_eq!(gross, 0);
    assert!(rms < 1.2 * expected_rms, "penumbra RMS {rms} against {expected_rms}");
}
