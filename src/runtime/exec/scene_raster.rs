//! `SceneRaster` passes: the scene's meshes drawn with one pipeline variant per draw class
//! (`crate::runtime::raster`), front to back, or back to front in a translucent pass, from the
//! draws kept in `super::draws`; a pass of shadow tiles (`PassDesc::shadow_tiles`) draws each
//! tile in use in its viewport, with its own pipelines and draws. A shadow-map pass of slots no
//! light uses this frame, or a translucent pass of a frame without translucent instances, is
//! not recorded (`Executor::draws_nothing`).

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
    /// back), opaque variants first, or in a translucent pass back to front. A pass of shadow
    /// tiles draws each tile whose slot a light uses in its viewport.
    pub(super) fn record_scene_raster_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        i: usize,
        pipelines: &ScenePipelines,
        slots_in_use: u32,
    ) -> Result<(), RuntimeError> {
        let mut rp = self.begin_render_pass(encoder, i);
        let planned = &self.plan.passes[i];
        let (Some(vertices), Some(indices)) = (self.scene_part(|s| s.vertices()).ok(), self.scene_part(|s| s.indices()).ok()) else {
            return Err(RuntimeError::Gpu(format!("pass {} draws the scene, but its geometry was not uploaded", planned.name)));
        };
        rp.set_vertex_buffer(0, vertices.slice(..));
        rp.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        let extent = planned.shadow_tiles.map(|_| self.attachment_extent(planned));
        for (tile, slot) in planned.shadow_slots().enumerate() {
            if let Some(extent) = extent {
                if !super::slot_in_use(slots_in_use, slot) {
                    continue;
                }
                let (x, y, w, h) = tile_viewport(extent, planned.tile_grid(), tile as u32);
                rp.set_viewport(x as f32, y as f32, w as f32, h as f32, 0.0, 1.0);
                rp.set_scissor_rect(x, y, w, h);
            }
            self.record_tile_draws(&mut rp, i, tile as u32, pipelines)?;
        }
        if planned.shadow_slot.is_none() {
            self.record_tile_draws(&mut rp, i, 0, pipelines)?;
        }
        Ok(())
    }

    /// Records the runs of draws of tile `tile` of pass `i` (0 for a pass without tiles).
    fn record_tile_draws(&self, rp: &mut wgpu::RenderPass<'_>, i: usize, tile: u32, pipelines: &ScenePipelines) -> Result<(), RuntimeError> {
        let Some(draws) = self.draws.pass(i, tile) else { return Ok(()) };
        for (class, run) in draws.runs() {
            let pipeline = pipelines.variant(tile, *class).ok_or_else(|| RuntimeError::Gpu(format!("no pipeline was made for draw class {class:?}")))?;
            rp.set_pipeline(pipeline);
            draws.record_run(rp, run);
        }
        Ok(())
    }

    /// The size of `pass`'s attachments (the first one's; a render pass's attachments share
    /// one), (1, 1) without any.
    fn attachment_extent(&self, pass: &PlannedPass) -> (u32, u32) {
        let (colors, depth) = self.attachments(pass);
        colors.first().copied().or(depth).map_or((1, 1), |r| self.plan.resources[r].extent)
    }

    /// Whether a kept pass draws a shadow map (a `SceneRaster` pass that writes only depth).
    pub(super) fn draws_shadow_maps(&self) -> bool {
        self.plan.passes.iter().any(|p| p.kind == PassKind::SceneRaster && p.writes.iter().all(|(_, r)| self.is_depth(*r)))
    }
}

/// The viewport (x, y, width, height) of tile `tile` of an attachment of size `extent` cut into
/// `(columns, rows)` tiles: row by row from the top left, each (width / columns, height / rows).
fn tile_viewport(extent: (u32, u32), (columns, rows): (u32, u32), tile: u32) -> (u32, u32, u32, u32) {
    let (w, h) = (extent.0 / columns.max(1), extent.1 / rows.max(1));
    (tile % columns.max(1) * w, tile / columns.max(1) * h, w, h)
}

#[cfg(test)]
mod tests {
    use super::tile_viewport;

    #[test]
    fn tiles_go_row_by_row_from_the_top_left() {
        let cube = |tile| tile_viewport((3072, 2048), (3, 2), tile);
        assert_eq!(cube(0), (0, 0, 1024, 1024));
        assert_eq!(cube(2), (2048, 0, 1024, 1024));
        assert_eq!(cube(3), (0, 1024, 1024, 1024));
        assert_eq!(cube(5), (2048, 1024, 1024, 1024));
        assert_eq!(tile_viewport((512, 256), (1, 1), 0), (0, 0, 512, 256));
    }
}
