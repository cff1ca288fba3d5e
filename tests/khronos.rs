//! The Khronos glTF sample models of `assets/khronos` (the working group's conformance set,
//! credits in `assets/khronos/CREDITS.md`), checked in numbers where a feature can be:
//! grey+alpha images (TextureEncodingTest's labels) against the `image` crate's own decode,
//! scene selection (MultipleScenes), the file's cameras with the built-in presets and the
//! orthographic camera's parallel projection in the rasterized and ray-traced G-buffers against
//! the f64 reference caster (Cameras), every clip at once (InterpolationTest), the BLEND panel's
//! alpha ramp composited over what lies behind it and the MASK panels cut at their cutoffs
//! (AlphaBlendModeTest), the sided rows of TextureSettingsTest.

mod common;

use common::{gpu, repo};
use raygraph::accel::reference_render::ReferenceRenderer;
use raygraph::backend::Backend;
use raygraph::graph::compile::{compile_with, CompileOptions, Project};
use raygraph::runtime::Executor;
use raygraph::scene::animation::ClipSet;
use raygraph::scene::{info, Camera, LoadOptions, Scene};

fn model(name: &str) -> String {
    repo().join(format!("assets/khronos/{name}/glTF/{name}.gltf")).to_str().unwrap().to_string()
}

fn open_with(name: &str, options: &LoadOptions) -> (Scene, raygraph::scene::ImportReport) {
    raygraph::scene::open(&model(name), options).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn grey_and_alpha_images_decode_as_grey_with_their_alpha() {
    let (scene, _) = open_with("TextureEncodingTest", &LoadOptions::default());
    for label in ["TestLabels.png", "SlotLabels.png"] {
        let texture = scene.textures().iter().find(|t| t.name == label).unwrap_or_else(|| panic!("no texture {label}"));
        let want = image::open(repo().join("assets/khronos/TextureEncodingTest/glTF").join(label)).unwrap();
        assert!(matches!(want.color(), image::ColorType::La8), "{label} is a grey+alpha PNG");
        let want = want.to_rgba8();
        assert_eq!((texture.width, texture.height), want.dimensions());
        assert_eq!(texture.rgba.as_slice(), want.as_raw().as_slice(), "{label}: every texel as the image crate converts it (grey to rgb, alpha kept)");
        let alphas: std::collections::BTreeSet<u8> = texture.rgba.chunks_exact(4).map(|p| p[3]).collect();
        assert!(alphas.contains(&0) && alphas.contains(&255), "{label}: a cut-out label has transparent and opaque texels");
    }
}

#[test]
fn the_default_scene_is_drawn_and_any_other_can_be_chosen_by_index_or_name() {
    // MultipleScenes: scene 0 holds the triangle (mesh 0), scene 1 (the file's `scene`) the
    // square (mesh 1).
    let (default, report) = open_with("MultipleScenes", &LoadOptions::default());
    assert_eq!(default.triangle_count(), 2, "the file's default scene, the square");
    let listed = info::describe(&default, Some(&report));
    assert!(listed.contains("gltf scenes 2") && listed.contains("1 `unnamed` 1 nodes (drawn, the file's default)"), "{listed}");
    assert!(!listed.contains("scene besides the default"), "{listed}");
    let first = LoadOptions { gltf_scene: Some("0".into()), ..Default::default() };
    assert_eq!(open_with("MultipleScenes", &first).0.triangle_count(), 1, "scene 0, the triangle");
    let missing = LoadOptions { gltf_scene: Some("lobby".into()), ..Default::default() };
    let err = raygraph::scene::open(&model("MultipleScenes"), &missing).unwrap_err().to_string();
    assert!(err.contains("MultipleScenes.gltf") && err.contains("no scene `lobby`") && err.contains("0 `unnamed`, 1 `unnamed`"), "{err}");
    let builtin = raygraph::scene::open("box", &first).unwrap_err().to_string();
    assert!(builtin.contains("built-in scene"), "{builtin}");
}

#[test]
fn every_file_camera_and_the_built_in_presets_are_listed() {
    let (scene, report) = open_with("Cameras", &LoadOptions::default());
    let names: Vec<&str> = scene.presets().iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["camera0", "camera1", "front", "top", "side"]);
    assert_eq!(*scene.camera(), scene.presets()[0].1, "the file's first camera is the default view");
    let ortho = scene.preset("camera1").unwrap();
    assert_eq!(ortho.orthographic, Some(1.0), "ymag");
    assert_eq!((ortho.near, ortho.far), (0.01, 100.0), "the file's znear and zfar");
    assert_eq!(scene.preset("camera0").unwrap().orthographic, None);
    let listed = info::describe(&scene, Some(&report));
    assert!(!listed.contains("orthographic camera `camera1` (skipped"), "{listed}");
}

/// Whether each pixel of `graph`'s G-buffer shows a surface, for `camera` at `size`.
fn coverage(scene: &Scene, graph: &str, camera: &Camera, size: (u32, u32)) -> Vec<bool> {
    let gpu = gpu();
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    let path = repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), size, &options).unwrap();
    let mut exec = Executor::new(&gpu, plan, scene).unwrap();
    exec.render(&gpu, camera, scene).unwrap();
    common::channel(&gpu, &exec, "gbuffer.position").iter().map(|p| p[3] != 0.0).collect()
}

/// The covered pixels of one row.
fn row_width(covered: &[bool], width: u32, row: u32) -> usize {
    covered[(row * width) as usize..((row + 1) * width) as usize].iter().filter(|c| **c).count()
}

#[test]
fn the_orthographic_camera_draws_parallel_rays_in_raster_and_ray_traced_g_buffers() {
    let (scene, _) = open_with("Cameras", &LoadOptions::default());
    let size = (48, 48);
    for name in ["camera1", "camera0"] {
        let camera = scene.preset(name).unwrap();
        let reference = ReferenceRenderer::new(&scene);
        let hits = reference.visibility(&ReferenceRenderer::camera_rays(&camera, size));
        let want: Vec<bool> = hits.iter().map(|h| h.value.is_some()).collect();
        // Pixels whose ray passes within 1e-4 (relative) of an edge may go either way in f32.
        let sure: Vec<bool> = hits.iter().map(|h| h.margin > 1e-4).collect();
        let rows: Vec<u32> = (0..size.1).filter(|&y| row_width(&want, size.0, y) > 0).collect();
        let (top, bottom) = (rows[1], rows[rows.len() - 2]);
        let (top_width, bottom_width) = (row_width(&want, size.0, top), row_width(&want, size.0, bottom));
        if camera.orthographic.is_some() {
            assert_eq!(top_width, bottom_width, "{name}: parallel rays see the tilted square's far edge as wide as its near edge");
        } else {
            assert!(top_width < bottom_width, "{name}: perspective makes the far edge narrower ({top_width} against {bottom_width})");
        }
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let got = coverage(&scene, graph, &camera, size);
            let wrong = (0..want.len()).filter(|&i| sure[i] && got[i] != want[i]).count();
            assert_eq!(wrong, 0, "{name} {graph}: pixels whose coverage differs from the f64 reference");
            assert!(got.iter().filter(|c| **c).count() > 100, "{name} {graph}: the square is in view");
        }
    }
}

#[test]
fn every_clip_at_once_poses_each_node_as_its_own_clip_does() {
    // InterpolationTest: nine clips, each driving one node (step, linear and cubic-spline
    // translation, rotation and scale).
    let (scene, _) = open_with("InterpolationTest", &LoadOptions::default());
    let rig = scene.rig().expect("a rig");
    assert_eq!(rig.animations.len(), 9);
    for t in [0.0, 0.4, 1.3, 2.7] {
        let all = rig.pose(ClipSet::All, t);
        for (c, clip) in rig.animations.iter().enumerate() {
            let alone = rig.pose(Some(c), t);
            for channel in &clip.channels {
                assert_eq!(all.world[channel.node], alone.world[channel.node], "clip `{}` at {t} s", clip.name);
            }
        }
    }
    // The longest clip sets the length.
    let longest = rig.animations.iter().map(|a| a.duration).fold(0.0, f32::max);
    assert_eq!(rig.duration(ClipSet::All), longest);
}

#[test]
fn the_default_view_frames_the_whole_animation_from_the_front() {
    let (scene, _) = open_with("InterpolationTest", &LoadOptions::default());
    let bounds = raygraph::scene::gltf_import::animated_bounds(&scene);
    let c = *scene.camera();
    let dir = (c.target - c.position).normalize();
    assert!((dir - glam::Vec3::NEG_Z).length() < 1e-6, "looks down -Z: {dir}");
    // Every corner of the animated bounds is inside the view frustum.
    let view_proj = c.view_proj(1.0);
    for i in 0..8 {
        let corner = glam::Vec3::new(
            if i & 1 == 0 { bounds.min.x } else { bounds.max.x },
            if i & 2 == 0 { bounds.min.y } else { bounds.max.y },
            if i & 4 == 0 { bounds.min.z } else { bounds.max.z },
        );
        let ndc = view_proj.project_point3(corner);
        assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z), "corner {corner} at {ndc}");
    }
    assert!(bounds.max.y - bounds.min.y >= scene.bounds().max.y - scene.bounds().min.y, "the animation's bounds hold the rest pose's");
}

#[test]
fn clip_planes_fitted_to_the_bounds_draw_the_scene_from_any_distance() {
    let (scene, _) = open_with("Cameras", &LoadOptions::default());
    let bounds = scene.bounds();
    for distance in [0.01, 120.0, 1.0e5] {
        let position = bounds.center() + glam::Vec3::Z * distance;
        let c = Camera::look(position, bounds.center(), 2.0, 0.05, 1000.0).fit_clip_planes(bounds);
        let d = position.distance(bounds.center());
        let r = 0.5 * bounds.diagonal();
        assert!(c.far >= d + r && c.near > 0.0 && c.near <= (d - r).max(c.far * 1e-4), "{distance}: near {} far {}", c.near, c.far);
    }
}

/// Resources of one frame of `graph` (compute back-end, no transient reuse).
fn channels(scene: &Scene, graph: &str, resources: &[&str], size: (u32, u32)) -> Vec<Vec<[f32; 4]>> {
    let gpu = gpu();
    let options = CompileOptions { reuse: false, ..gpu.compile_options_for(Backend::Compute) };
    let path = repo().join(graph);
    let plan = compile_with(&path, &Project::beside_graph(&path), size, &options).unwrap();
    let mut exec = Executor::new(&gpu, plan, scene).unwrap();
    exec.render(&gpu, scene.camera(), scene).unwrap();
    resources.iter().map(|r| common::channel(&gpu, &exec, r)).collect()
}

/// The HDR colour before tone mapping of `graph`'s frame and the resource that holds it.
fn hdr(scene: &Scene, graph: &str, resource: &str, size: (u32, u32)) -> Vec<[f32; 4]> {
    channels(scene, graph, &[resource], size).remove(0)
}

#[test]
fn texture_settings_tests_single_sided_quad_is_culled_and_still_casts_its_shadow() {
    // TextureSettingsTest's sided rows: a quad facing away from the camera 0.1 in front of one
    // facing it. The root node turns the file's planes y = -0.1 and y = 0 into world z = 0.1
    // and z = 0. Single-sided (doubleSided false): the nearer quad is culled and the check mark
    // behind it shows; double-sided: the nearer quad shows its own check mark. The culled quad
    // is still geometry: it shadows the check mark behind it from the scene's default sun,
    // which is why that cell reads darker than in the reference screenshot (drawn unshadowed).
    let (mut scene, _) = open_with("TextureSettingsTest", &LoadOptions::default());
    assert!(scene.lights().is_empty(), "lit by the default sun");
    // The Test column's cells (file x 0 to 0.9) of the single-sided row (file z 2.09 to 2.99)
    // and of the double-sided row (1.07 to 1.97).
    for (row, centre_y, nearer_drawn) in [("single-sided", 2.54, false), ("double-sided", 1.52, true)] {
        let centre = glam::Vec3::new(0.45, centre_y, 0.05);
        *scene.camera_mut() = Camera::look(centre + glam::Vec3::new(0.0, 0.0, 3.0), centre, 8.0, 0.05, 100.0);
        let size = (9, 9);
        let middle = (4 * size.0 + 4) as usize;
        for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
            let c = channels(&scene, graph, &["gbuffer.position", "shadow.shadow"], size);
            let (position, shadow) = (c[0][middle], c[1][middle]);
            let want_z = if nearer_drawn { 0.1 } else { 0.0 };
            println!("TextureSettingsTest {row}, {graph}: z {:.4}, sun visibility {:.3}", position[2], shadow[0]);
            assert!(position[3] >= 1.0 && (position[2] - want_z).abs() < 1e-3, "{row}, {graph}: the drawn quad lies at z {want_z}: {position:?}");
            let want_visibility = if nearer_drawn { 1.0 } else { 0.0 };
            assert_eq!(shadow[0], want_visibility, "{row}, {graph}: the sun's visibility");
        }
    }
}

#[test]
fn unlit_materials_show_their_base_colour_in_every_mode() {
    let (scene, report) = open_with("UnlitTest", &LoadOptions::default());
    assert!(scene.materials().iter().all(|m| m.unlit));
    let listed = info::describe(&scene, Some(&report));
    assert!(!listed.contains("KHR_materials_unlit"), "nothing about unlit is approximated or ignored: {listed}");
    let colours = [glam::Vec3::new(1.0, 0.217_637_64, 0.0), glam::Vec3::new(0.0, 0.217_637_64, 1.0)];
    // Bounds: the output's rgba16float holds 0.2176 to within 1.2e-4 (raster shades straight
    // into it); the hybrid and full-RT G-buffer keeps the base colour in 8-bit linear albedo,
    // half a step 1/510 = 0.00196 (measured 0.00206 with the f16 output's rounding).
    let g_buffer_bound = 1.0 / 510.0 + 2e-4;
    for (graph, resource, bound) in
        [("graph/raster.ron", "forward.color", 2e-4), ("graph/hybrid.ron", "resolve.hdr", g_buffer_bound), ("graph/full_rt.ron", "resolve.hdr", g_buffer_bound)]
    {
        let pixels = hdr(&scene, graph, resource, (64, 48));
        let covered: Vec<glam::Vec3> = pixels.iter().filter(|p| p[3] > 0.0).map(|p| glam::Vec3::new(p[0], p[1], p[2])).collect();
        assert!(covered.len() > 400, "{graph}: both objects in view ({} pixels)", covered.len());
        let mut errors: Vec<f32> = covered.iter().map(|c| colours.iter().map(|b| (*c - *b).abs().max_element()).fold(f32::INFINITY, f32::min)).collect();
        errors.sort_by(f32::total_cmp);
        let (median, worst) = (errors[errors.len() / 2], errors[errors.len() - 1]);
        println!("{graph}: unlit colour error over {} pixels: median {median:.5}, max {worst:.5}", errors.len());
        assert!(worst < bound, "{graph}: max error {worst} (median {median})");
    }
}

#[test]
fn scene_info_ignores_nothing_on_any_khronos_model() {
    for name in common::khronos_models() {
        let (scene, report) = open_with(&name, &LoadOptions::default());
        assert!(report.ignored_features.is_empty(), "{name}: {:?}", report.ignored_features);
        assert!(info::describe(&scene, Some(&report)).contains("ignored     nothing"), "{name}");
        // What is drawn differently is said: BLEND (instances sorted in raster). The cameras' aspect
        // ratios are honoured (tests/cli.rs).
        for line in &report.approximated {
            assert!(line.contains("alphaMode BLEND"), "{name}: {line}");
        }
    }
}

#[test]
fn alpha_blend_mode_tests_blend_panel_composites_its_alpha_ramp_over_what_lies_behind() {
    // Every material unlit (each shows its base colour times its texture), so a pixel through
    // the BLEND panel is coverage x the panel's colour + (1 - coverage) x what lies behind:
    // the colour from a render with the panel made OPAQUE, what lies behind from one without
    // the panel, the coverage from the f64 CPU read of the panel's texture alpha at the hit
    // (accel::alpha, the CPU traversal through the model). Full RT: one primary ray per pixel,
    // the same ray cone for the panel's colour in both renders.
    let (mut scene, _) = open_with("AlphaBlendModeTest", &LoadOptions::default());
    for m in scene.materials_mut().iter_mut() {
        m.unlit = true;
    }
    let blend = scene.materials().iter().position(|m| m.name == "MatBlend").expect("the BLEND material");
    let panel = scene
        .instances()
        .iter()
        .position(|i| i.material == blend && scene.meshes()[i.mesh].indices.len() == 6 && scene.meshes()[i.mesh].name.contains("TestBlend"))
        .expect("the BLEND panel");
    // The panel fills the frame's middle: look at it straight on from 3.5 in front.
    let centre = scene.instances()[panel].transform.transform_point3(glam::Vec3::new(0.0, 1.035, 0.0));
    *scene.camera_mut() = Camera::look(centre + glam::Vec3::new(0.0, 0.0, 3.5), centre, 40.0, 0.05, 100.0);
    let size = (48, 64);
    let composite = hdr(&scene, "graph/full_rt.ron", "blend.color", size);
    let mut opaque = scene.clone();
    opaque.materials_mut()[blend].alpha_mode = raygraph::scene::AlphaMode::Opaque;
    let colour = hdr(&opaque, "graph/full_rt.ron", "resolve.hdr", size);
    let mut without = scene.clone();
    without.instances_mut().remove(panel);
    let behind = hdr(&without, "graph/full_rt.ron", "blend.color", size);
    // Which pixels see the panel first, and its coverage there.
    let accel = raygraph::accel::layout::GpuAccel::build(&scene, &Default::default());
    let cpu = raygraph::accel::cpu_traverse::CpuTraverser::with_scene(&accel, &scene);
    let (mut checked, mut worst, mut covers) = (0, 0.0f32, (1.0f64, 0.0f64));
    for (i, (origin, dir)) in scene.camera().rays(size, 1).into_iter().enumerate() {
        let Some(hit) = cpu.closest(&raygraph::accel::cpu_traverse::Ray::new(origin, dir)) else { continue };
        if hit.instance_id as usize != panel {
            continue;
        }
        let Some(a) = raygraph::accel::alpha::blend_coverage(&scene, panel, hit.prim as usize, [hit.u as f64, hit.v as f64]) else { continue };
        // Away from the ramp's texel-sharp edges (its black border, the labels' cut-outs), where
        // a bilinear read moves fast and the GPU's f32 barycentrics may land on another texel.
        let near = |d: f64| raygraph::accel::alpha::blend_coverage(&scene, panel, hit.prim as usize, [hit.u as f64 + d, hit.v as f64]);
        if [near(0.004), near(-0.004)].iter().any(|n| n.is_none_or(|n| (n - a).abs() > 0.02)) {
            continue;
        }
        covers = (covers.0.min(a), covers.1.max(a));
        for k in 0..3 {
            let want = a as f32 * colour[i][k] + (1.0 - a as f32) * behind[i][k];
            worst = worst.max((composite[i][k] - want).abs());
        }
        checked += 1;
    }
    println!("AlphaBlendModeTest: {checked} pixels through the BLEND panel, coverage {:.3} to {:.3}, largest error {worst:.5}", covers.0, covers.1);
    assert!(checked > 500, "the panel is in view ({checked} pixels)");
    assert!(covers.1 - covers.0 > 0.5, "the ramp spans its coverage ({covers:?})");
    // The panel's colour comes through the G-buffer's 8-bit albedo (half a step: 1/510) in the
    // OPAQUE render only; the three images are f16 (2^-11 relative); the coverage is f32 on the
    // GPU against f64 here (1e-3 with the texel-edge margin above).
    assert!(worst < 1.0 / 510.0 + 2e-3, "largest error {worst}");
}

#[test]
fn alpha_blend_mode_tests_mask_panels_are_cut_at_their_cutoffs_as_the_cpu_alpha_test_cuts_them() {
    // Every pixel's first surface in the hybrid (raster G-buffer) and full-RT (primary rays)
    // G-buffers against the f64-textured CPU traversal with the same alpha test, on the model's
    // own view: where the CPU's first hit is opaque or MASK, the instance drawn must be the one
    // it hits (MASK texels below their material's alphaCutoff let the ray through to what lies
    // behind). BLEND surfaces are left out (the G-buffers pass them; tests above composite them).
    let (scene, _) = open_with("AlphaBlendModeTest", &LoadOptions::default());
    let size = (128, 96);
    let first_hits = |scene: &Scene| -> Vec<Option<usize>> {
        let accel = raygraph::accel::layout::GpuAccel::build(scene, &Default::default());
        let cpu = raygraph::accel::cpu_traverse::CpuTraverser::with_scene(&accel, scene);
        let ray = |(origin, dir)| cpu.closest(&raygraph::accel::cpu_traverse::Ray::new(origin, dir)).map(|h| h.instance_id as usize);
        scene.camera().rays(size, 1).into_iter().map(ray).collect()
    };
    let first = first_hits(&scene);
    let mode = |i: usize| scene.materials()[scene.instances()[i].material].alpha_mode;
    // The pixels a MASK panel covers but cuts: its first hit with the panels made opaque.
    let mut opaque = scene.clone();
    for m in opaque.materials_mut().iter_mut().filter(|m| matches!(m.alpha_mode, raygraph::scene::AlphaMode::Mask(_))) {
        m.alpha_mode = raygraph::scene::AlphaMode::Opaque;
    }
    let cut: Vec<bool> =
        first_hits(&opaque).iter().zip(&first).map(|(o, f)| o.is_some_and(|i| matches!(mode(i), raygraph::scene::AlphaMode::Mask(_))) && o != f).collect();
    assert!(cut.iter().filter(|&&c| c).count() > 100, "the view crosses cut texels");
    for graph in ["graph/hybrid.ron", "graph/full_rt.ron"] {
        let position = channels(&scene, graph, &["gbuffer.position"], size).remove(0);
        let (mut compared, mut masked, mut differ, mut through) = (0, 0, 0, 0);
        for ((p, want), cut) in position.iter().zip(&first).zip(&cut) {
            if want.is_some_and(|i| mode(i) == raygraph::scene::AlphaMode::Blend) {
                continue;
            }
            let drawn = (p[3] >= 1.0).then(|| p[3] as usize - 1);
            compared += 1;
            masked += usize::from(want.is_some_and(|i| matches!(mode(i), raygraph::scene::AlphaMode::Mask(_))));
            differ += usize::from(drawn != *want);
            through += usize::from(*cut && drawn == *want);
        }
        println!("AlphaBlendModeTest MASK, {graph}: {compared} pixels compared ({masked} on MASK panels, {through} through their cut texels), {differ} differ");
        assert!(masked > 200, "{graph}: the MASK panels are in view ({masked} pixels)");
        assert!(through > 100, "{graph}: {through} pixels see through cut texels");
        // A pixel on a texel edge of the cut or on a silhouette may land either side (the GPU's
        // f32 barycentrics against f64 here): 1% allowed, none measured on lavapipe.
        assert!(differ * 100 <= compared, "{graph}: {differ} of {compared} pixels show another surface");
    }
}
