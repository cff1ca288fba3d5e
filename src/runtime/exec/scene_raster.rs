//! `SceneRaster` passes: the scene's meshes drawn with one pipeline variant per draw class
//! (`crate::runtime::raster`), front to back, or back to front in a translucent pass, from the
//! draws kept in `super::draws`; a
//! shadow-map pass of a slot no light uses this frame, or a translucent pass of a frame without
//! translucent instances, recorded as an empty pass that keeps its timestamps.

use super::bindings::{PassBindings, PassLayout};
use super::{Executor, PassRuntime, Pipeline};
use crate::error::RuntimeError;
use crate::graph::compile::PlannedPass;
use crate::graph::desc::PassKind;
use crate::runtime::gpu::Gpu;
use crate::runtime::raster::{DrawnInstances, ScenePipelines};

impl Executor {
    pub(super) fn build_scene_raster_pass(&self, gpu: &Gpu, pass: &PlannedPass, layout: PassLayout, bindings: PassBindings) -> PassRuntime {
        self.build_render_pass(gpu, pass, layout, bindings, |spec| {
            Pipeline::Scene(ScenePipelines::new(spec, pass.cull_back_faces, pass.cull_closed_back_faces, DrawnInstances::of_pass(pass)))
        })
    }

    /// Records scene raster pass `i`: its runs of draws ([`super::draws`]), each with the
    /// pipeline variant of its class: every variant's draws in the frame's draw order (front to
    /// back), opaque variants first, or in a translucent pass back to front.
    pub(super) fn record_scene_raster_pass(&self, encoder: &mut wgpu::CommandEncoder, i: usize, pipelines: &ScenePipelines) -> Result<(), RuntimeError> {
        let mut rp = self.begin_render_pass(encoder, i);
        let (Some(vertices), Some(indices)) = (self.scene_part(|s| s.vertices()).ok(), self.scene_part(|s| s.indices()).ok()) else {
            return Err(RuntimeError::Gpu(format!("pass {} draws the scene, but its geometry was not uploaded", self.plan.passes[i].name)));
        };
        rp.set_vertex_buffer(0, vertices.slice(..));
        rp.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        let Some(draws) = self.draws.pass(i) else { return Ok(()) };
        for (class, run) in draws.runs() {
            let pipeline = pipelines.variant(*class).ok_or_else(|| RuntimeError::Gpu(format!("no pipeline was made for draw class {class:?}")))?;
            rp.set_pipeline(pipeline);
            draws.record_run(&mut rp, run);
        }
        Ok(())
    }

    /// Whether a kept pass draws a shadow map (a `SceneRaster` pass that writes only depth).
    pub(super) fn draws_shadow_maps(&self) -> bool {
        self.plan.passes.iter().any(|p| p.kind == PassKind::SceneRaster && p.writes.iter().all(|(_, r)| self.is_depth(*r)))
    }
}
