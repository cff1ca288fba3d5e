//! Camera tracks: key-frames recorded from a camera, saved to and loaded from RON files
//! (written atomically), played back deterministically by frame index.
//!
//! A track is a list of key-frames at increasing times (seconds). Playback at frame `i` of a
//! track played at `fps` evaluates the camera at `t = i / fps` with a centripetal-free
//! uniform Catmull-Rom spline through the positions and targets (linear for two key-frames),
//! so the same frame index always gives the same camera, whatever the machine's speed.

use super::Camera;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Why a camera track could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    /// The file cannot be read.
    #[error("{path}: cannot read the camera track: {message}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The system's message.
        message: String,
    },
    /// The file is not a track in RON.
    #[error("{path}:{line}:{col}: not a camera track: {message}\n  help: a track is `Track(fps: 30.0, keys: [Key(time: 0.0, position: (x, y, z), target: (x, y, z), fov_y_deg: 50.0), ...])`")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// Line of the error, from 1.
        line: usize,
        /// Column of the error, from 1.
        col: usize,
        /// The parser's message.
        message: String,
    },
    /// The track parses but cannot be played (no keys, times out of order, ...).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The track could not be saved.
    #[error("could not write {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// One key-frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Key {
    /// Seconds from the start of the track.
    pub time: f32,
    /// World-space camera position.
    pub position: (f32, f32, f32),
    /// World-space point the camera looks at.
    pub target: (f32, f32, f32),
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

/// A recorded camera path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Track {
    /// Playback rate: frame `i` is shown at `i / fps` seconds.
    pub fps: f32,
    /// The key-frames, in time order.
    pub keys: Vec<Key>,
}

fn v(t: (f32, f32, f32)) -> Vec3 {
    Vec3::new(t.0, t.1, t.2)
}

impl Key {
    /// A key-frame at `time` holding the camera `c`.
    pub(crate) fn from_camera(time: f32, c: &Camera) -> Self {
        Key { time, position: c.position.into(), target: c.target.into(), fov_y_deg: c.fov_y.to_degrees() }
    }
}

impl Track {
    /// An empty track to record into.
    pub fn new(fps: f32) -> Self {
        Track { fps, keys: Vec::new() }
    }

    /// Appends a key-frame of `camera` at `time` (seconds; must not go back in time).
    pub fn record(&mut self, time: f32, camera: &Camera) {
        self.keys.push(Key::from_camera(time, camera));
    }

    /// Length in seconds.
    pub fn duration(&self) -> f32 {
        self.keys.last().map(|k| k.time).unwrap_or(0.0)
    }

    /// Number of frames the track plays for at its fps (the last key included).
    pub fn frame_count(&self) -> u32 {
        (self.duration() * self.fps).floor() as u32 + 1
    }

    /// Checks what playback relies on: at least one key, finite values, increasing times,
    /// position distinct from target, a field of view in (0, 180) degrees, fps > 0.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(format!("fps is {}; it must be a positive number", self.fps));
        }
        if self.keys.is_empty() {
            return Err("the track has no key-frames".into());
        }
        for (i, k) in self.keys.iter().enumerate() {
            let finite = k.time.is_finite() && v(k.position).is_finite() && v(k.target).is_finite() && k.fov_y_deg.is_finite();
            if !finite {
                return Err(format!("key {i} has a value that is not a finite number"));
            }
            if !(k.fov_y_deg > 0.0 && k.fov_y_deg < 180.0) {
                return Err(format!("key {i}: fov_y_deg {} is outside (0, 180)", k.fov_y_deg));
            }
            if v(k.position).distance(v(k.target)) < 1e-6 {
                return Err(format!("key {i}: position and target are the same point"));
            }
            if i > 0 && k.time <= self.keys[i - 1].time {
                return Err(format!("key {i}: time {} does not come after the previous key's {}", k.time, self.keys[i - 1].time));
            }
        }
        Ok(())
    }

    /// The camera at `frame` (deterministic: depends only on the track and the index).
    /// `base` supplies what a track does not store (up vector, near and far planes).
    pub fn camera_at_frame(&self, frame: u32, base: &Camera) -> Camera {
        self.camera_at(frame as f32 / self.fps, base)
    }

    /// The camera at `time` seconds, clamped to the track's ends.
    pub(crate) fn camera_at(&self, time: f32, base: &Camera) -> Camera {
        let Some(first) = self.keys.first() else { return *base };
        let n = self.keys.len();
        let mut cam = *base;
        if n == 1 || time <= first.time {
            set(&mut cam, first);
            return cam;
        }
        let last = self.keys[n - 1];
        if time >= last.time {
            set(&mut cam, &last);
            return cam;
        }
        // The segment [i, i+1] holding `time`.
        let i = self.keys.partition_point(|k| k.time <= time) - 1;
        let (k1, k2) = (self.keys[i], self.keys[i + 1]);
        let k0 = if i > 0 { self.keys[i - 1] } else { k1 };
        let k3 = if i + 2 < n { self.keys[i + 2] } else { k2 };
        let s = (time - k1.time) / (k2.time - k1.time);
        cam.position = catmull_rom(v(k0.position), v(k1.position), v(k2.position), v(k3.position), s);
        cam.target = catmull_rom(v(k0.target), v(k1.target), v(k2.target), v(k3.target), s);
        cam.fov_y = (k1.fov_y_deg + (k2.fov_y_deg - k1.fov_y_deg) * s).to_radians();
        if cam.position.distance(cam.target) < 1e-6 {
            cam.target = cam.position + (v(k2.target) - v(k2.position)).normalize_or(Vec3::NEG_Z);
        }
        cam
    }

    /// A circle around `center` at `radius` and `height`, looking at `center`, `seconds` long
    /// with one key-frame per `seconds / keys`.
    pub fn orbit(center: Vec3, radius: f32, height: f32, seconds: f32, keys: u32, fov_y_deg: f32) -> Self {
        let keys = keys.max(2);
        let keys = (0..=keys)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / keys as f32;
                let p = center + Vec3::new(radius * a.cos(), height, radius * a.sin());
                Key { time: seconds * i as f32 / keys as f32, position: p.into(), target: center.into(), fov_y_deg }
            })
            .collect();
        Track { fps: 30.0, keys }
    }

    /// Loads and validates a track file.
    pub fn load(path: &Path) -> Result<Self, TrackError> {
        let text = std::fs::read_to_string(path).map_err(|e| TrackError::Read { path: path.to_path_buf(), message: e.to_string() })?;
        let track: Track = ron::from_str(&text).map_err(|e| TrackError::Syntax {
            path: path.to_path_buf(),
            line: e.position.line,
            col: e.position.col,
            message: e.code.to_string(),
        })?;
        track.validate().map_err(|message| TrackError::Invalid { path: path.to_path_buf(), message })?;
        Ok(track)
    }

    /// Writes the track as RON to a temporary file beside `path`, then renames it: a failed
    /// write never leaves a partial track.
    pub fn save(&self, path: &Path) -> Result<(), TrackError> {
        let err = |message: String| TrackError::Write { path: path.to_path_buf(), message };
        self.validate().map_err(err)?;
        let text = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default()).map_err(|e| err(e.to_string()))?;
        crate::util::write_atomic(path, text.as_bytes()).map_err(|e| err(e.to_string()))
    }
}

fn set(cam: &mut Camera, k: &Key) {
    cam.position = v(k.position);
    cam.target = v(k.target);
    cam.fov_y = k.fov_y_deg.to_radians();
}

/// Uniform Catmull-Rom between p1 and p2.
fn catmull_rom(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, s: f32) -> Vec3 {
    let s2 = s * s;
    let s3 = s2 * s;
    0.5 * ((2.0 * p1) + (p2 - p0) * s + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s2 + (3.0 * p1 - p0 - 3.0 * p2 + p3) * s3)
}
