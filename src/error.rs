//! Diagnostics: every error a user's file can cause, with the file, line and column it
//! points at and a hint saying what to change.

use std::fmt;
use std::path::{Path, PathBuf};

/// A position in a source file (1-based line and column).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file, as the user named it (or `<built-in>/...` for a built-in file).
    pub file: PathBuf,
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub col: u32,
}

impl Location {
    /// A location from its parts.
    pub(crate) fn new(file: impl Into<PathBuf>, line: u32, col: u32) -> Self {
        Self { file: file.into(), line, col }
    }

    /// Location of byte `offset` inside `text`.
    pub(crate) fn at_offset(file: &Path, text: &str, offset: usize) -> Self {
        let offset = offset.min(text.len());
        let prefix = &text[..offset];
        let line = prefix.matches('\n').count() as u32 + 1;
        let line_start = prefix.rfind('\n').map(|p| p + 1).unwrap_or(0);
        let col = prefix[line_start..].chars().count() as u32 + 1;
        Self { file: file.to_path_buf(), line, col }
    }

    /// The start of a file, for errors that concern the file as a whole.
    pub fn file_start(file: &Path) -> Self {
        Self::new(file, 1, 1)
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// The class of a graph error. Each class is distinct so tools and tests can tell them apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A file could not be read.
    Io,
    /// A graph or layer file is not valid RON or does not match the schema.
    Syntax,
    /// A graph node names a layer file that does not exist.
    UnknownLayer,
    /// A connection names a node or an output that does not exist.
    UnknownOutput,
    /// The graph's connections form a cycle.
    Cycle,
    /// A resource is read but nothing produces it.
    NoProducer,
    /// Two passes write the same resource.
    TwoProducers,
    /// A parameter is not declared by its layer.
    UnknownParam,
    /// A parameter value lies outside the declared range.
    ParamOutOfRange,
    /// A parameter value has the wrong type.
    ParamType,
    /// A consumer expects a different texture format or resource type than its producer gives.
    FormatMismatch,
    /// A shader's global bindings do not match the pass's declared resources.
    BindingMismatch,
    /// A WGSL file does not parse or validate.
    ShaderInvalid,
    /// The graph is well-formed but asks for something the runtime cannot do.
    Unsupported,
}

/// An error located in a graph, layer or shader file.
#[derive(Debug, Clone)]
pub struct GraphError {
    /// The class of the error.
    pub kind: ErrorKind,
    /// Where it is.
    pub location: Location,
    /// What is wrong, one sentence.
    pub message: String,
    /// What to change to fix it.
    pub help: Option<String>,
    /// Other places involved (for example the WGSL line of a binding).
    pub notes: Vec<(Location, String)>,
}

impl GraphError {
    /// An error without help or notes (add them with [`GraphError::help`] and [`GraphError::note`]).
    pub(crate) fn new(kind: ErrorKind, location: Location, message: impl Into<String>) -> Self {
        Self { kind, location, message: message.into(), help: None, notes: Vec::new() }
    }

    /// Adds what to change to fix it.
    pub(crate) fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Adds another place involved, with what it is.
    pub(crate) fn note(mut self, location: Location, text: impl Into<String>) -> Self {
        self.notes.push((location, text.into()));
        self
    }
}

impl fmt::Display for GraphError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: error: {}", self.location, self.message)?;
        for (loc, text) in &self.notes {
            write!(f, "\n  --> {loc}: {text}")?;
        }
        if let Some(help) = &self.help {
            write!(f, "\n  help: {help}")?;
        }
        Ok(())
    }
}

impl std::error::Error for GraphError {}

/// Errors of the GPU runtime (device creation, execution, output).
#[derive(Debug, thiserror::Error)]
pub enum RuntimeError {
    /// No adapter: wgpu found no device (its message).
    #[error("no Vulkan adapter found: {0}\n  help: install a Vulkan driver (on a machine without a GPU: Mesa's lavapipe, see README.md)")]
    NoAdapter(String),
    /// The adapter refused the device raygraph asked for.
    #[error("could not create the GPU device on {adapter}: {message}")]
    Device {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        message: String,
    },
    /// A GPU operation failed (wgpu's message).
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The device was lost during the run.
    #[error("the GPU device was lost ({adapter}): {reason}\n  help: nothing was written; a driver reset or a GPU fault ends the run, start it again")]
    DeviceLost {
        /// The adapter's name.
        adapter: String,
        /// Why, as the driver or wgpu said.
        reason: String,
    },
    /// An allocation failed.
    #[error("the GPU ran out of memory ({adapter}) {what}: {message}\n  help: nothing was written; use a smaller frame (--width, --height) or scene")]
    OutOfMemory {
        /// The adapter's name.
        adapter: String,
        /// The work that allocated ("while building the executor").
        what: String,
        /// wgpu's message.
        message: String,
    },
    /// A wait ran past the GPU deadline ([`crate::runtime::Gpu::gpu_timeout`]).
    #[error("the GPU ran past its deadline of {seconds} s (--gpu-timeout) on {work}\n  help: nothing was written; look for a loop that never ends in these passes' shaders, or raise --gpu-timeout if the frame is only slow")]
    GpuTimeout {
        /// The deadline, in seconds.
        seconds: f64,
        /// The work waited for (a frame and its passes).
        work: String,
    },
    /// An output file could not be written.
    #[error("could not write {path}: {source}")]
    Output {
        /// The file.
        path: PathBuf,
        /// The error of the write.
        source: std::io::Error,
    },
    /// An image could not be encoded.
    #[error("could not encode image {path}: {message}")]
    Encode {
        /// The file it was for.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// An error in a graph, layer or shader file.
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// The scene exceeds what the device can bind.
    #[error(transparent)]
    SceneLimit(#[from] crate::scene::usage::SceneLimitError),
    /// The scene could not be opened.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// A camera track could not be read or written.
    #[error(transparent)]
    Track(#[from] crate::scene::track::TrackError),
    /// A measurement does not meet its test's definition (a Stress view with sky in it, a Miss
    /// view that hits): the message names the test, scene, camera and what was measured.
    #[error("{0}")]
    NotTheTest(String),
}
