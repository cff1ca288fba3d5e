//! Shadow maps in the Rasterization graph (`shadow_map` layer -> `forward` layer), on scenes
//! built in code, with the layers and shaders of the repository at their default parameters.
//!
//! "Shadowed" is read against a second render of the same graph with `shadows: false` on the
//! `forward` node: a pixel is *shadowed* when the sum of its RGB bytes is below
//! `SHADOWED_RATIO` times the unshadowed render's, and *darkened* when it is below it by more
//! than `DARKENED_SUM` (8-bit units summed over RGB; a lit pixel computes the same value, so
//! lit pixels should be equal). The tone map runs at exposure 0.25 with the sky off, so a lit
//! grey floor stays well below saturation and a floor in shadow (ambient only) is about a
//! quarter as bright.
//!
//! Analytic classification uses the pixel's camera ray: its hit on the plane y = 0 and its
//! footprint there (the largest distance to the hits of the neighbouring pixels' rays, in world
//! units per pixel), so a world distance to the analytic shadow outline divided by the
//! footprint is a lower bound of the distance in pixels.

mod common;

use common::gpu;

use glam::{Mat4, Vec3};
use raygraph::graph::{compile, Project};
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::builtin::{default_scene, plane, sphere};
use raygraph::scene::{Camera, Instance, Light, LightKind, Material, PunctualLight, Scene};

const W: u32 = 320;
const H: u32 = 240;
/// Shadowed: RGB sum below this fraction of the unshadowed render's.
const SHADOWED_RATIO: f64 = 0.6;
/// Darkened: RGB sum below the unshadowed render's by more than this.
const DARKENED_SUM: i32 = 3;
/// Pixels closer than this (in pixels) to the analytic shadow outline are not classified: the
/// 3x3 PCF, the shadow-map texels and the sphere's tessellation blur the edge.
const EDGE_MARGIN_PX: f64 = 3.0;
/// Half the width of the floor plane.
const FLOOR_HALF: f32 = 4.0;

/// A temporary project with the repository's layers and shaders and the Rasterization graph
/// written with `shadows` set on the forward node (every other parameter at its default).
struct Graphs {
    project: common::TempProject,
}

impl Graphs {
    fn new() -> Self {
        let project = common::TempProject::with_repo_files();
        for shadows in [false, true] {
            let text = format!(
                r#"// graph/raster.ron with `shadows: {shadows}` and a tone map that keeps a lit floor unsaturated.
Graph(
    output: "tonemap.color",
    nodes: {{
        "shadow_map": Layer(layer: "shadow_map"),
        "forward": Layer(
            layer: "forward",
            inputs: {{"shadow_map": "shadow_map.depth", "shadow_cube": "shadow_map.cube"}},
            params: {{"shadows": {shadows}}},
        ),
        "tonemap": Layer(
            layer: "tonemap",
            inputs: {{"hdr": "forward.color"}},
            params: {{"exposure": 0.25, "sky": false}},
        ),
    }},
)
"#
            );
            project.write(&format!("graph/shadows_{shadows}.ron"), &text);
        }
        Self { project }
    }

    /// The same graphs over a `shadow_map` layer that draws both sides of every triangle
    /// (`cull_closed_back_faces: false`).
    fn without_closed_culling() -> Self {
        let graphs = Self::new();
        let path = graphs.project.root.join("layers/shadow_map.ron");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("cull_closed_back_faces: true"), "the shipped shadow_map layer culls closed meshes");
        std::fs::write(&path, text.replace("cull_closed_back_faces: true", "cull_closed_back_faces: false")).unwrap();
        graphs
    }

    fn render(&self, gpu: &Gpu, shadows: bool, scene: &Scene, camera: &Camera) -> image::RgbaImage {
        let path = self.project.root.join(format!("graph/shadows_{shadows}.ron"));
        let plan = compile(&path, &Project::beside_graph(&path), (W, H)).unwrap_or_else(|e| panic!("{e}"));
        let mut exec = Executor::new(gpu, plan, scene).unwrap();
        exec.render(gpu, camera, scene).unwrap();
        exec.read_output(gpu).unwrap()
    }
}

/// A grey floor (`FLOOR_HALF` * 2 wide at y = 0), optionally a grey sphere `sphere_at` =
/// (centre, radius), under a directional light towards `light`, seen by `camera`.
fn scene(sphere_at: Option<(Vec3, f32)>, light: Vec3, camera: Camera) -> Scene {
    let mut s = default_scene();
    s.set_name("shadow test");
    s.set_meshes(vec![plane("floor", 2.0 * FLOOR_HALF, 1.0), sphere("ball", 48, 96)]);
    *s.textures_mut() = Vec::new();
    *s.materials_mut() = vec![Material::diffuse("grey", [0.8, 0.8, 0.8, 1.0], None)];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }];
    if let Some((c, r)) = sphere_at {
        s.instances_mut().push(Instance { mesh: 1, material: 0, transform: Mat4::from_scale_rotation_translation(Vec3::splat(r), glam::Quat::IDENTITY, c) });
    }
    *s.light_mut() = Light { direction: light.normalize(), color: Vec3::ONE, intensity: 3.0, ambient: 0.35 };
    *s.camera_mut() = camera;
    *s.presets_mut() = vec![("main".into(), camera)];
    s
}

/// Camera rays of the frame.
struct Rays {
    origin: Vec3,
    inv_view_proj: Mat4,
}

impl Rays {
    fn new(camera: &Camera) -> Self {
        Self { origin: camera.position, inv_view_proj: camera.view_proj(W as f32 / H as f32).inverse() }
    }

    /// Unit direction through the point (x, y) in pixels (pixel centres at +0.5).
    fn dir(&self, x: f64, y: f64) -> Vec3 {
        let ndc = glam::Vec4::new((x / W as f64 * 2.0 - 1.0) as f32, (1.0 - y / H as f64 * 2.0) as f32, 1.0, 1.0);
        let p = self.inv_view_proj * ndc;
        (p.truncate() / p.w - self.origin).normalize()
    }

    /// Where the ray through (x, y) meets y = 0.
    fn floor_hit(&self, x: f64, y: f64) -> Option<Vec3> {
        let d = self.dir(x, y);
        (d.y < 0.0).then(|| self.origin + d * (-self.origin.y / d.y))
    }

    /// The floor point seen at pixel (px, py) and the footprint there (world units per pixel),
    /// for pixels whose ray meets the floor at least `EDGE_MARGIN_PX` pixels inside its edge.
    fn floor_pixel(&self, px: u32, py: u32) -> Option<(Vec3, f32)> {
        let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
        let p = self.floor_hit(x, y)?;
        let fx = self.floor_hit(x + 1.0, y)?.distance(p);
        let fy = self.floor_hit(x, y + 1.0)?.distance(p);
        let f = fx.max(fy);
        let inside = FLOOR_HALF - EDGE_MARGIN_PX as f32 * f;
        (p.x.abs() < inside && p.z.abs() < inside).then_some((p, f))
    }

    /// Whether the ray through pixel (px, py) passes within `radius` of `centre` (in front of
    /// the camera).
    fn passes_near(&self, px: u32, py: u32, centre: Vec3, radius: f32) -> bool {
        let d = self.dir(px as f64 + 0.5, py as f64 + 0.5);
        let t = (centre - self.origin).dot(d);
        t > 0.0 && (self.origin + d * t).distance(centre) < radius
    }
}

fn rgb_sum(img: &image::RgbaImage, x: u32, y: u32) -> i32 {
    let p = img.get_pixel(x, y);
    p[0] as i32 + p[1] as i32 + p[2] as i32
}

fn look(position: Vec3, target: Vec3) -> Camera {
    Camera::look(position, target, 50.0, 0.05, 100.0)
}

/// The floor pixels of a sphere scene classified against an analytic shadow outline.
#[derive(Default)]
struct Tally {
    inside: usize,
    inside_ok: usize,
    outside: usize,
    outside_ok: usize,
    worst_inside_ratio: f64,
    worst_outside_darkening: i32,
}

impl Tally {
    /// Every floor pixel of `img` (shadows on) against `lit_img` (off) whose ray does not pass
    /// within 1.1 radii of the sphere (`centre`, `radius`): at least `EDGE_MARGIN_PX` pixels
    /// inside the outline (`to_outline(floor point)`, a world distance on the floor, negative
    /// inside) it must be shadowed, at least that far outside not darkened at all.
    fn of(img: &image::RgbaImage, lit_img: &image::RgbaImage, camera: &Camera, (centre, radius): (Vec3, f32), to_outline: impl Fn(Vec3) -> f32) -> Self {
        let rays = Rays::new(camera);
        let mut t = Tally::default();
        for py in 0..H {
            for px in 0..W {
                let Some((p, footprint)) = rays.floor_pixel(px, py) else { continue };
                if rays.passes_near(px, py, centre, 1.1 * radius) {
                    continue;
                }
                let to_outline_px = to_outline(p) as f64 / footprint as f64;
                let (on, sh) = (rgb_sum(lit_img, px, py), rgb_sum(img, px, py));
                let ratio = sh as f64 / on.max(1) as f64;
                if to_outline_px < -EDGE_MARGIN_PX {
                    t.inside += 1;
                    t.inside_ok += (ratio < SHADOWED_RATIO) as usize;
                    t.worst_inside_ratio = t.worst_inside_ratio.max(ratio);
                } else if to_outline_px > EDGE_MARGIN_PX {
                    t.outside += 1;
                    t.outside_ok += (on - sh <= DARKENED_SUM) as usize;
                    t.worst_outside_darkening = t.worst_outside_darkening.max(on - sh);
                }
            }
        }
        t
    }

    fn report(&self, what: &str) {
        println!(
            "{what}: {}/{} floor pixels > {EDGE_MARGIN_PX} px inside the shadow shadowed (highest shadowed/lit ratio {:.3}, limit {SHADOWED_RATIO}); \
             {}/{} pixels > {EDGE_MARGIN_PX} px outside lit (largest darkening {}, limit {DARKENED_SUM})",
            self.inside_ok, self.inside, self.worst_inside_ratio, self.outside_ok, self.outside, self.worst_outside_darkening
        );
    }

    /// Every classified pixel right, with at least `inside` and `outside` of them.
    fn assert_right(&self, what: &str, inside: usize, outside: usize) {
        assert!(
            self.inside > inside && self.outside > outside,
            "{what}: the view must show the shadow and the floor around it: {} inside, {} outside",
            self.inside,
            self.outside
        );
        assert_eq!(self.inside_ok, self.inside, "{what}: pixels inside the analytic shadow are lit (highest ratio {:.3})", self.worst_inside_ratio);
        assert_eq!(self.outside_ok, self.outside, "{what}: pixels outside the analytic shadow are darkened (by up to {})", self.worst_outside_darkening);
    }
}

/// (a) A sphere of radius 1 centred 2.5 above the floor, the light straight above: the floor's
/// shadow is the disc of radius 1 under the sphere's centre. Every floor pixel at least
/// `EDGE_MARGIN_PX` pixels inside its outline is shadowed, every one at least that far outside
/// is lit (and not darkened at all). Pixels whose ray passes within 1.1 radii of the sphere's
/// centre (the sphere itself, and its silhouette) are left out.
#[test]
fn a_sphere_above_the_floor_casts_a_disc_of_its_radius_straight_down() {
    let gpu = gpu();
    let graphs = Graphs::new();
    let (centre, radius) = (Vec3::new(0.0, 2.5, 0.0), 1.0f32);
    for camera in [look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO), look(Vec3::new(-7.0, 4.5, -3.0), Vec3::new(0.0, 0.5, 0.0))] {
        let s = scene(Some((centre, radius)), Vec3::Y, camera);
        let lit_img = graphs.render(&gpu, false, &s, &camera);
        let img = graphs.render(&gpu, true, &s, &camera);
        let tally = Tally::of(&img, &lit_img, &camera, (centre, radius), |p| Vec3::new(p.x, 0.0, p.z).length() - radius);
        let what = format!("camera at {:?}", camera.position);
        tally.report(&what);
        tally.assert_right(&what, 300, 10_000);
    }
}

/// The floor pixels of `s` (seen by `camera`, with shadows on), how many of them the shadows
/// darken by more than `DARKENED_SUM`, and the largest darkening.
fn darkened_floor(graphs: &Graphs, gpu: &Gpu, s: &Scene, camera: &Camera) -> (usize, usize, i32) {
    let lit_img = graphs.render(gpu, false, s, camera);
    let img = graphs.render(gpu, true, s, camera);
    let rays = Rays::new(camera);
    let (mut floor, mut darkened, mut worst) = (0usize, 0usize, 0i32);
    for (px, py) in (0..H).flat_map(|y| (0..W).map(move |x| (x, y))) {
        if rays.floor_pixel(px, py).is_some() {
            floor += 1;
            let d = rgb_sum(&lit_img, px, py) - rgb_sum(&img, px, py);
            darkened += (d > DARKENED_SUM) as usize;
            worst = worst.max(d);
        }
    }
    (floor, darkened, worst)
}

/// (b) Shadow acne: a lone floor with nothing above it, lit from straight above, 45 degrees
/// and 70 degrees from the zenith (two azimuths each), seen from four cameras (grazing, high,
/// around the floor): no floor pixel is darkened at all by the shadow map.
#[test]
fn an_open_floor_has_no_shadow_acne_from_any_view() {
    let gpu = gpu();
    let graphs = Graphs::new();
    // (degrees from the zenith, azimuth in degrees)
    let lights = [(0.0, 0.0), (45.0, 0.0), (45.0, 135.0), (70.0, 60.0), (70.0, 210.0)].map(|(z, a): (f32, f32)| {
        let (z, a) = (z.to_radians(), a.to_radians());
        Vec3::new(z.sin() * a.cos(), z.cos(), z.sin() * a.sin())
    });
    let cameras = [
        look(Vec3::new(0.0, 1.2, 7.0), Vec3::new(0.0, 0.0, 0.0)),
        look(Vec3::new(5.5, 3.0, 5.5), Vec3::new(0.0, 0.0, 0.0)),
        look(Vec3::new(-6.0, 1.0, -2.0), Vec3::new(0.0, 0.0, 0.5)),
        look(Vec3::new(0.5, 9.0, 1.0), Vec3::new(0.0, 0.0, 0.0)),
    ];
    let mut total = 0usize;
    for light in lights {
        for camera in cameras {
            let s = scene(None, light, camera);
            let (floor, darkened, worst) = darkened_floor(&graphs, &gpu, &s, &camera);
            let zenith = light.normalize().y.acos().to_degrees();
            println!(
                "light {zenith:.0} deg from the zenith, camera at {:?}: {darkened} of {floor} floor pixels darkened (largest darkening {worst})",
                camera.position
            );
            assert!(floor > 10_000, "the view must show the floor ({floor} pixels)");
            assert_eq!(
                darkened, 0,
                "shadow acne: {darkened} of {floor} floor pixels darkened by up to {worst} (light {light:?}, camera {:?})",
                camera.position
            );
            total += floor;
        }
    }
    println!("{total} floor pixels checked");
}

/// (c) `shadows: false`: the sphere scene of (a) draws its floor exactly as a floor with
/// nothing above it does (every floor pixel not covered by the sphere, within 1 per channel),
/// while the same scene with shadows on does not.
#[test]
fn shadows_off_draw_the_floor_fully_lit() {
    let gpu = gpu();
    let graphs = Graphs::new();
    let (centre, radius) = (Vec3::new(0.0, 2.5, 0.0), 1.0f32);
    let camera = look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO);
    let with_sphere = scene(Some((centre, radius)), Vec3::new(0.3, 1.0, -0.2), camera);
    let open = scene(None, Vec3::new(0.3, 1.0, -0.2), camera);
    let off = graphs.render(&gpu, false, &with_sphere, &camera);
    let on = graphs.render(&gpu, true, &with_sphere, &camera);
    let reference = graphs.render(&gpu, false, &open, &camera);
    let rays = Rays::new(&camera);
    let (mut floor, mut off_differs, mut on_shadowed, mut worst) = (0usize, 0usize, 0usize, 0i32);
    for py in 0..H {
        for px in 0..W {
            if rays.floor_pixel(px, py).is_none() || rays.passes_near(px, py, centre, 1.1 * radius) {
                continue;
            }
            floor += 1;
            let (a, b) = (off.get_pixel(px, py), reference.get_pixel(px, py));
            let d = (0..3).map(|c| (a[c] as i32 - b[c] as i32).abs()).max().unwrap();
            off_differs += (d > 1) as usize;
            worst = worst.max(d);
            on_shadowed += ((rgb_sum(&on, px, py) as f64) < SHADOWED_RATIO * rgb_sum(&reference, px, py) as f64) as usize;
        }
    }
    println!(
        "shadows off: {off_differs} of {floor} floor pixels differ from the open floor by more than 1 (largest {worst}); shadows on: {on_shadowed} shadowed"
    );
    assert!(floor > 10_000);
    assert_eq!(off_differs, 0, "with shadows off the sphere still darkens the floor (by up to {worst})");
    assert!(on_shadowed > 500, "with shadows on the sphere should shadow the floor ({on_shadowed} pixels)");
}

/// (d) Closed meshes' back faces culled in the shadow maps (`cull_closed_back_faces`) change
/// no pixel: a closed sphere above the floor under the sun, under a spot light above it, and
/// with a spot light inside it (the sphere then holds the light, is not culled, and shadows
/// everything around it but the floor lit through nothing: a wrongly culled sphere would let
/// its light out). The images must be identical, byte for byte: the nearest depth seen from a
/// light outside a closed mesh is the same triangle's either way.
#[test]
fn culling_closed_meshes_in_shadow_maps_changes_no_pixel() {
    let gpu = gpu();
    let (culling, both_sides) = (Graphs::new(), Graphs::without_closed_culling());
    let (centre, radius) = (Vec3::new(0.0, 1.5, 0.0), 1.0f32);
    let camera = look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO);
    let spot = |position: Vec3| PunctualLight {
        name: "spot".into(),
        kind: LightKind::Spot { range: None, inner_cone: 0.9, outer_cone: 1.2 },
        position,
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 20.0,
    };
    let cases: [(&str, Vec<PunctualLight>); 3] =
        [("sun", Vec::new()), ("spot above", vec![spot(Vec3::new(0.5, 4.0, 0.0))]), ("spot inside", vec![spot(centre)])];
    for (name, lights) in cases {
        let mut s = scene(Some((centre, radius)), Vec3::new(0.3, 1.0, -0.2), camera);
        *s.lights_mut() = lights;
        let a = culling.render(&gpu, true, &s, &camera);
        let b = both_sides.render(&gpu, true, &s, &camera);
        let lit = culling.render(&gpu, false, &s, &camera);
        let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
        let shadowed =
            (0..H).flat_map(|y| (0..W).map(move |x| (x, y))).filter(|&(x, y)| (rgb_sum(&a, x, y) as f64) < SHADOWED_RATIO * rgb_sum(&lit, x, y) as f64).count();
        println!("{name}: {differ} pixels differ with both sides drawn; {shadowed} pixels shadowed");
        assert!(shadowed > 500, "{name}: the view must show a shadow ({shadowed} pixels)");
        assert_eq!(differ, 0, "{name}: culling closed meshes changed {differ} pixels");
    }
}

/// A point light at `position` (a cube shadow map in raster mode while it is among the first
/// two point lights).
fn point(position: Vec3, intensity: f32) -> PunctualLight {
    PunctualLight { name: "point".into(), kind: LightKind::Point { range: None }, position, direction: Vec3::NEG_Y, color: Vec3::ONE, intensity }
}

/// `scene` lit by the point lights `lights` alone and a dim sky (ambient 0.03 against the sun
/// scenes' 0.35): a point light's shadow reaches far across the floor, where its inverse-square
/// light is weak, and `SHADOWED_RATIO` compares a shadowed pixel's ambient light with the lit
/// one's ambient and direct light.
fn point_lit(sphere_at: Option<(Vec3, f32)>, lights: Vec<PunctualLight>, camera: Camera) -> Scene {
    let mut s = scene(sphere_at, Vec3::Y, camera);
    *s.lights_mut() = lights;
    s.light_mut().ambient = 0.03;
    s
}

/// World distance on the floor from floor point `p` to the outline of the shadow a sphere
/// (`centre`, `radius`) casts from a point light at `light` (negative inside): the distance
/// from the centre to the segment from the light to `p`, less the radius, carried out to `p`
/// along the segment (a lower bound of the distance on the floor, which the slant only
/// lengthens).
fn cone_outline(light: Vec3, (centre, radius): (Vec3, f32), p: Vec3) -> f32 {
    let length = (p - light).length();
    let u = (p - light) / length;
    let t = (centre - light).dot(u).clamp(0.0, length);
    if t <= 0.0 {
        return f32::INFINITY; // the sphere is behind the light
    }
    ((light + u * t).distance(centre) - radius) * length / t
}

/// (e) Point lights' cube shadow maps: a sphere of radius 0.8 at 1.2 above the floor and a
/// point light straight above it, beside it and low to the other side, so that the shadow
/// falls through different faces of the cube map and across their edges. The floor's shadow is
/// the cone from the light through the sphere ([`cone_outline`]); every floor pixel at least
/// `EDGE_MARGIN_PX` pixels inside it is shadowed, every one at least that far outside is lit.
#[test]
fn a_point_light_casts_the_cone_of_a_sphere_through_its_cube_map() {
    let gpu = gpu();
    let graphs = Graphs::new();
    let sphere_at = (Vec3::new(0.0, 1.2, 0.0), 0.8f32);
    let lights = [Vec3::new(0.0, 4.0, 0.0), Vec3::new(2.2, 3.0, 1.0), Vec3::new(-1.8, 2.2, -1.4)];
    let cameras = [look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO), look(Vec3::new(-7.0, 4.5, -3.0), Vec3::new(0.0, 0.5, 0.0))];
    for light in lights {
        for camera in cameras {
            let s = point_lit(Some(sphere_at), vec![point(light, 30.0)], camera);
            let lit_img = graphs.render(&gpu, false, &s, &camera);
            let img = graphs.render(&gpu, true, &s, &camera);
            let tally = Tally::of(&img, &lit_img, &camera, sphere_at, |p| cone_outline(light, sphere_at, p));
            let what = format!("point light at {light:?}, camera at {:?}", camera.position);
            tally.report(&what);
            tally.assert_right(&what, 300, 10_000);
        }
    }
}

/// (f) Shadow acne under point lights: a lone floor lit by a point light high above it, low
/// over it (the floor then spans five faces of the cube map, at grazing angles far out) and
/// off its corner, from three cameras: no floor pixel is darkened at all by the cube map, on a
/// face or along the edge between two.
#[test]
fn an_open_floor_under_a_point_light_has_no_acne_on_any_cube_face() {
    let gpu = gpu();
    let graphs = Graphs::new();
    let lights = [Vec3::new(0.0, 3.0, 0.0), Vec3::new(1.0, 0.6, -0.5), Vec3::new(-4.5, 2.0, 3.5)];
    let cameras = [
        look(Vec3::new(0.0, 1.2, 7.0), Vec3::new(0.0, 0.0, 0.0)),
        look(Vec3::new(5.5, 3.0, 5.5), Vec3::new(0.0, 0.0, 0.0)),
        look(Vec3::new(0.5, 9.0, 1.0), Vec3::new(0.0, 0.0, 0.0)),
    ];
    for light in lights {
        for camera in cameras {
            let s = point_lit(None, vec![point(light, 20.0)], camera);
            let (floor, darkened, worst) = darkened_floor(&graphs, &gpu, &s, &camera);
            println!("point light at {light:?}, camera at {:?}: {darkened} of {floor} floor pixels darkened (largest {worst})", camera.position);
            assert!(floor > 10_000, "the view must show the floor ({floor} pixels)");
            assert_eq!(
                darkened, 0,
                "shadow acne: {darkened} of {floor} floor pixels darkened by up to {worst} (light {light:?}, camera {:?})",
                camera.position
            );
        }
    }
}

/// (g) The slots: the second point light has a cube map of its own (slots 10-15); a third of
/// the same power has none (the documented limit: it lights the raster mode unshadowed), and a
/// third more powerful than the others takes one from them. The lights other than the one
/// above the sphere sit under the floor, so they light none of it.
#[test]
fn the_two_most_powerful_point_lights_have_cube_maps() {
    let gpu = gpu();
    let graphs = Graphs::new();
    let sphere_at = (Vec3::new(0.0, 1.2, 0.0), 0.8f32);
    let above = Vec3::new(0.0, 4.0, 0.0);
    let under = |x: f32| point(Vec3::new(x, -3.0, 0.0), 30.0);
    let camera = look(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO);
    let tally = |lights: Vec<PunctualLight>| {
        let s = point_lit(Some(sphere_at), lights, camera);
        let (img, lit_img) = (graphs.render(&gpu, true, &s, &camera), graphs.render(&gpu, false, &s, &camera));
        Tally::of(&img, &lit_img, &camera, sphere_at, |p| cone_outline(above, sphere_at, p))
    };
    let second = tally(vec![under(0.0), point(above, 30.0)]);
    second.report("second point light");
    second.assert_right("second point light", 300, 10_000);

    let third = tally(vec![under(1.0), under(0.0), point(above, 30.0)]);
    third.report("third point light, of equal power");
    assert!(third.inside > 300, "the view must show where the shadow would be ({} pixels)", third.inside);
    assert_eq!(third.inside_ok, 0, "a third point light has no cube map, so nothing is shadowed ({} pixels are)", third.inside_ok);

    let brightest = tally(vec![under(1.0), under(0.0), point(above, 40.0)]);
    brightest.report("third point light, the most powerful");
    brightest.assert_right("third point light, the most powerful", 300, 10_000);
}
