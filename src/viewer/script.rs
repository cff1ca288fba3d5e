//! `raygraph view --script FILE`: timed actions for automated runs, a RON list of steps, each
//! done at the start of a frame (frame 0 is the first frame drawn):
//!
//! ```ron
//! Script(steps: [
//!     (frame: 2, action: Mode(FullRt)),
//!     (frame: 4, action: Param(node: "ao", name: "rays", value: 2)),
//!     (frame: 5, action: Enable(node: "reflection", on: false)),
//!     (frame: 6, action: SelectPass("ao/sum")),
//!     (frame: 7, action: Seek(1.25)),
//!     (frame: 7, action: Play(false)),
//!     (frame: 8, action: Screenshot("ao.png")),
//!     (frame: 9, action: Quit),
//! ])
//! ```
//!
//! Relative paths are taken from the current directory.

use crate::graph::desc::ParamValue;
use crate::graph::Mode;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Timed actions, as a RON file writes them.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, rename = "Script")]
pub struct Script {
    /// The steps, in frame order.
    pub(crate) steps: Vec<Step>,
}

/// One action at one frame.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Step {
    /// The frame (redraw count) it runs at.
    pub(crate) frame: u64,
    /// What it does.
    pub(crate) action: Action,
}

/// What the UI can do, as a script step.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum Action {
    /// Switch to a built-in mode's graph.
    Mode(ScriptMode),
    /// Switch the traversal back-end (`compute`, `ray-query`).
    Backend(String),
    /// Set a parameter of a layer node.
    Param {
        /// The node.
        node: String,
        /// The parameter.
        name: String,
        /// Its new value.
        value: ParamValue,
    },
    /// Switch a layer node (an effect) on or off.
    Enable {
        /// The node.
        node: String,
        /// On or off.
        on: bool,
    },
    /// Show the first texture a pass writes in the viewport (as clicking it in the overlay).
    SelectPass(String),
    /// Whether a camera move restarts the history of an accumulating graph (on at start).
    ResetHistoryOnMove(bool),
    /// Show a texture resource by name (`gbuffer.normal`).
    SelectResource(String),
    /// Show the graph's output again.
    ShowOutput,
    /// Move the camera to a preset of the scene.
    Preset(String),
    /// Place the camera.
    Camera {
        /// Eye position.
        position: (f32, f32, f32),
        /// Point looked at.
        target: (f32, f32, f32),
    },
    /// Write the window (frame and overlay) to a PNG, and what the overlay lists beside it
    /// (`FILE.overlay.txt`).
    Screenshot(PathBuf),
    /// Show or hide the overlay.
    Overlay(bool),
    /// Start recording a camera track (a key every 1/30 s of the fly camera).
    Record,
    /// Stop recording and save the track (RON, as `bench track` reads).
    SaveTrack(PathBuf),
    /// Play a track file.
    PlayTrack(PathBuf),
    /// Run or pause the animation's clock.
    Play(bool),
    /// Move the animation's clock to a time (seconds; scrubbing).
    Seek(f32),
    /// Seconds of animation per second of wall time (per 1/60 s step in scripted runs).
    Speed(f32),
    /// Play another clip of the scene, by name or index, from its start.
    Clip(String),
    /// Close the window.
    Quit,
}

/// [`Mode`] as written in scripts.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub enum ScriptMode {
    /// [`Mode::Raster`].
    Raster,
    /// [`Mode::Hybrid`].
    Hybrid,
    /// [`Mode::FullRt`].
    FullRt,
}

impl From<ScriptMode> for Mode {
    fn from(m: ScriptMode) -> Mode {
        match m {
            ScriptMode::Raster => Mode::Raster,
            ScriptMode::Hybrid => Mode::Hybrid,
            ScriptMode::FullRt => Mode::FullRt,
        }
    }
}

impl Script {
    /// Reads a script; errors name the file and, for syntax errors, the line and column.
    pub fn load(path: &Path) -> Result<Script, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: cannot read the script: {e}", path.display()))?;
        let mut script: Script =
            ron::from_str(&text).map_err(|e| format!("{}:{}:{}: invalid script: {}", path.display(), e.position.line, e.position.col, e.code))?;
        script.steps.sort_by_key(|s| s.frame);
        Ok(script)
    }

    /// The steps due at `frame`.
    pub(crate) fn due(&self, frame: u64) -> impl Iterator<Item = &Action> {
        self.steps.iter().filter(move |s| s.frame == frame).map(|s| &s.action)
    }
}
