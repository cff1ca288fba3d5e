//! `raygraph view`: a winit window showing a running graph with an egui overlay.
//!
//! - [`session`]: the running graph without any window (compile, hot reload with the last
//!   good plan kept, parameter edits in place, effect switches, mode and back-end switches,
//!   the rolling frame statistics);
//! - [`display`]: the viewport's texture (the output, or any pass's texture mapped for display);
//! - [`camera`]: the fly camera and track recording/playback;
//! - [`clock`]: the animation clock (play, pause, scrub, speed);
//! - [`ui`]: the egui overlay (controls, profiler, parameters, graph, errors);
//! - [`script`]: timed actions for automated runs;
//! - [`app`]: the window, surface and event loop tying them together.

pub mod app;
pub mod camera;
pub mod clock;
pub mod display;
pub mod script;
pub mod session;
pub mod ui;

pub use app::{run, ViewerOptions};
