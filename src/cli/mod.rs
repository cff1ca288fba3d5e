//! The subcommands of `raygraph`, one module each: each turns its arguments into calls of the
//! library and prints what they return. The argument groups they share are in [`args`].

pub(crate) mod args;
pub(crate) mod bench;
pub(crate) mod graph;
pub(crate) mod render;
pub(crate) mod scene;
pub(crate) mod selftest;
pub(crate) mod soak;
pub(crate) mod view;

/// The target of the command's own log lines: the binary's name, which `env_logger` prints
/// with each line.
pub(crate) const LOG_TARGET: &str = "raygraph";
