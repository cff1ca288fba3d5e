//! Render pipelines of `Fullscreen` and `SceneRaster` passes, and the draw classes of a scene
//! pass: each instance is drawn with a pipeline variant chosen from its material and transform.
//!
//! - Culling: with the layer's `cull_back_faces` (the default), the rasterizer culls the back
//!   faces of single-sided materials: `Back` for an instance whose transform keeps handedness,
//!   `Front` for one that mirrors it (its triangles' winding turns on screen; `front_facing` in
//!   the shader stays that of the pipeline, as `raster_front_face` expects). Double-sided
//!   materials (glTF `doubleSided`) are drawn on both sides.
//! - Closed meshes in shadow maps: a pass with `cull_closed_back_faces` (a shadow-map slot)
//!   also culls the back faces of an opaque instance whose mesh is closed and wound outwards
//!   (`scene::topology`), whatever its material's sidedness, when all of its bounds lie beyond
//!   the near plane of the slot's light: the light is then outside the mesh, the nearest
//!   surface it sees is a front face, and the depth written is the same as with both sides
//!   drawn.
//! - Alpha test: a shader that declares the pipeline constant [`ALPHA_TEST_CONSTANT`]
//!   (`shaders/common/raster_alpha_test.wgsl`) gets it false for the instances of opaque materials, so
//!   their fragment stage has no discard and keeps early depth testing; only alpha-tested
//!   materials pay for the test.
//!
//! Variants are created the first time a class is drawn. Within a class, draws go front to back
//! (by the distance from the camera to the centre of each instance's bounds), so that early
//! depth testing spares the fragments behind.

use crate::runtime::scene_upload::Draw;
use crate::scene::Scene;

/// The pipeline constant a shadow pass's shader reads its slot from (`PassDesc::shadow_slot`,
/// shadow_map/shadow_map.wgsl), so that one entry point serves every slot; a pass of shadow
/// tiles has a pipeline per tile, each with its own slot.
pub(crate) const SHADOW_SLOT_CONSTANT: &str = "SHADOW_SLOT";

/// The pipeline constant that switches the raster alpha test (WGSL `override`).
pub(crate) const ALPHA_TEST_CONSTANT: &str = "RASTER_ALPHA_TEST";

/// What the rasterizer culls for a draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Cull {
    None,
    Back,
    Front,
}

impl Cull {
    fn face(self) -> Option<wgpu::Face> {
        match self {
            Cull::None => None,
            Cull::Back => Some(wgpu::Face::Back),
            Cull::Front => Some(wgpu::Face::Front),
        }
    }
}

/// The pipeline variant an instance is drawn with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct DrawClass {
    pub(crate) cull: Cull,
    pub(crate) alpha_test: bool,
}

impl DrawClass {
    /// A fullscreen pass's one pipeline: nothing culled, the shader as written.
    pub(crate) const FULLSCREEN: DrawClass = DrawClass { cull: Cull::None, alpha_test: true };
}

/// What decides an instance's draw class, whatever the pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct InstanceClass {
    pub(crate) double_sided: bool,
    pub(crate) mirrored: bool,
    pub(crate) alpha_tested: bool,
    /// Its material is translucent (BLEND or transmissive: not drawn by passes with
    /// `skip_blend`).
    pub(crate) blend: bool,
    /// An opaque instance of a closed, outward-wound mesh (`Draw::closed`).
    pub(crate) closed: bool,
    /// The world-space corners of its mesh's bounds (`Draw::local_bounds`; `None`: never culled
    /// by a light's frustum, nor as a closed mesh).
    pub(crate) corners: Option<[glam::Vec3; 8]>,
}

impl InstanceClass {
    /// One per scene instance, in order; `draws` (one per instance, from the upload) tell
    /// which meshes are closed.
    pub(crate) fn of_scene(scene: &Scene, draws: &[Draw]) -> Vec<InstanceClass> {
        (0..scene.instances().len())
            .map(|i| {
                let inst = &scene.instances()[i];
                let material = scene.materials().get(inst.material);
                let double_sided = material.is_some_and(|m| m.double_sided);
                let alpha_tested = crate::accel::alpha::instance_tested(scene, i);
                let draw = draws.get(i).filter(|d| d.instance as usize == i);
                InstanceClass {
                    double_sided,
                    mirrored: glam::Mat3::from_mat4(inst.transform).determinant() < 0.0,
                    alpha_tested,
                    blend: material.is_some_and(|m| m.translucent()),
                    closed: !alpha_tested && draw.is_some_and(|d| d.closed),
                    corners: draw.and_then(|d| d.local_bounds).map(|b| corners(&b).map(|c| inst.transform.transform_point3(c))),
                }
            })
            .collect()
    }

    /// Whether the instance is closed, opaque and wholly beyond the near plane of the light
    /// whose view-projection is `light_view_proj` (wgpu's clip depth: beyond the near plane
    /// is z > 0), so that the light is outside it.
    pub(crate) fn closed_and_beyond_near_plane(&self, light_view_proj: &glam::Mat4) -> bool {
        let corners = self.corners.filter(|_| self.closed);
        corners.is_some_and(|corners| corners.iter().all(|c| (*light_view_proj * c.extend(1.0)).z > 0.0))
    }

    /// Whether the instance lies wholly outside the frustum of `light_view_proj` (every corner
    /// of its bounds beyond one of the clip volume's six planes; the planes are linear in
    /// homogeneous clip coordinates, so the box, the corners' hull, is then outside too): the
    /// rasterizer would clip every triangle of it.
    pub(crate) fn outside_frustum(&self, light_view_proj: &glam::Mat4) -> bool {
        let Some(corners) = self.corners else { return false };
        let clip = corners.map(|c| *light_view_proj * c.extend(1.0));
        let planes: [fn(glam::Vec4) -> f32; 6] = [|c| c.x + c.w, |c| c.w - c.x, |c| c.y + c.w, |c| c.w - c.y, |c| c.z, |c| c.w - c.z];
        planes.iter().any(|inside| clip.iter().all(|c| inside(*c) < 0.0))
    }

    /// The class of this instance in a pass that culls back faces (`cull_back_faces`) or not,
    /// whose shader can switch the alpha test off (`alpha_switch`) or not; `cull_closed`: a
    /// closed mesh seen from outside, culled whatever its material's sidedness.
    pub(crate) fn draw_class(self, cull_back_faces: bool, alpha_switch: bool, cull_closed: bool) -> DrawClass {
        let cull = match (cull_back_faces && !self.double_sided || cull_closed, self.mirrored) {
            (false, _) => Cull::None,
            (true, false) => Cull::Back,
            (true, true) => Cull::Front,
        };
        DrawClass { cull, alpha_test: self.alpha_tested || !alpha_switch }
    }
}

/// The eight corners of `b`.
fn corners(b: &crate::scene::Bounds) -> [glam::Vec3; 8] {
    std::array::from_fn(|i| {
        glam::Vec3::new(if i & 1 == 0 { b.min.x } else { b.max.x }, if i & 2 == 0 { b.min.y } else { b.max.y }, if i & 4 == 0 { b.min.z } else { b.max.z })
    })
}

/// The order in which `draws` are recorded: nearest first (to `eye`, by the world-space centre
/// of each instance's mesh bounds); draws of instances `scene` does not have go last.
pub(crate) fn front_to_back(draws: &[Draw], scene: &Scene, eye: glam::Vec3) -> Vec<usize> {
    let distance = |d: &Draw| {
        scene.instances().get(d.instance as usize).map_or(f32::INFINITY, |inst| inst.transform.transform_point3(d.local_center).distance_squared(eye))
    };
    let keys: Vec<f32> = draws.iter().map(distance).collect();
    let mut order: Vec<usize> = (0..draws.len()).collect();
    order.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
    order
}

/// Which of the scene's instances a `SceneRaster` pass draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum DrawnInstances {
    /// Every instance (translucent ones screen-door: the shadow maps).
    All,
    /// The opaque and alpha-tested instances (`skip_blend`).
    Opaque,
    /// The translucent instances, back to front and blended (`translucent`).
    Translucent,
}

impl DrawnInstances {
    /// What `pass` draws.
    pub(crate) fn of_pass(pass: &crate::graph::compile::PlannedPass) -> Self {
        match (pass.translucent, pass.skip_blend) {
            (true, _) => Self::Translucent,
            (false, true) => Self::Opaque,
            (false, false) => Self::All,
        }
    }

    /// Whether an instance of class `c` is drawn.
    pub fn draws(self, c: &InstanceClass) -> bool {
        match self {
            Self::All => true,
            Self::Opaque => !c.blend,
            Self::Translucent => c.blend,
        }
    }
}

/// Everything a render pipeline of a pass is made from, but the variant.
pub(crate) struct RenderSpec {
    pub(crate) label: String,
    pub(crate) layout: wgpu::PipelineLayout,
    pub(crate) module: wgpu::ShaderModule,
    pub(crate) vertex_entry: String,
    pub(crate) fragment_entry: String,
    pub(crate) targets: Vec<Option<wgpu::ColorTargetState>>,
    /// Vertex attributes the vertex stage reads from the scene's vertex buffer; `None` for a
    /// fullscreen pass (no vertex buffer).
    pub(crate) scene_attributes: Option<Vec<wgpu::VertexAttribute>>,
    pub(crate) depth: bool,
    /// The shader declares [`ALPHA_TEST_CONSTANT`].
    pub(crate) alpha_switch: bool,
    /// The scene's feature constants the shader declares, with their values
    /// (`crate::runtime::exec::features`).
    pub(crate) scene_constants: Vec<(&'static str, f64)>,
    /// The fragment stage does nothing but the alpha test: a built-in shader (its files
    /// raygraph's own, byte for byte) with the alpha switch and no colour targets, such as the
    /// shadow maps'. Its opaque draw classes get a depth-only pipeline, no fragment stage at all.
    pub(crate) fragment_only_alpha_tests: bool,
}

impl RenderSpec {
    /// The pipeline of one variant, for tile `tile` of a pass of shadow tiles (its slot the
    /// pass's plus `tile`; 0 otherwise).
    pub fn create(&self, device: &wgpu::Device, class: DrawClass, tile: u32) -> wgpu::RenderPipeline {
        let mut constants = self.scene_constants.clone();
        for (name, value) in constants.iter_mut() {
            if *name == SHADOW_SLOT_CONSTANT {
                *value += f64::from(tile);
            }
        }
        if self.alpha_switch {
            constants.push((ALPHA_TEST_CONSTANT, if class.alpha_test { 1.0 } else { 0.0 }));
        }
        let compilation_options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let vertex_buffers: Vec<Option<wgpu::VertexBufferLayout>> = self
            .scene_attributes
            .iter()
            .map(|attributes| {
                Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes,
                })
            })
            .collect();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&self.label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(&self.vertex_entry),
                compilation_options: compilation_options.clone(),
                buffers: &vertex_buffers,
            },
            primitive: wgpu::PrimitiveState { cull_mode: class.cull.face(), ..Default::default() },
            depth_stencil: self.depth.then_some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: (!self.fragment_only_alpha_tests || class.alpha_test).then(|| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(&self.fragment_entry),
                compilation_options,
                targets: &self.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// The pipeline variants of a `SceneRaster` pass, made as draw classes appear.
pub(crate) struct ScenePipelines {
    spec: RenderSpec,
    cull_back_faces: bool,
    cull_closed_back_faces: bool,
    drawn: DrawnInstances,
    /// By (tile, class): a pass of shadow tiles has a pipeline per tile, each reading its slot.
    variants: Vec<((u32, DrawClass), wgpu::RenderPipeline)>,
}

impl ScenePipelines {
    /// The pipelines of a pass with its layer's `cull_back_faces` and
    /// `cull_closed_back_faces`, drawing the instances `drawn` names.
    pub(crate) fn new(spec: RenderSpec, cull_back_faces: bool, cull_closed_back_faces: bool, drawn: DrawnInstances) -> Self {
        Self { spec, cull_back_faces, cull_closed_back_faces, drawn, variants: Vec::new() }
    }

    /// The class of each instance in this pass (`None`: not drawn: a translucent instance in a
    /// pass with `skip_blend`, an opaque one in a translucent pass); `light_view_proj` is the
    /// view-projection of the pass's shadow-map slot, where it has one in use.
    pub fn classes(&self, instances: &[InstanceClass], light_view_proj: Option<&glam::Mat4>) -> Vec<Option<DrawClass>> {
        let closed_culling = light_view_proj.filter(|_| self.cull_closed_back_faces);
        instances
            .iter()
            .map(|c| {
                let outside = light_view_proj.is_some_and(|vp| c.outside_frustum(vp));
                (self.drawn.draws(c) && !outside)
                    .then(|| c.draw_class(self.cull_back_faces, self.spec.alpha_switch, closed_culling.is_some_and(|vp| c.closed_and_beyond_near_plane(vp))))
            })
            .collect()
    }

    /// Creates the variants of `classes` for tile `tile` that do not exist yet.
    pub(crate) fn prepare(&mut self, device: &wgpu::Device, tile: u32, classes: &[Option<DrawClass>]) {
        for &class in classes.iter().flatten() {
            if !self.variants.iter().any(|(key, _)| *key == (tile, class)) {
                let pipeline = self.spec.create(device, class, tile);
                self.variants.push(((tile, class), pipeline));
            }
        }
    }

    /// The variant of `class` for tile `tile`, once made.
    pub fn variant(&self, tile: u32, class: DrawClass) -> Option<&wgpu::RenderPipeline> {
        self.variants.iter().find(|(key, _)| *key == (tile, class)).map(|(_, p)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn class(double_sided: bool, mirrored: bool, alpha_tested: bool) -> InstanceClass {
        InstanceClass { double_sided, mirrored, alpha_tested, blend: false, closed: false, corners: None }
    }

    #[test]
    fn each_pass_draws_its_share_of_the_instances() {
        let opaque = class(false, false, false);
        let translucent = InstanceClass { blend: true, ..class(true, false, true) };
        assert!(DrawnInstances::All.draws(&opaque) && DrawnInstances::All.draws(&translucent));
        assert!(DrawnInstances::Opaque.draws(&opaque) && !DrawnInstances::Opaque.draws(&translucent));
        assert!(!DrawnInstances::Translucent.draws(&opaque) && DrawnInstances::Translucent.draws(&translucent));
    }

    #[test]
    fn draws_go_nearest_first() {
        let mut scene = crate::scene::builtin::default_scene();
        let mesh = scene.instances()[0].mesh;
        *scene.instances_mut() = [5.0f32, -1.0, 2.0]
            .iter()
            .map(|&z| crate::scene::Instance { mesh, material: 0, transform: glam::Mat4::from_translation(glam::Vec3::new(0.0, 0.0, z)) })
            .collect();
        let draws: Vec<Draw> =
            (0..4).map(|i| Draw { indices: 0..3, base_vertex: 0, instance: i, local_center: glam::Vec3::ZERO, local_bounds: None, closed: false }).collect();
        // Instance 3 does not exist: last.
        assert_eq!(front_to_back(&draws, &scene, glam::Vec3::new(0.0, 0.0, 10.0)), vec![0, 2, 1, 3]);
        assert_eq!(front_to_back(&draws, &scene, glam::Vec3::new(0.0, 0.0, -10.0)), vec![1, 2, 0, 3]);
    }

    #[test]
    fn single_sided_instances_are_culled_by_handedness() {
        assert_eq!(class(false, false, false).draw_class(true, true, false), DrawClass { cull: Cull::Back, alpha_test: false });
        assert_eq!(class(false, true, false).draw_class(true, true, false), DrawClass { cull: Cull::Front, alpha_test: false });
        assert_eq!(class(true, true, false).draw_class(true, true, false).cull, Cull::None);
        assert_eq!(class(false, false, false).draw_class(false, true, false).cull, Cull::None);
    }

    #[test]
    fn only_alpha_tested_materials_keep_the_test_where_the_shader_can_switch_it() {
        assert!(class(false, false, true).draw_class(true, true, false).alpha_test);
        assert!(!class(false, false, false).draw_class(true, true, false).alpha_test);
        // A shader without the constant always runs what it has.
        assert!(class(false, false, false).draw_class(true, false, false).alpha_test);
    }

    /// The view-projection of shadow-map slot 0 for `light` in the scene sphere at the origin
    /// of radius 4.
    fn slot_view_proj(light: crate::scene::PunctualLight) -> glam::Mat4 {
        crate::runtime::light_records::light_records(&[light], glam::Vec3::ZERO, 4.0).shadow_view_proj[0]
    }

    fn light(kind: crate::scene::LightKind, position: glam::Vec3, direction: glam::Vec3) -> crate::scene::PunctualLight {
        crate::scene::PunctualLight { name: "l".into(), kind, position, direction, color: glam::Vec3::ONE, intensity: 1.0 }
    }

    /// A unit sphere (closed) at `center` with its draw.
    fn closed_instance(center: glam::Vec3, alpha_tested: bool, double_sided: bool) -> InstanceClass {
        let b = crate::scene::Bounds { min: glam::Vec3::splat(-1.0), max: glam::Vec3::ONE };
        let corners = corners(&b).map(|c| c + center);
        InstanceClass { double_sided, mirrored: false, alpha_tested, blend: false, closed: !alpha_tested, corners: Some(corners) }
    }

    /// A unit box at `center` through a point light's cube face +x at the origin: inside, beside
    /// and behind the face, beyond its far plane, and straddling its edge.
    #[test]
    fn instances_wholly_outside_a_shadow_slots_frustum_are_culled_and_no_others() {
        let (faces, _) = crate::runtime::light_records::cube_projections(glam::Vec3::ZERO, None, glam::Vec3::ZERO, 10.0);
        let plus_x = faces[0];
        let at = |x: f32, y: f32, z: f32| closed_instance(glam::Vec3::new(x, y, z), false, false);
        assert!(!at(5.0, 0.0, 0.0).outside_frustum(&plus_x), "in front of the face");
        assert!(!at(5.0, 5.5, 0.0).outside_frustum(&plus_x), "across the face's edge (45 degrees)");
        assert!(at(5.0, 8.0, 0.0).outside_frustum(&plus_x), "beyond the edge");
        assert!(at(-5.0, 0.0, 0.0).outside_frustum(&plus_x), "behind the light");
        assert!(at(0.0, 0.0, 5.0).outside_frustum(&plus_x), "beside the light, in the +z face");
        assert!(at(30.0, 0.0, 0.0).outside_frustum(&plus_x), "beyond the far plane (10)");
        assert!(!at(0.2, 0.0, 0.0).outside_frustum(&plus_x), "around the light: every face draws it");
        let no_bounds = InstanceClass { corners: None, ..at(-5.0, 0.0, 0.0) };
        assert!(!no_bounds.outside_frustum(&plus_x), "a deforming mesh is never culled");
    }

    #[test]
    fn closed_meshes_are_culled_only_from_lights_outside_them() {
        let spot_towards = |position: glam::Vec3, direction: glam::Vec3| {
            let kind = crate::scene::LightKind::Spot { range: None, inner_cone: 0.3, outer_cone: 0.6 };
            slot_view_proj(light(kind, position, direction))
        };
        let spot = |position: glam::Vec3| spot_towards(position, -position.normalize());
        let sun = slot_view_proj(light(crate::scene::LightKind::Directional, glam::Vec3::ZERO, glam::Vec3::new(0.3, -1.0, 0.2)));
        let at_origin = closed_instance(glam::Vec3::ZERO, false, false);
        let aside = closed_instance(glam::Vec3::new(2.5, 0.0, 0.0), false, false);
        // A directional light's near plane lies outside the scene's sphere.
        assert!(at_origin.closed_and_beyond_near_plane(&sun) && aside.closed_and_beyond_near_plane(&sun));
        // A spot light outside the sphere's bounds, and one inside them.
        assert!(at_origin.closed_and_beyond_near_plane(&spot(glam::Vec3::new(0.0, 3.0, 0.0))));
        assert!(!at_origin.closed_and_beyond_near_plane(&spot(glam::Vec3::new(0.0, 0.5, 0.0))));
        // Inside the corner of the bounds though outside the sphere: still not culled.
        assert!(!at_origin.closed_and_beyond_near_plane(&spot(glam::Vec3::new(0.9, 0.9, 0.9))));
        // Outside the bounds, but beside them, so that they straddle the light's near plane.
        assert!(!aside.closed_and_beyond_near_plane(&spot_towards(glam::Vec3::new(2.5, 1.5, 0.0), glam::Vec3::X)));
        assert!(aside.closed_and_beyond_near_plane(&spot_towards(glam::Vec3::new(5.0, 0.0, 0.0), -glam::Vec3::X)));
        // Alpha-tested or open meshes never.
        assert!(!closed_instance(glam::Vec3::ZERO, true, false).closed_and_beyond_near_plane(&sun));
        assert!(!class(false, false, false).closed_and_beyond_near_plane(&sun));
    }

    #[test]
    fn a_closed_mesh_seen_from_outside_is_culled_whatever_its_sidedness() {
        let double_sided = closed_instance(glam::Vec3::ZERO, false, true);
        assert_eq!(double_sided.draw_class(false, true, true).cull, Cull::Back);
        assert_eq!(double_sided.draw_class(false, true, false).cull, Cull::None);
        let mirrored = InstanceClass { mirrored: true, ..double_sided };
        assert_eq!(mirrored.draw_class(false, true, true).cull, Cull::Front);
    }
}
