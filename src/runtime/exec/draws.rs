//! The draws of `SceneRaster` passes, kept from frame to frame: each instance's draw class,
//! the front-to-back order of the draws, and per pass the classes of its instances and its
//! draw commands, grouped in runs of one pipeline variant and uploaded as indirect commands
//! (one `multi_draw_indexed_indirect` per run). They are made again only when the scene
//! changes (the executor's scene generation), when the camera's position moves (the order; the
//! classes stay), or when a shadow map's light moves (its pass's classes, with the instances its
//! frustum culls), so a frame of a static scene and camera records a few calls per pass,
//! whatever the number of instances.
//!
//! A device without indirect draws that set the first instance
//! (`wgpu::Features::INDIRECT_FIRST_INSTANCE`) draws the same commands one by one.

use crate::runtime::raster::{front_to_back, DrawClass, InstanceClass, ScenePipelines};
use crate::runtime::scene_upload::Draw;
use crate::scene::Scene;
use std::ops::Range;
use wgpu::util::DrawIndexedIndirectArgs;

/// The draw inputs of every `SceneRaster` pass of an executor.
#[derive(Default)]
pub(super) struct DrawInputs {
    /// The scene generation `instances` were made for.
    generation: Option<u64>,
    instances: Vec<InstanceClass>,
    /// (scene generation, camera position) the order was made for, and its version.
    order_key: Option<(u64, [f32; 3])>,
    order_version: u64,
    order: Vec<usize>,
    /// Per pass, by index in the plan (none for passes that draw no scene), per tile of a pass
    /// of shadow tiles (one otherwise).
    passes: Vec<Vec<PassDraws>>,
}

/// One pass's draws.
#[derive(Default)]
pub(super) struct PassDraws {
    /// (scene generation, order version, the slot light's view-projection) they were made for.
    key: Option<(u64, u64, Option<[f32; 16]>)>,
    /// Each instance's class in this pass (`None`: not drawn), and the (scene generation, slot
    /// light's view-projection) it was made for: a camera that moves changes the order alone.
    classes: Vec<Option<DrawClass>>,
    classes_key: Option<(u64, Option<[f32; 16]>)>,
    /// The draw commands, in recording order.
    args: Vec<DrawIndexedIndirectArgs>,
    /// Runs of `args` drawn with one variant.
    runs: Vec<(DrawClass, Range<u32>)>,
    /// `args` on the device.
    buffer: Option<wgpu::Buffer>,
}

impl PassDraws {
    /// Runs of `args` drawn with one variant.
    pub(super) fn runs(&self) -> &[(DrawClass, Range<u32>)] {
        &self.runs
    }
}

/// Where a pass's draws come from this frame.
pub(super) struct PassDrawSource<'a> {
    pub(super) pipelines: &'a mut ScenePipelines,
    /// Whether the pass draws back to front (a translucent pass).
    pub(super) back_to_front: bool,
    /// The tile of a pass of shadow tiles (0 otherwise).
    pub(super) tile: u32,
    /// The view-projection of the tile's shadow-map slot, where a light uses it this frame.
    pub(super) light_view_proj: Option<glam::Mat4>,
}

impl DrawInputs {
    /// Forgets every pass's draws (their pipelines were built again).
    pub(super) fn forget_passes(&mut self) {
        self.passes.clear();
    }

    /// Brings the draws of pass `i` (of its tile `source.tile`) up to date for a frame of
    /// `scene` (generation `generation`) seen from `eye`; makes the pipeline variants its runs
    /// need.
    pub(super) fn update_pass(
        &mut self,
        gpu: &crate::runtime::gpu::Gpu,
        scene: &Scene,
        generation: u64,
        draws: &[Draw],
        eye: glam::Vec3,
        i: usize,
        source: PassDrawSource,
    ) {
        self.update_scene(scene, generation, draws, eye);
        if self.passes.len() <= i {
            self.passes.resize_with(i + 1, Vec::new);
        }
        let tiles = &mut self.passes[i];
        let tile = source.tile as usize;
        if tiles.len() <= tile {
            tiles.resize_with(tile + 1, PassDraws::default);
        }
        let light = source.light_view_proj.map(|m| m.to_cols_array());
        let key = (generation, self.order_version, light);
        let pass = &mut tiles[tile];
        if pass.key != Some(key) {
            if pass.classes_key != Some((generation, light)) {
                pass.classes = source.pipelines.classes(&self.instances, source.light_view_proj.as_ref());
                pass.classes_key = Some((generation, light));
            }
            (pass.args, pass.runs) = runs(&self.order, draws, &pass.classes, source.back_to_front);
            pass.upload(gpu);
            pass.key = Some(key);
        }
        for (class, _) in &pass.runs {
            source.pipelines.prepare(gpu.device(), source.tile, &[Some(*class)]);
        }
    }

    /// The draws of tile `tile` of pass `i` (none before its first update).
    pub(super) fn pass(&self, i: usize, tile: u32) -> Option<&PassDraws> {
        self.passes.get(i).and_then(|tiles| tiles.get(tile as usize))
    }

    /// The instances' classes for scene generation `generation`, and the draw order from `eye`.
    fn update_scene(&mut self, scene: &Scene, generation: u64, draws: &[Draw], eye: glam::Vec3) {
        if self.generation != Some(generation) {
            self.instances = InstanceClass::of_scene(scene, draws);
            self.generation = Some(generation);
        }
        let order_key = (generation, eye.to_array());
        if self.order_key != Some(order_key) {
            self.order = front_to_back(draws, scene, eye);
            self.order_key = Some(order_key);
            self.order_version += 1;
        }
    }
}

/// The draw commands of a pass whose instances have `classes`, in draw `order` (reversed
/// `back_to_front`): grouped by variant, opaque variants first, each group in draw order; or,
/// back to front, in one sequence cut where the class changes.
fn runs(order: &[usize], draws: &[Draw], classes: &[Option<DrawClass>], back_to_front: bool) -> (Vec<DrawIndexedIndirectArgs>, Vec<(DrawClass, Range<u32>)>) {
    let classed = |d: &Draw| classes.get(d.instance as usize).copied().flatten();
    let mut sequence: Vec<(DrawClass, &Draw)> = order.iter().filter_map(|&k| draws.get(k)).filter_map(|d| classed(d).map(|c| (c, d))).collect();
    if back_to_front {
        sequence.reverse();
    } else {
        // Stable: each class keeps the draw order. Opaque variants before alpha-tested ones,
        // so that the cheap draws fill the depth buffer first.
        sequence.sort_by_key(|(c, _)| (c.alpha_test, c.cull));
    }
    let args: Vec<DrawIndexedIndirectArgs> = sequence
        .iter()
        .map(|(_, d)| DrawIndexedIndirectArgs {
            index_count: d.indices.end - d.indices.start,
            instance_count: 1,
            first_index: d.indices.start,
            base_vertex: d.base_vertex,
            first_instance: d.instance,
        })
        .collect();
    let mut runs: Vec<(DrawClass, Range<u32>)> = Vec::new();
    for (k, (class, _)) in sequence.iter().enumerate() {
        match runs.last_mut() {
            Some((c, range)) if c == class => range.end = k as u32 + 1,
            _ => runs.push((*class, k as u32..k as u32 + 1)),
        }
    }
    (args, runs)
}

impl PassDraws {
    /// Writes `args` to the indirect buffer (a larger one when they outgrew it), where the
    /// device draws indirect.
    fn upload(&mut self, gpu: &crate::runtime::gpu::Gpu) {
        if !indirect_draws(gpu.device()) || self.args.is_empty() {
            return;
        }
        let bytes: Vec<u8> = self.args.iter().flat_map(|a| a.as_bytes().iter().copied()).collect();
        if self.buffer.as_ref().is_none_or(|b| b.size() < bytes.len() as u64) {
            self.buffer = Some(gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene draws"),
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(buffer) = &self.buffer {
            gpu.queue().write_buffer(buffer, 0, &bytes);
        }
    }

    /// Records run `run` into `rp`, whose pipeline is set: one indirect call, or its draws one
    /// by one on a device without indirect first instances.
    pub(super) fn record_run(&self, rp: &mut wgpu::RenderPass<'_>, run: &Range<u32>) {
        match &self.buffer {
            Some(buffer) => rp.multi_draw_indexed_indirect(buffer, run.start as u64 * DRAW_ARGS_BYTES, run.end - run.start),
            None => {
                for a in &self.args[run.start as usize..run.end as usize] {
                    rp.draw_indexed(a.first_index..a.first_index + a.index_count, a.base_vertex, a.first_instance..a.first_instance + 1);
                }
            }
        }
    }
}

/// Bytes of one indexed indirect draw command.
const DRAW_ARGS_BYTES: u64 = std::mem::size_of::<DrawIndexedIndirectArgs>() as u64;

/// Whether `device` draws the scene through indirect commands: it can set their first
/// instance (the instance index the shaders read).
fn indirect_draws(device: &wgpu::Device) -> bool {
    device.features().contains(wgpu::Features::INDIRECT_FIRST_INSTANCE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runtime::raster::Cull;

    fn draw(instance: u32) -> Draw {
        Draw { indices: instance * 3..instance * 3 + 3, base_vertex: 0, instance, local_center: glam::Vec3::ZERO, local_bounds: None, closed: false }
    }

    #[test]
    fn runs_group_classes_in_draw_order_or_follow_it_back_to_front() {
        let opaque = DrawClass { cull: Cull::Back, alpha_test: false };
        let tested = DrawClass { cull: Cull::None, alpha_test: true };
        let draws: Vec<Draw> = (0..4).map(draw).collect();
        let classes = [Some(tested), Some(opaque), None, Some(opaque)];
        let order = [3, 0, 2, 1];
        let (args, groups) = runs(&order, &draws, &classes, false);
        assert_eq!(args.iter().map(|a| a.first_instance).collect::<Vec<_>>(), vec![3, 1, 0]);
        assert_eq!(groups, vec![(opaque, 0..2), (tested, 2..3)]);
        let (args, groups) = runs(&order, &draws, &classes, true);
        assert_eq!(args.iter().map(|a| a.first_instance).collect::<Vec<_>>(), vec![1, 0, 3]);
        assert_eq!(groups, vec![(opaque, 0..1), (tested, 1..2), (opaque, 2..3)]);
        assert_eq!((args[0].first_index, args[0].index_count), (3, 3));
    }
}
