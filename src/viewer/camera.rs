//! The viewer's camera: the fly camera (`scene::fly`; mouse look while the right button is
//! held) and track recording and playback.

pub use crate::scene::fly::{FlyCamera, Motion};
use crate::scene::track::Track;

/// Recording or playing a camera track.
#[derive(Debug, Default)]
pub(crate) enum TrackState {
    /// Neither.
    #[default]
    Idle,
    /// Recording.
    Recording {
        /// The keys recorded so far.
        track: Track,
        /// Seconds since recording started.
        seconds: f32,
    },
    /// Playing.
    Playing {
        /// The track played.
        track: Track,
        /// Where in the track, seconds.
        seconds: f32,
    },
}

/// Keys per second while recording.
pub(crate) const RECORD_FPS: f32 = 30.0;
