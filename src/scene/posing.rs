//! Posing a [`Scene`] from its rig ([`crate::scene::animation`]): instance transforms from the
//! nodes' world matrices, and the deforming meshes morphed and skinned on the CPU
//! ([`Scene::pose`]) or left to the executor's GPU deformation ([`Scene::pose_for_gpu`]).

use super::animation::{ClipSet, Pose, PoseTime, Rig};
use super::{Scene, Vertex};
use glam::Mat4;

impl Scene {
    /// Poses the scene at `time` seconds of `clip` (a clip index, `None` for the rest pose, or
    /// a [`ClipSet`]): instance transforms from the nodes' world matrices, deforming meshes
    /// morphed and skinned on the CPU. Nothing to do for a scene without a rig.
    pub fn pose(&mut self, clip: impl Into<ClipSet>, time: f32) {
        let clip = clip.into();
        let Some(rig) = self.rig.clone() else { return };
        let pose = rig.pose(clip, time);
        self.apply_pose(&rig, &pose, true);
        self.posed = Some(PoseTime { clip, time, meshes_deformed: true });
    }

    /// Poses the instances only and leaves the deforming meshes' vertices as they are: an
    /// executor deforms them on the GPU (skinning and morph targets, no per-vertex work on the
    /// CPU); CPU consumers that need the vertices call [`Scene::pose`] on a copy
    /// ([`Scene::with_meshes_posed`]).
    pub fn pose_for_gpu(&mut self, clip: impl Into<ClipSet>, time: f32) {
        let clip = clip.into();
        let Some(rig) = self.rig.clone() else { return };
        let pose = rig.pose(clip, time);
        self.apply_pose(&rig, &pose, false);
        self.posed = Some(PoseTime { clip, time, meshes_deformed: rig.deformers.is_empty() });
    }

    /// This scene with its deforming meshes' vertices holding its pose: itself, or a copy posed
    /// on the CPU when the pose was left to the GPU (its images shared, not copied).
    pub fn with_meshes_posed(&self) -> std::borrow::Cow<'_, Scene> {
        match self.posed {
            Some(PoseTime { clip, time, meshes_deformed: false }) => {
                let mut copy = self.clone();
                copy.pose(clip, time);
                std::borrow::Cow::Owned(copy)
            }
            _ => std::borrow::Cow::Borrowed(self),
        }
    }

    /// A key that changes whenever the deforming meshes' shape changes: their vertices' hash,
    /// or the pose time when the GPU deforms them; `None` without deforming meshes.
    pub(crate) fn deformation_key(&self) -> Option<u64> {
        use crate::util::hash_words;
        let deforming = self.deforming_meshes();
        if deforming.is_empty() {
            return None;
        }
        Some(match self.posed {
            Some(PoseTime { clip, time, meshes_deformed: false }) => hash_words(
                match clip {
                    ClipSet::Rest => u64::MAX,
                    ClipSet::All => u64::MAX - 1,
                    ClipSet::One(c) => c as u64,
                },
                &time.to_bits().to_le_bytes(),
            ),
            _ => deforming.iter().fold(7, |h, &m| hash_words(h, bytemuck::cast_slice(&self.meshes[m].vertices))),
        })
    }

    fn apply_pose(&mut self, rig: &Rig, pose: &Pose, deform: bool) {
        for (inst, src) in self.instances_mut().iter_mut().zip(rig.instances.iter()) {
            inst.transform = if src.skinned { Mat4::IDENTITY } else { pose.world[src.node] };
        }
        if deform {
            use rayon::prelude::*;
            let meshes: Vec<(usize, Vec<Vertex>)> = rig
                .deformers
                .par_iter()
                .map(|d| {
                    let (joints, weights) = pose.deform_inputs(rig, d);
                    (d.mesh, d.deform(&joints, &weights))
                })
                .collect();
            for (m, vertices) in meshes {
                std::sync::Arc::make_mut(&mut self.meshes[m]).vertices = vertices;
            }
        }
    }
}
