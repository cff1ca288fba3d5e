//! The reference-channel suite: every ray-traced channel of the full ray-tracing graph against the f64 reference renderer
//! (`accel::reference_render`), pixel by pixel, on the built-in `default` scene and a small
//! scene of a floor, a wall, a sphere and two cubes, one mirrored (each with a point light
//! added), at 64x48, on every back-end and layout (`compute` and `rt-pipeline` with
//! the merged layout, as the graph ships, and two-level; `ray-query` two-level).
//!
//! The secondary channels are rebuilt from the GPU's own G-buffer (position, geometric and
//! shading normal as stored), so each comparison checks one trace pass: the reference builds
//! the same f32 rays and traces them in f64. Metric and tolerance: a pixel's GPU answer must
//! equal the reference's, except where the reference's margin (the smallest relative
//! perturbation of the ray that could change its answer: a triangle edge passed within that
//! distance, a ray end, a second surface at nearly the same depth) is below `MARGIN`, 1e-5 of
//! the coordinate magnitude (about 80 f32 ulps: the GPU rounds its own camera directions,
//! normalisations, square roots, sines and cosines, and may fuse multiply-adds). Primary hits
//! must also lie where the reference's hit is (within 1e-4 of the depth). AO (sampling "net",
//! whose numbers the reference mirrors as it does R2's): per pixel the
//! number of unoccluded rays may differ from the reference's by at most the number of that
//! pixel's rays within the margin, and the mean absolute difference of the unoccluded fraction
//! over all pixels must stay below 1e-3. The mirror channel is a test-only trace pass that
//! writes the instance and triangle hit by the first ray of `rt_reflection` for a mirror.
//!
//! The graph, layers and shaders are the built-in copies, with the mirror layer and shader
//! added, in a private temporary project (`ChannelProject`). `tests/reference_channels.rs` and
//! `raygraph selftest` run these same functions.

use super::target::Target;
use crate::accel::cpu_traverse::Ray;
use crate::accel::reference::RefHit;
use crate::accel::reference_render::{AoSettings, Classified, ReferenceRenderer, SurfacePoint};
use crate::graph::compile::{compile_with, CompileOptions, Project};
use crate::runtime::{Executor, Gpu};
use crate::scene::{builtin, Camera, Instance, LoadOptions, PointLight, Scene};
use glam::{Mat4, Quat, Vec3};
use std::path::{Path, PathBuf};

/// The largest margin at which the GPU may disagree with the reference (module docs).
const MARGIN: f64 = 1e-5;
const SIZE: (u32, u32) = (64, 48);
const AO_RAYS: u32 = 8;

pub(crate) const MIRROR_LAYER: &str = r#"// Test only: the instance and triangle that the first ray of rt_reflection hits for a mirror.
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

pub(crate) const MIRROR_SHADER: &str = r#"// The first ray of shaders/rt/reflection.wgsl for a mirror (roughness below 0.03), its hit ids.
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
pub fn scenes() -> Result<Vec<Scene>, String> {
    let (default, _) = crate::scene::open("default", &LoadOptions { textures: false, ..Default::default() }).map_err(|e| format!("opening default: {e}"))?;
    let mut small = default.clone();
    small.set_name("small");
    small.set_meshes(vec![builtin::plane("floor", 8.0, 1.0), builtin::sphere("ball", 16, 32), builtin::cube("box")]);
    let wall = Mat4::from_translation(Vec3::new(0.0, 2.0, -2.5)) * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let ball = Mat4::from_scale_rotation_translation(Vec3::splat(0.7), Quat::IDENTITY, Vec3::new(0.0, 0.7, 0.0));
    let cube = Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(-1.4, 0.5, -0.6));
    let mirrored = Mat4::from_scale_rotation_translation(Vec3::new(-0.8, 0.8, 0.8), Quat::from_rotation_y(-0.3), Vec3::new(1.3, 0.4, 0.8));
    small.set_instances(
        [(0, Mat4::IDENTITY), (0, wall), (1, ball), (2, cube), (2, mirrored)]
            .iter()
            .map(|&(mesh, transform)| Instance { mesh, material: 0, transform })
            .collect(),
    );
    *small.camera_mut() = Camera::look(Vec3::new(2.5, 2.2, 4.0), Vec3::new(0.0, 0.5, 0.0), 50.0, 0.05, 100.0);
    small.light_mut().direction = Vec3::new(-0.4, 0.8, 0.45).normalize();
    let mut scenes = vec![default, small];
    for s in &mut scenes {
        let b = s.bounds();
        s.set_point_light(Some(PointLight { position: b.center() + Vec3::new(0.3, 0.45, 0.2) * b.diagonal(), color: Vec3::ONE, intensity: 5.0 }));
    }
    Ok(scenes)
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

/// A private copy of the full ray-tracing graph with the mirror layer added, in two layouts
/// (merged, as the graph ships, and two-level), each also as a graph whose output is the mirror
/// pass's mask; the folder is removed when dropped. Layers and shaders not written here are the
/// built-in copies.
pub struct ChannelProject {
    dir: PathBuf,
    merged: (PathBuf, PathBuf),
    two_level: (PathBuf, PathBuf),
    /// AO rays of this fraction of the scene's bounding radius.
    range_scale: f32,
}

impl Drop for ChannelProject {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

impl ChannelProject {
    /// Writes the project into a fresh temporary folder.
    pub fn new() -> Result<Self, String> {
        static COUNT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("raygraph-selftest-{}-{n}", std::process::id()));
        let write = |rel: &str, text: &str| -> Result<PathBuf, String> {
            let path = dir.join(rel);
            std::fs::create_dir_all(path.parent().unwrap_or(&dir)).map_err(|e| format!("creating {}: {e}", dir.display()))?;
            std::fs::write(&path, text).map_err(|e| format!("writing {}: {e}", path.display()))?;
            Ok(path)
        };
        write("layers/test_mirror_ids.ron", MIRROR_LAYER)?;
        write("shaders/test/mirror_ids.wgsl", MIRROR_SHADER)?;
        let range_scale = 0.2f32;
        let shipped = crate::graph::files::read(&dir.join("graph/full_rt.ron")).map_err(|e| format!("reading graph/full_rt.ron: {e}"))?.text;
        let full_rt = shipped
            .replace(r#"params: {"rays": 8, "range_scale": 0.05}"#, &format!(r#"params: {{"rays": {AO_RAYS}, "range": 0.0, "range_scale": {range_scale:?}, "sampling": 2}}"#))
            .replace(
                r#""resolve": Layer("#,
                r#""mirror": Layer(layer: "test_mirror_ids", inputs: {"position": "gbuffer.position", "normal": "gbuffer.normal", "geo_normal": "gbuffer.geo_normal", "tlas": "accel.tlas"}),
        "resolve": Layer("#,
            );
        ensure!(full_rt.contains(r#""range_scale": 0.2"#) && full_rt.contains("test_mirror_ids"), "graph/full_rt.ron changed: update the suite's edits");
        // The graph's output decides which passes run: the mirror pass's mask is a second
        // graph's output (the same G-buffer, then only the mirror pass).
        let mirror_graph = full_rt.replace(r#"output: "tonemap.color""#, r#"output: "mirror.mask""#);
        ensure!(mirror_graph != full_rt, "graph/full_rt.ron's output changed: update the suite");
        let two_level = |g: &str| g.replace("Accel(merge: true)", "Accel()");
        let merged = (write("graph/merged.ron", &full_rt)?, write("graph/merged_mirror.ron", &mirror_graph)?);
        let two_level = (write("graph/two_level.ron", &two_level(&full_rt))?, write("graph/two_level_mirror.ron", &two_level(&mirror_graph))?);
        Ok(Self { dir, merged, two_level, range_scale })
    }
}

/// One frame of `graph`, without texture reuse so every channel can be read back.
fn render(target: &Target, graph: &Path, scene: &Scene) -> Result<Executor, String> {
    let gpu = target.gpu;
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(target.variant.backend) };
    let plan = compile_with(graph, &Project::beside_graph(graph), SIZE, &options).map_err(|e| e.to_string())?;
    let mut exec = Executor::new(gpu, plan, scene).map_err(|e| e.to_string())?;
    exec.render(gpu, scene.camera(), scene).map_err(|e| e.to_string())?;
    Ok(exec)
}

fn read(gpu: &Gpu, exec: &Executor, name: &str) -> Result<Vec<[f32; 4]>, String> {
    let r = exec.plan().resource_by_name(name).ok_or_else(|| format!("no resource {name}"))?;
    Ok(exec.read_texture_f32(gpu, r).map_err(|e| e.to_string())?.2)
}

fn xyz(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// A scene with the reference's camera rays, visibility and surfaces, made once and compared
/// with every back-end.
pub struct ChannelScene {
    scene: Scene,
    renderer: ReferenceRenderer,
    settings: AoSettings,
    rays: Vec<Ray>,
    visibility: Vec<Classified<Option<RefHit>>>,
    own_surfaces: Vec<Option<SurfacePoint>>,
}

impl ChannelScene {
    /// The reference's primary answers for `scene` in `project`'s AO settings.
    pub fn new(scene: Scene, project: &ChannelProject) -> Self {
        let renderer = ReferenceRenderer::new(&scene);
        let settings = AoSettings { rays: AO_RAYS, range: project.range_scale * (0.5 * scene.bounds().diagonal()).max(1e-6), sampling: 2, seed: 0 };
        let rays = ReferenceRenderer::camera_rays(scene.camera(), SIZE);
        let visibility = renderer.visibility(&rays);
        let own_surfaces = renderer.surfaces(&rays, &visibility);
        Self { scene, renderer, settings, rays, visibility, own_surfaces }
    }

    /// What the scene is, for the notes.
    pub fn describe(&self) -> String {
        let hit = self.own_surfaces.iter().flatten().count();
        format!("{}: {} triangles, {hit} of {} pixels hit", self.scene.name(), self.renderer.reference.triangle_count(), self.rays.len())
    }

    /// Primary visibility against the reference's own camera rays; where both hit, the
    /// G-buffer's point is the reference's and its geometric normal the triangle's (the
    /// largest 1 - cos returned).
    fn primary(&self, pos: &[[f32; 4]], geo: &[[f32; 4]]) -> (Tally, f32) {
        let mut primary = Tally::default();
        let mut worst_normal = 0.0f32;
        for (i, ray) in self.rays.iter().enumerate() {
            let r = &self.visibility[i];
            let agree = match (pos[i][3] != 0.0, r.value) {
                (false, None) => true,
                (true, Some(h)) => {
                    let at = ray.origin.as_dvec3() + h.t * ray.dir.as_dvec3();
                    let close = (xyz(pos[i]).as_dvec3() - at).length() <= 1e-4 * h.t;
                    if let (true, true, Some(own)) = (close, r.margin >= MARGIN, self.own_surfaces[i]) {
                        worst_normal = worst_normal.max(1.0 - xyz(geo[i]).normalize().dot(own.geo_normal));
                    }
                    close
                }
                _ => false,
            };
            primary.add(agree, r.margin);
        }
        (primary, worst_normal)
    }

    /// The sun and point-light shadow tallies from the GPU's G-buffer surfaces.
    fn shadows(&self, surfaces: &[Option<SurfacePoint>], shadow: &[[f32; 4]]) -> Result<(Tally, Tally), String> {
        let (mut sun, mut point) = (Tally::default(), Tally::default());
        for (i, s) in self.renderer.shadow(surfaces, self.scene.light(), self.scene.point_light()).iter().enumerate() {
            let Some(s) = s else { continue };
            sun.add((shadow[i][0] == 1.0) == s.sun.value, s.sun.margin);
            let lit = s.point.ok_or("the scene has a point light")?;
            point.add((shadow[i][1] == 1.0) == lit.value, lit.margin);
        }
        Ok((sun, point))
    }

    /// The AO rays' tally, the mean absolute difference of the unoccluded fraction and the
    /// pixels compared.
    fn ao(&self, surfaces: &[Option<SurfacePoint>], ao: &[[f32; 4]]) -> (Tally, f64, usize) {
        let mut ao_rays = Tally::default();
        let (mut difference, mut pixels) = (0.0, 0usize);
        for (i, rays_of_pixel) in self.renderer.ao(surfaces, SIZE.0, &self.settings).iter().enumerate() {
            let Some(rays_of_pixel) = rays_of_pixel else { continue };
            let open = rays_of_pixel.iter().filter(|c| c.value).count() as i64;
            let within_margin = rays_of_pixel.iter().filter(|c| c.margin < MARGIN).count() as i64;
            let gpu_open = (ao[i][0] * AO_RAYS as f32).round() as i64;
            let diff = (gpu_open - open).abs();
            ao_rays.compared += rays_of_pixel.len();
            ao_rays.excused += diff.min(within_margin) as usize;
            ao_rays.wrong += (diff - within_margin).max(0) as usize;
            difference += diff as f64 / AO_RAYS as f64;
            pixels += 1;
        }
        (ao_rays, difference / pixels.max(1) as f64, pixels)
    }

    /// The mirror rays' tally.
    fn mirror(&self, surfaces: &[Option<SurfacePoint>], mirror: &[[f32; 4]]) -> Tally {
        let mut mirrored = Tally::default();
        for (i, m) in self.renderer.mirror(self.scene.camera().position, surfaces).iter().enumerate() {
            let Some(m) = m else { continue };
            let gpu_hit = (mirror[i][0] >= 0.0).then(|| (mirror[i][0] as u32, mirror[i][1] as u32));
            mirrored.add(gpu_hit == m.value.map(|h| (h.instance_id, h.prim)), m.margin);
        }
        mirrored
    }

    /// Renders the graph on `target` (its layout's graphs from `project`) and compares every
    /// channel with the reference, pixel by pixel (module docs).
    pub fn compare(&self, project: &ChannelProject, target: &Target, notes: &mut Vec<String>) -> Result<(), String> {
        let (gpu, scene, variant) = (target.gpu, &self.scene, target.variant.name);
        let graphs = if target.variant.merge { &project.merged } else { &project.two_level };
        let exec = render(target, &graphs.0, scene)?;
        let (pos, normal, geo) = (read(gpu, &exec, "gbuffer.position")?, read(gpu, &exec, "gbuffer.normal")?, read(gpu, &exec, "gbuffer.geo_normal")?);
        let (shadow, ao) = (read(gpu, &exec, "shadow.shadow")?, read(gpu, &exec, "ao.ao")?);
        let mirror_exec = render(target, &graphs.1, scene)?;
        let mirror = read(gpu, &mirror_exec, "mirror.ids")?;
        // The mirror graph's own G-buffer is checked against the reference too, and its mirror
        // rays start from it: a driver that builds its acceleration structure anew for each
        // executor may report the other triangle at a shared edge (NVIDIA's, on the H100),
        // which the reference's margin covers; on lavapipe the two G-buffers are identical.
        let (mirror_pos, mirror_normal, mirror_geo) =
            (read(gpu, &mirror_exec, "gbuffer.position")?, read(gpu, &mirror_exec, "gbuffer.normal")?, read(gpu, &mirror_exec, "gbuffer.geo_normal")?);
        let (primary, worst_normal) = self.primary(&pos, &geo);
        let (mirror_primary, mirror_worst_normal) = self.primary(&mirror_pos, &mirror_geo);
        // Shadow, AO and the mirror ray from the GPU's G-buffer.
        let (surfaces, mirror_surfaces) = (surface_points(&pos, &geo, &normal), surface_points(&mirror_pos, &mirror_geo, &mirror_normal));
        let (sun, point) = self.shadows(&surfaces, &shadow)?;
        let (ao_rays, ao_mean, ao_pixels) = self.ao(&surfaces, &ao);
        let mirrored = self.mirror(&mirror_surfaces, &mirror);
        let name = scene.name();
        let regathered = (0..pos.len()).filter(|&i| pos[i] != mirror_pos[i]).count();
        notes.push(format!("{name:8} {variant:20} the mirror graph's G-buffer: {regathered} of {} pixels differ from the first graph's", pos.len()));
        let in_shadow = (0..pos.len()).filter(|&i| pos[i][3] != 0.0 && shadow[i][0] == 0.0).count();
        let occluded: f64 = (0..pos.len()).filter(|&i| pos[i][3] != 0.0).map(|i| 1.0 - ao[i][0] as f64).sum::<f64>() * AO_RAYS as f64;
        let mirror_hits = mirror.iter().filter(|m| m[3] != 0.0 && m[0] >= 0.0).count();
        notes.push(format!("{name:8} {variant:20} {in_shadow} pixels in the sun's shadow, {occluded:.0} AO rays occluded, {mirror_hits} mirror rays hit"));
        ensure!(in_shadow > 50 && occluded > 500.0 && mirror_hits > 50, "{name}: the view holds shadows, occlusion and reflected geometry");
        let channels = [
            ("primary", &primary),
            ("primary (2)", &mirror_primary),
            ("sun shadow", &sun),
            ("point shadow", &point),
            ("AO rays", &ao_rays),
            ("mirror", &mirrored),
        ];
        for (channel, t) in channels {
            notes.push(format!(
                "{name:8} {variant:20} {channel:12}: {:6} compared, {:3} differ within the margin (largest {:.1e}), {} outside",
                t.compared, t.excused, t.largest_excused, t.wrong
            ));
            ensure!(t.compared > 0, "{name}, {variant}, {channel}: nothing compared");
            ensure_eq!(t.wrong, 0, "{name}, {variant}, {channel}: disagreements outside the margin");
        }
        notes.push(format!(
            "{name:8} {variant:20} AO: mean |V - V_ref| {ao_mean:.2e} over {ao_pixels} pixels; geometric normals within {worst_normal:.1e} (1 - cos)"
        ));
        ensure!(ao_pixels > 1000 && ao_mean <= 1e-3, "{name}, {variant}: AO mean difference {ao_mean}");
        let worst_normal = worst_normal.max(mirror_worst_normal);
        ensure!(worst_normal <= 2e-3, "{name}, {variant}: geometric normal 1 - cos {worst_normal}");
        Ok(())
    }
}

/// The surface points of a G-buffer's pixels (`None` where it shows no geometry).
fn surface_points(pos: &[[f32; 4]], geo: &[[f32; 4]], normal: &[[f32; 4]]) -> Vec<Option<SurfacePoint>> {
    (0..pos.len())
        .map(|i| (pos[i][3] != 0.0).then(|| SurfacePoint { position: xyz(pos[i]), geo_normal: xyz(geo[i]), normal: xyz(normal[i]), shadow_offset: geo[i][3] }))
        .collect()
}
