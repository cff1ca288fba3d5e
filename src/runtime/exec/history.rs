//! History resources at run time (`LayerDesc::history`): each used history and the resource it
//! keeps own two textures that trade places before every frame but the first, so that what a
//! frame wrote is what the next frame reads as its history, with no copy. Resources map to
//! their texture through `Executor::slot_of`; a pass that binds either texture of a pair has
//! a second set of bind groups with the two exchanged, used on the frames where they are.
//!
//! The history is valid (`frame.history_valid` = 1) from the second frame of an executor on
//! (a recompile or a resize makes a new one), until a camera cut: `Executor::camera_cut`,
//! or a camera that jumps more than `CUT_DISTANCE` times the scene's bounding radius, turns
//! more than `CUT_ANGLE_DEGREES` or changes its field of view in one frame.

use crate::graph::compile::Plan;
use crate::scene::Camera;

/// A camera move longer than this fraction of the scene's bounding radius in one frame is a cut.
pub(crate) const CUT_DISTANCE: f32 = 0.25;
/// A camera turn larger than this in one frame is a cut.
pub(crate) const CUT_ANGLE_DEGREES: f32 = 30.0;

/// The history pairs of a plan and where they stand.
#[derive(Debug, Default)]
pub(super) struct HistoryState {
    /// (slot of the kept resource, slot of its history), for every used history.
    pub(super) pairs: Vec<(usize, usize)>,
    /// Whether the two slots of every pair are exchanged this frame.
    pub(super) swapped: bool,
    /// Whether the history holds the previous frame (`frame.history_valid`).
    pub(super) valid: bool,
    /// A cut was asked for (`Executor::camera_cut`).
    pub(super) cut_requested: bool,
    /// The camera and view-projection of the previous frame.
    pub(super) previous: Option<(Camera, glam::Mat4)>,
    /// The instances of the previous frame (`scene_motion`), as the scene holds them.
    pub(super) instances: Option<std::sync::Arc<Vec<crate::scene::Instance>>>,
    /// The instances whose transforms the `scene_motion` buffer holds.
    pub(super) motion_written: Option<std::sync::Arc<Vec<crate::scene::Instance>>>,
}

impl HistoryState {
    /// The pairs of `plan`'s used histories.
    pub(super) fn of_plan(plan: &Plan) -> Self {
        let pairs = plan
            .resources
            .iter()
            .filter_map(|h| match (h.history_of, h.slot) {
                (Some(source), Some(hs)) => plan.resources[source].slot.map(|ss| (ss, hs)),
                _ => None,
            })
            .collect();
        Self { pairs, ..Default::default() }
    }

    /// The slot that holds slot `s`'s resource when the pairs are `swapped` or not.
    pub(super) fn map(&self, s: usize, swapped: bool) -> usize {
        if !swapped {
            return s;
        }
        self.pairs
            .iter()
            .find_map(|&(a, b)| {
                if s == a {
                    Some(b)
                } else if s == b {
                    Some(a)
                } else {
                    None
                }
            })
            .unwrap_or(s)
    }

    /// Whether slot `s` belongs to a pair.
    pub(super) fn holds(&self, s: usize) -> bool {
        self.pairs.iter().any(|&(a, b)| a == s || b == s)
    }

    /// Before a frame of `camera` (`view_proj`) in a scene of bounding `radius`: the pairs
    /// trade places (but before the first frame) and the history's validity is decided.
    pub(super) fn begin_frame(&mut self, camera: &Camera, view_proj: glam::Mat4, radius: f32) {
        let first = self.previous.is_none();
        if !first && !self.pairs.is_empty() {
            self.swapped = !self.swapped;
        }
        let cut = std::mem::take(&mut self.cut_requested) || self.previous.as_ref().is_some_and(|(p, _)| is_cut(p, camera, radius));
        self.valid = !first && !cut;
        if !self.valid && !first {
            log::debug!("history not valid this frame (camera cut)");
        }
        // The previous view-projection is kept by the caller before it is replaced here.
        self.previous = Some((*camera, view_proj));
    }
}

/// Whether going from camera `a` to `b` in one frame is a cut.
fn is_cut(a: &Camera, b: &Camera, radius: f32) -> bool {
    let jump = a.position.distance(b.position) > CUT_DISTANCE * radius.max(1e-6);
    let (da, db) = ((a.target - a.position).normalize_or_zero(), (b.target - b.position).normalize_or_zero());
    let turn = da.dot(db).clamp(-1.0, 1.0).acos() > CUT_ANGLE_DEGREES.to_radians();
    jump || turn || a.fov_y != b.fov_y
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(position: glam::Vec3, target: glam::Vec3) -> Camera {
        Camera::look(position, target, 50.0, 0.1, 100.0)
    }

    #[test]
    fn small_moves_keep_the_history_and_jumps_turns_and_zooms_cut_it() {
        let a = camera(glam::Vec3::new(0.0, 1.0, 5.0), glam::Vec3::ZERO);
        assert!(!is_cut(&a, &camera(glam::Vec3::new(0.1, 1.0, 5.0), glam::Vec3::ZERO), 4.0));
        assert!(is_cut(&a, &camera(glam::Vec3::new(1.5, 1.0, 5.0), glam::Vec3::ZERO), 4.0));
        assert!(is_cut(&a, &camera(glam::Vec3::new(0.0, 1.0, 5.0), glam::Vec3::new(10.0, 1.0, 5.0)), 4.0));
        assert!(is_cut(&a, &Camera { fov_y: a.fov_y * 0.5, ..a }, 4.0));
    }

    #[test]
    fn the_pairs_trade_places_from_the_second_frame_on() {
        let mut h = HistoryState { pairs: vec![(3, 7)], ..Default::default() };
        let c = camera(glam::Vec3::new(0.0, 1.0, 5.0), glam::Vec3::ZERO);
        h.begin_frame(&c, glam::Mat4::IDENTITY, 4.0);
        assert!(!h.swapped && !h.valid);
        assert_eq!((h.map(3, h.swapped), h.map(7, h.swapped), h.map(5, h.swapped)), (3, 7, 5));
        h.begin_frame(&c, glam::Mat4::IDENTITY, 4.0);
        assert!(h.swapped && h.valid);
        assert_eq!((h.map(3, h.swapped), h.map(7, h.swapped), h.map(5, h.swapped)), (7, 3, 5));
        h.cut_requested = true;
        h.begin_frame(&c, glam::Mat4::IDENTITY, 4.0);
        assert!(!h.swapped && !h.valid);
        h.begin_frame(&c, glam::Mat4::IDENTITY, 4.0);
        assert!(h.valid);
    }
}
