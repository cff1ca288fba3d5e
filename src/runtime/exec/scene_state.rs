//! The scene on the device and the frame uniforms: the upload of the parts a plan reads, the
//! changes followed from frame to frame (passes rebuilt when the upload is replaced), the
//! scene's bounding sphere and light records written every frame.

use super::features::SceneFeatures;
use super::Executor;
use crate::error::RuntimeError;
use crate::graph::compile::Plan;
use crate::graph::desc::PassKind;
use crate::runtime::gpu::Gpu;
use crate::runtime::light_records::light_records;
use crate::runtime::scene_upload::{GpuScene, SceneContent};
use crate::scene::{Camera, Scene};
use crate::uniforms::{FrameUniforms, CUBE_SHADOW_MAPS, SHADOW_MAP_SLOTS};

impl Executor {
    /// The parts of `scene` that `plan` reads, uploaded; `None` when it reads none.
    pub(super) fn upload_scene(gpu: &Gpu, plan: &Plan, scene: &Scene) -> Result<Option<GpuScene>, RuntimeError> {
        if !plan.scene_usage.any() {
            log::info!("scene not uploaded: no pass of the graph uses it");
            return Ok(None);
        }
        let s = GpuScene::upload(gpu.device(), gpu.queue(), scene, plan.scene_usage, None)?;
        log::info!("scene `{}` uploaded ({}): {} triangles, {} bytes", scene.name(), plan.scene_usage.describe(), scene.triangle_count(), s.bytes());
        Ok(Some(s))
    }

    /// A part of the uploaded scene; the plan's [`crate::scene::usage::SceneUsage`] decides what
    /// was uploaded, so a missing part is an internal inconsistency reported as an error.
    pub(super) fn scene_part<T>(&self, part: impl Fn(&GpuScene) -> Option<&T>) -> Result<&T, RuntimeError> {
        self.scene.as_ref().and_then(part).ok_or_else(|| RuntimeError::Gpu("a pass binds a part of the scene that the plan did not upload".into()))
    }

    /// Before a frame is recorded: the injected device loss (`RAYGRAPH_INJECT_DEVICE_LOSS`), the
    /// device's state, the scene's changes and its bounding sphere.
    pub(super) fn begin_frame(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) -> Result<(), RuntimeError> {
        if gpu.inject_device_loss_at() == Some(self.frame_index) {
            log::warn!("RAYGRAPH_INJECT_DEVICE_LOSS: destroying the device at frame {}", self.frame_index);
            gpu.device().destroy();
        }
        gpu.check()?;
        if self.seen.as_ref().is_some_and(|seen| seen.matches(scene)) {
            // The same scene (by pointer, `scene::memo`): only the camera's projection can
            // change the passes' constants.
            return self.use_features(gpu, self.features.with_camera(camera));
        }
        self.sync_scene(gpu, scene, camera)?;
        let b = scene.bounds_from(&self.bounds_memo.values(scene.meshes(), crate::scene::Mesh::bounds));
        self.scene_sphere = if b.is_empty() { (glam::Vec3::ZERO, 1.0) } else { (b.center(), (0.5 * b.diagonal()).max(1e-6)) };
        self.seen = Some(crate::scene::memo::SceneSnapshot::of(scene));
        self.scene_generation += 1;
        Ok(())
    }

    /// The passes built again when `features` (their pipeline constants) differ from the
    /// ones they were built with.
    fn use_features(&mut self, gpu: &Gpu, features: SceneFeatures) -> Result<(), RuntimeError> {
        if features != self.features {
            self.features = features;
            self.rebuild_passes(gpu)?;
            self.accel_generation = u64::MAX;
        }
        Ok(())
    }

    /// Keeps the uploaded scene equal to `scene`: moved instances are rewritten in place; any
    /// other change (meshes, materials, textures, instances added or removed) uploads the scene
    /// again and rebuilds the passes that bind it. Nothing to do for graphs that upload none.
    /// The passes are also built again when the scene's features or `camera`'s projection
    /// change (their pipeline constants, [`super::features`]).
    pub(super) fn sync_scene(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) -> Result<(), RuntimeError> {
        self.use_features(gpu, SceneFeatures::of(scene).with_camera(camera))?;
        let Some(uploaded) = &self.scene else { return Ok(()) };
        let content = SceneContent::of(scene, &mut self.content_memo);
        if content == self.scene_content {
            return Ok(());
        }
        // Moved instances and deformed meshes are rewritten in place.
        if content.structure == self.scene_content.structure {
            let instances_ok = content.transforms == self.scene_content.transforms || uploaded.write_instances(gpu.queue(), scene);
            // Deformed on the CPU: uploaded; left to the GPU: `record_deform` writes them.
            let cpu_deformed = scene.posed().is_none_or(|p| p.meshes_deformed) || self.deform.is_none();
            let vertices_ok = content.deformed == self.scene_content.deformed
                || uploaded.vertices().is_none()
                || !cpu_deformed
                || uploaded.write_vertices(gpu.queue(), scene, &scene.deforming_meshes());
            // The emitters' world-space corners follow both (written only where a pass binds them).
            let emitters_ok = (content.transforms == self.scene_content.transforms && content.deformed == self.scene_content.deformed)
                || uploaded.write_emitters(gpu.queue(), scene);
            if instances_ok && vertices_ok && emitters_ok {
                self.scene_content = content;
                return Ok(());
            }
        }
        let scope = gpu.scopes();
        self.scene = Some(GpuScene::upload(gpu.device(), gpu.queue(), scene, self.plan.scene_usage, self.scene.as_ref())?);
        // The new buffers hold the current transforms: `write_motion` writes the previous ones.
        self.history.motion_written = None;
        self.make_deform(gpu, scene);
        self.rebuild_passes(gpu)?;
        // The new passes have no accel bind group yet: make the next update re-create them.
        self.accel_generation = u64::MAX;
        scope.finish(gpu, "uploading the changed scene")?;
        log::info!("scene `{}` changed: uploaded again ({} bytes)", scene.name(), self.scene.as_ref().map_or(0, |s| s.bytes()));
        self.scene_content = content;
        Ok(())
    }

    /// The GPU deformation of `scene`'s deforming meshes into the uploaded scene (none without
    /// them); the acceleration-structure cache reads the positions it writes.
    pub(super) fn make_deform(&mut self, gpu: &Gpu, scene: &Scene) {
        self.deform = self.scene.as_ref().and_then(|uploaded| crate::runtime::deform::GpuDeform::new(gpu.device(), scene, uploaded));
        if let Some(cache) = self.accel.as_mut() {
            cache.set_device_positions(self.deform.as_ref().map(|d| d.positions().clone()));
            if scene.rig().is_some_and(|r| r.is_animated()) {
                cache.prepare_for_changes(gpu.device());
            }
        }
    }

    /// Records the GPU deformation of the frame's pose (nothing when the CPU posed the meshes
    /// or the pose has not changed).
    pub(super) fn record_deform(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, scene: &Scene) {
        if let Some(deform) = self.deform.as_mut() {
            deform.record(gpu.queue(), encoder, scene);
        }
    }

    /// `scene_motion`, where the plan binds it: each instance's transform of the previous frame
    /// (its current one on a frame without history, or where the instances changed in number),
    /// written only when it differs from what the buffer holds (by pointer first: nothing is
    /// read while the instances stay the same `Arc`).
    fn write_motion(&mut self, gpu: &Gpu, scene: &Scene) -> Result<(), RuntimeError> {
        use std::sync::Arc;
        let Some(uploaded) = self.scene.as_ref().filter(|s| s.motion().is_some()) else { return Ok(()) };
        let current = Arc::clone(scene.instances_arc());
        let previous = self.history.instances.replace(Arc::clone(&current));
        let motion = match previous {
            Some(previous) if self.history.valid && previous.len() == current.len() => previous,
            _ => current,
        };
        let transforms = |instances: &[crate::scene::Instance]| instances.iter().map(|i| i.transform).collect::<Vec<glam::Mat4>>();
        let written = self.history.motion_written.as_ref().is_some_and(|w| Arc::ptr_eq(w, &motion) || transforms(w) == transforms(&motion));
        if !written {
            if !uploaded.write_motion(gpu.queue(), &transforms(&motion)) {
                return Err(RuntimeError::Gpu("the previous-transform buffer does not match the scene's instances".into()));
            }
        }
        // Kept even when equal by value: the next frame compares pointers.
        self.history.motion_written = Some(motion);
        Ok(())
    }

    /// The scene's light records, made and written (where the plan reads them) when the scene
    /// changed since they were (its generation, `scene::memo`: the lights are part of what it
    /// compares); a static scene's frame reuses them.
    fn write_lights(&mut self, gpu: &Gpu, scene: &Scene) -> Result<(), RuntimeError> {
        if self.lights.as_ref().is_some_and(|(generation, _)| *generation == self.scene_generation) {
            return Ok(());
        }
        let (center, radius) = self.scene_sphere;
        let lights = light_records(&scene.effective_lights(), center, radius);
        if let Some(uploaded) = self.scene.as_ref().filter(|s| s.lights().is_some()) {
            if !uploaded.write_lights(gpu.queue(), &lights.records) {
                return Err(RuntimeError::Gpu("the light buffer does not match the scene's lights".into()));
            }
            if !self.warned_unshadowed && lights.unshadowed_in_raster > 0 && self.draws_shadow_maps() {
                self.warned_unshadowed = true;
                eprintln!(
                    "warning: lights without a shadow map in raster mode: {} of {} (directional or spot lights after the first {SHADOW_MAP_SLOTS}, point lights but the {CUBE_SHADOW_MAPS} most powerful); they light the scene unshadowed (a cube map is six draws of the scene a frame: BENCHMARKS.md, \"Raster point-light shadows\")",
                    lights.unshadowed_in_raster,
                    lights.records.len()
                );
            }
        }
        self.warn_of_glow();
        self.lights = Some((self.scene_generation, lights));
        Ok(())
    }

    /// Once: the scene's emissive surfaces light nothing in a graph that rasterizes it and has no
    /// pass sampling them (raster mode: they glow; their light is the ray-traced shadow pass's).
    fn warn_of_glow(&mut self) {
        let rasterized = self.plan.passes.iter().any(|p| p.kind == PassKind::SceneRaster);
        if !self.warned_glow && self.features.emitters && rasterized && !self.plan.scene_usage.emitters {
            self.warned_glow = true;
            eprintln!(
                "warning: emissive surfaces glow but light nothing in this graph (raster mode): the ray-traced modes' shadow pass samples them as lights"
            );
        }
    }

    /// The frame uniforms; writes the scene's light records when they changed.
    pub(super) fn frame_uniforms(&mut self, gpu: &Gpu, camera: &Camera, scene: &Scene) -> Result<FrameUniforms, RuntimeError> {
        let (w, h) = self.plan.frame_size;
        let vp = camera.view_proj(w as f32 / h as f32);
        let (center, radius) = self.scene_sphere;
        let previous_vp = self.history.previous.as_ref().map(|(_, m)| *m);
        self.history.begin_frame(camera, vp, radius);
        let prev_view_proj = if self.history.valid { previous_vp.unwrap_or(vp) } else { vp };
        self.write_motion(gpu, scene)?;
        self.write_lights(gpu, scene)?;
        let lights = self.lights.as_ref().map(|(_, lights)| lights).expect("written above");
        let shadow_view_proj = lights.shadow_view_proj.map(|m| m.to_cols_array_2d());
        Ok(FrameUniforms {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            // w: 1 for a perspective camera, 0 for an orthographic one (common/camera.wgsl).
            camera_pos: camera.position.extend(if camera.orthographic.is_some() { 0.0 } else { 1.0 }).into(),
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            scene_sphere: center.extend(radius).into(),
            shadow_view_proj,
            ambient: scene.light().ambient,
            light_count: lights.records.len() as u32,
            shadow_slots: lights.shadow_slots,
            frame_index: self.frame_index,
            history_valid: self.history.valid as u32,
            _pad: [0; 3],
            prev_view_proj: prev_view_proj.to_cols_array_2d(),
        })
    }
}
