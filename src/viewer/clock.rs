//! The viewer's animation clock: which clip plays, where it is, whether it runs and how fast.
//! It advances by the wall time between frames times the speed, or by a fixed step per frame
//! in scripted and `--frames` runs (so that their screenshots do not depend on the machine's
//! speed); clips loop. The session poses the scene for the GPU at the clock's time.

use crate::scene::animation::{ClipChoice, ClipSet};
use crate::scene::Scene;
use std::time::Instant;

/// The clock of a scene's animation.
#[derive(Debug, Clone)]
pub(crate) struct AnimationClock {
    /// The clips that play (rest: the scene has no animation).
    clip: ClipSet,
    /// Seconds into the clip.
    time: f32,
    /// Whether time runs.
    playing: bool,
    /// Seconds of clip per second of wall time.
    speed: f32,
    /// Seconds per frame instead of the wall clock (scripted runs).
    fixed_step: Option<f32>,
    last: Option<Instant>,
}

impl AnimationClock {
    /// The clips that play (rest: the scene has no animation).
    pub(crate) fn clip(&self) -> ClipSet {
        self.clip
    }

    /// Seconds into the clip.
    pub(crate) fn time(&self) -> f32 {
        self.time
    }

    /// Whether time runs.
    pub(crate) fn playing(&self) -> bool {
        self.playing
    }

    /// Runs (`true`) or stops time.
    pub(crate) fn set_playing(&mut self, on: bool) {
        self.playing = on;
    }

    /// Seconds of clip per second of wall time.
    pub(crate) fn speed(&self) -> f32 {
        self.speed
    }

    /// Sets the seconds of clip per second of wall time.
    pub(crate) fn set_speed(&mut self, speed: f32) {
        self.speed = speed;
    }

    /// Seconds per frame instead of the wall clock (scripted runs).
    pub(crate) fn fixed_step(&self) -> Option<f32> {
        self.fixed_step
    }

    /// Advances by `step` seconds per frame instead of the wall clock (`None`: the wall clock).
    pub(crate) fn set_fixed_step(&mut self, step: Option<f32>) {
        self.fixed_step = step;
    }

    /// A clock at the rest pose, stopped (until the scene's own clock replaces it).
    pub(crate) fn at_rest() -> Self {
        Self { clip: ClipSet::Rest, time: 0.0, playing: false, speed: 1.0, fixed_step: None, last: None }
    }

    /// The clock of `scene`'s clip `choice`, at `start` seconds, playing.
    pub fn new(scene: &Scene, choice: &ClipChoice, start: f32) -> Result<Self, String> {
        let clip = match &scene.rig() {
            Some(rig) => rig.clip(choice)?,
            None if matches!(choice, ClipChoice::First | ClipChoice::All) => ClipSet::Rest,
            None => return Err(format!("scene `{}` has no animations", scene.name())),
        };
        Ok(Self { clip, time: start, playing: clip.is_playing(), speed: 1.0, fixed_step: None, last: None })
    }

    /// The clip's length in seconds (0 without one).
    pub fn duration(&self, scene: &Scene) -> f32 {
        scene.rig().map_or(0.0, |rig| rig.duration(self.clip))
    }

    /// Moves time on by one frame (when playing), wrapping at the clip's end.
    pub(crate) fn tick(&mut self, scene: &Scene) {
        let now = Instant::now();
        let dt = match (self.fixed_step, self.last) {
            (Some(step), _) => step,
            (None, Some(last)) => now.duration_since(last).as_secs_f32(),
            (None, None) => 0.0,
        };
        self.last = Some(now);
        if self.playing && self.clip.is_playing() {
            let d = self.duration(scene);
            self.time = if d > 0.0 { (self.time + dt * self.speed).rem_euclid(d) } else { 0.0 };
        }
    }

    /// Jumps to `time` seconds (wrapped into the clip).
    pub(crate) fn seek(&mut self, scene: &Scene, time: f32) {
        let d = self.duration(scene);
        self.time = if d > 0.0 && time.is_finite() { time.rem_euclid(d) } else { 0.0 };
    }

    /// One line for the overlay, for a scene with a clip.
    pub fn describe(&self, scene: &Scene) -> Option<String> {
        let name = scene.rig().filter(|_| self.clip.is_playing())?.describe(self.clip);
        let state = if self.playing { format!("playing at {:.2}x", self.speed) } else { "paused".into() };
        Some(format!("animation: `{name}` at {:.3} of {:.2} s, {state}", self.time, self.duration(scene)))
    }
}
