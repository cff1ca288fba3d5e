//! The viewer's running graph, without any window: which graph file and back-end, the
//! parameter values and effect switches set from the UI, the executor of the last plan that
//! compiled, hot reload (the graph file, every layer file and every WGSL file are watched; a
//! change compiles a new plan, and an error keeps the last good one running), and a rolling
//! window of frame timings for the profiler overlay.

use crate::backend::Backend;
use crate::graph::compile::{compile_with, CompileOptions, Plan};
use crate::graph::desc::{NodeDesc, ParamDecl, ParamValue};
use crate::graph::{Mode, Project};
use crate::runtime::profiler::FrameTimings;
use crate::runtime::report::Report;
use crate::runtime::{Executor, Gpu};
use crate::scene::{Camera, Scene};
use std::collections::{BTreeMap, VecDeque};
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

/// Frames kept for the overlay's statistics.
pub(crate) const STATS_WINDOW: usize = 120;

/// A layer node of the graph file, for the parameters panel: its parameters as declared (with
/// the values in effect) and whether it is switched on.
#[derive(Debug, Clone)]
pub(crate) struct NodeControls {
    pub(crate) node: String,
    pub(crate) layer: String,
    pub(crate) enabled: bool,
    pub(crate) params: Vec<(String, ParamDecl, ParamValue)>,
}

/// Every file a compile of the graph reads, with its modification time.
#[derive(Debug, Default, PartialEq)]
struct Snapshot(BTreeMap<PathBuf, Option<SystemTime>>);

impl Snapshot {
    fn take(graph_file: &Path, project: &Project) -> Self {
        let mut files = BTreeMap::new();
        let mtime = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
        files.insert(graph_file.to_path_buf(), mtime(graph_file));
        let mut stack = vec![project.layers_dir.clone(), project.shaders_dir.clone()];
        while let Some(dir) = stack.pop() {
            let Ok(entries) = std::fs::read_dir(&dir) else { continue };
            for e in entries.flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "wgsl")) {
                    files.insert(p.clone(), mtime(&p));
                }
            }
        }
        Snapshot(files)
    }
}

/// What happened when the files changed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Reload {
    /// A new plan runs.
    Reloaded {
        /// The new plan's passes.
        passes: usize,
    },
    /// The change does not compile; the last good plan keeps running.
    Failed(String),
}

pub(crate) struct Session {
    root: PathBuf,
    graph_file: PathBuf,
    mode: Option<Mode>,
    project: Project,
    options: CompileOptions,
    size: (u32, u32),
    scene: Scene,
    /// The scene's bounds over its whole animation (the camera's clip planes are fitted to
    /// them every frame).
    scene_bounds: crate::scene::Bounds,
    exec: Option<Executor>,
    /// The last compile or frame error (file:line where it has one), shown until a compile
    /// succeeds.
    error: Option<String>,
    snapshot: Snapshot,
    last_poll: Instant,
    /// Recent frames of the current plan (cleared when the plan changes).
    frames: VecDeque<FrameTimings>,
    frame_index: u64,
    /// Plans compiled since start (1 after the first).
    generation: u64,
    /// Transient memory of the current graph with resource reuse (the viewer runs it without).
    reuse_bytes: Option<u64>,
    /// Per-pass statistics over the rolling window (mean, median, min, max of GPU and CPU ms,
    /// rays per pixel, GigaRays/s), updated by every frame.
    report: Option<Report>,
    controls: Vec<NodeControls>,
    /// Whether a camera move restarts the history (an accumulating graph then converges only
    /// while the camera is still); off, the graph's own reprojection carries it across moves.
    reset_history_on_move: bool,
    /// The camera of the last frame.
    last_camera: Option<Camera>,
    /// Frames in a row with a valid history (0 on a frame without).
    history_frames: u64,
    /// History resets caused by camera moves since the viewer started.
    history_resets: u64,
    /// The animation's clock; the scene is posed at its time before every frame.
    clock: super::clock::AnimationClock,
}

impl Session {
    /// The project root (the built-in shaders of the viewer are found under it).
    pub(crate) fn root(&self) -> &Path {
        &self.root
    }

    /// The graph file that runs.
    pub(crate) fn graph_file(&self) -> &Path {
        &self.graph_file
    }

    /// The mode whose graph runs (`None`: a graph file of its own).
    pub(crate) fn mode(&self) -> Option<Mode> {
        self.mode
    }

    /// The scene rendered.
    pub(crate) fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene's bounds over its whole animation (the camera's clip planes are fitted to
    /// them every frame).
    pub(crate) fn scene_bounds(&self) -> crate::scene::Bounds {
        self.scene_bounds
    }

    /// The last compile or frame error (file:line where it has one), shown until a compile
    /// succeeds.
    pub(crate) fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Shows `error` until a compile succeeds (`None`: clears it).
    pub(crate) fn set_error(&mut self, error: Option<String>) {
        self.error = error;
    }

    /// Recent frames of the current plan (cleared when the plan changes).
    pub(crate) fn frames(&self) -> &VecDeque<FrameTimings> {
        &self.frames
    }

    /// Frames rendered since start.
    pub(crate) fn frame_index(&self) -> u64 {
        self.frame_index
    }

    /// Transient memory of the current graph with resource reuse (the viewer runs it without).
    pub(crate) fn reuse_bytes(&self) -> Option<u64> {
        self.reuse_bytes
    }

    /// Per-pass statistics over the rolling window (mean, median, min, max of GPU and CPU ms,
    /// rays per pixel, GigaRays/s), updated by every frame.
    pub(crate) fn report(&self) -> Option<&Report> {
        self.report.as_ref()
    }

    /// Whether a camera move restarts the history (an accumulating graph then converges only
    /// while the camera is still); off, the graph's own reprojection carries it across moves.
    pub(crate) fn reset_history_on_move(&self) -> bool {
        self.reset_history_on_move
    }

    /// Sets whether a camera move restarts the history.
    pub(crate) fn set_reset_history_on_move(&mut self, on: bool) {
        self.reset_history_on_move = on;
    }

    /// Frames in a row with a valid history (0 on a frame without).
    pub(crate) fn history_frames(&self) -> u64 {
        self.history_frames
    }

    /// History resets caused by camera moves since the viewer started.
    pub(crate) fn history_resets(&self) -> u64 {
        self.history_resets
    }

    /// The animation's clock; the scene is posed at its time before every frame.
    pub(crate) fn clock(&self) -> &super::clock::AnimationClock {
        &self.clock
    }

    /// Replaces the animation's clock (another clip, or a fixed step).
    pub(crate) fn set_clock(&mut self, clock: super::clock::AnimationClock) {
        self.clock = clock;
    }

    /// The animation's clock, for play, pause and speed.
    pub(crate) fn clock_mut(&mut self) -> &mut super::clock::AnimationClock {
        &mut self.clock
    }

    /// Jumps the animation to `time` seconds (wrapped into the clip).
    pub(crate) fn seek(&mut self, time: f32) {
        self.clock.seek(&self.scene, time);
    }

    /// Compiles the graph and instantiates it; an error here is fatal (there is no good plan
    /// to fall back to).
    pub fn new(gpu: &Gpu, root: &Path, graph_file: PathBuf, mode: Option<Mode>, backend: Backend, size: (u32, u32), scene: Scene) -> Result<Self, String> {
        let project = Project::beside_graph(&graph_file);
        let mut options = gpu.compile_options_for(backend);
        options.backend = backend;
        let mut s = Self {
            root: root.to_path_buf(),
            snapshot: Snapshot::take(&graph_file, &project),
            graph_file,
            mode,
            project,
            options,
            size,
            scene_bounds: crate::scene::gltf_import::animated_bounds(&scene),
            scene,
            exec: None,
            error: None,
            last_poll: Instant::now(),
            frames: VecDeque::new(),
            frame_index: 0,
            generation: 0,
            reuse_bytes: None,
            report: None,
            controls: Vec::new(),
            reset_history_on_move: true,
            last_camera: None,
            history_frames: 0,
            history_resets: 0,
            clock: super::clock::AnimationClock::at_rest(),
        };
        s.recompile(gpu).map_err(|e| e.to_string())?;
        Ok(s)
    }

    pub(crate) fn exec(&self) -> Option<&Executor> {
        self.exec.as_ref()
    }

    pub(crate) fn plan(&self) -> Option<&Plan> {
        self.exec.as_ref().map(|e| e.plan())
    }

    pub(crate) fn backend(&self) -> Backend {
        self.options.backend
    }

    /// Compiles the graph with the current options and replaces the executor; on error the
    /// previous executor stays. The viewer allocates every resource on its own (no reuse), so
    /// that any texture can be inspected after the frame; `reuse_bytes` is what the same plan
    /// takes with reuse.
    pub(crate) fn recompile(&mut self, gpu: &Gpu) -> Result<usize, String> {
        let mut options = self.options.clone();
        // Overrides of nodes or parameters the files no longer have (or that are switched
        // off) wait until they are there again, rather than failing every compile.
        self.refresh_controls();
        let controls = &self.controls;
        if !controls.is_empty() {
            options.enabled.retain(|node, _| controls.iter().any(|c| &c.node == node));
            options.params.retain(|(node, param), _| controls.iter().any(|c| &c.node == node && c.enabled && c.params.iter().any(|(p, ..)| p == param)));
        }
        self.reuse_bytes = compile_with(&self.graph_file, &self.project, self.size, &options).ok().map(|p| p.bytes_with_reuse());
        options.reuse = false;
        let result = compile_with(&self.graph_file, &self.project, self.size, &options)
            .map_err(|e| e.to_string())
            .and_then(|plan| Executor::new(gpu, plan, &self.scene).map_err(|e| e.to_string()));
        match result {
            Ok(exec) => {
                let passes = exec.plan().passes.len();
                self.exec = Some(exec);
                self.error = None;
                self.clear_frames();
                self.generation += 1;
                Ok(passes)
            }
            Err(e) => Err(e),
        }
    }

    /// Checks the watched files (at most every `interval`) and compiles again if any changed.
    pub(crate) fn poll_reload(&mut self, gpu: &Gpu, interval: std::time::Duration) -> Option<Reload> {
        if self.last_poll.elapsed() < interval {
            return None;
        }
        self.last_poll = Instant::now();
        let now = Snapshot::take(&self.graph_file, &self.project);
        if now == self.snapshot {
            return None;
        }
        self.snapshot = now;
        Some(match self.recompile(gpu) {
            Ok(passes) => Reload::Reloaded { passes },
            Err(e) => {
                // Shown until a compile succeeds.
                self.error = Some(e.clone());
                Reload::Failed(e)
            }
        })
    }

    /// Switches to one of the built-in modes' graphs.
    pub fn set_mode(&mut self, gpu: &Gpu, mode: Mode) -> Result<usize, String> {
        self.switch_graph(gpu, self.root.join(mode.graph()), Some(mode))
    }

    fn switch_graph(&mut self, gpu: &Gpu, graph_file: PathBuf, mode: Option<Mode>) -> Result<usize, String> {
        let previous = (
            std::mem::replace(&mut self.graph_file, graph_file),
            self.mode,
            self.project.clone(),
            std::mem::take(&mut self.options.params),
            std::mem::take(&mut self.options.enabled),
        );
        self.mode = mode;
        self.project = Project::beside_graph(&self.graph_file);
        match self.recompile(gpu) {
            Ok(n) => {
                self.snapshot = Snapshot::take(&self.graph_file, &self.project);
                Ok(n)
            }
            Err(e) => {
                (self.graph_file, self.mode, self.project, self.options.params, self.options.enabled) = previous;
                self.refresh_controls();
                Err(e)
            }
        }
    }

    /// Switches the traversal back-end (the same graph compiled for it).
    pub(crate) fn set_backend(&mut self, gpu: &Gpu, backend: Backend) -> Result<usize, String> {
        let previous = self.options.backend;
        self.options.backend = backend;
        self.recompile(gpu).inspect_err(|_| self.options.backend = previous)
    }

    /// Sets a parameter: in place where the executor can, else by compiling again. Kept for
    /// later compiles (hot reload, mode switches keep it only for the same graph).
    pub fn set_param(&mut self, gpu: &Gpu, node: &str, name: &str, value: ParamValue) -> Result<(), String> {
        let in_place = match self.exec.as_mut() {
            Some(exec) => exec.set_param(gpu, node, name, value)?,
            None => false,
        };
        let previous = self.options.params.insert((node.to_string(), name.to_string()), value);
        // The timings from before the change describe another workload.
        self.clear_frames();
        if in_place {
            let param = self.controls.iter_mut().filter(|c| c.node == node).flat_map(|c| c.params.iter_mut()).find(|(p, ..)| p == name);
            if let Some((_, _, v)) = param {
                *v = value;
            }
        } else if let Err(e) = self.recompile(gpu) {
            match previous {
                Some(v) => self.options.params.insert((node.to_string(), name.to_string()), v),
                None => self.options.params.remove(&(node.to_string(), name.to_string())),
            };
            self.refresh_controls();
            return Err(e);
        }
        Ok(())
    }

    /// Switches an effect (a layer node) on or off: a new plan without (or with) its passes.
    pub(crate) fn set_enabled(&mut self, gpu: &Gpu, node: &str, on: bool) -> Result<(), String> {
        let previous = self.options.enabled.insert(node.to_string(), on);
        self.recompile(gpu).map(|_| ()).inspect_err(|_| {
            match previous {
                Some(v) => self.options.enabled.insert(node.to_string(), v),
                None => self.options.enabled.remove(node),
            };
            self.refresh_controls();
        })
    }

    /// The graph file's layer nodes with their parameter declarations and values in effect
    /// (read from the files, so switched-off nodes are listed too), as of the last compile or
    /// parameter change.
    pub(crate) fn controls(&self) -> &[NodeControls] {
        &self.controls
    }

    /// Reads the graph and layer files again for [`Self::controls`].
    fn refresh_controls(&mut self) {
        self.controls = self.read_controls();
    }

    fn read_controls(&self) -> Vec<NodeControls> {
        let Ok(graph) = crate::graph::compile::parse_graph(&self.graph_file) else { return Vec::new() };
        let mut out = Vec::new();
        for (node, desc) in &graph.nodes {
            let NodeDesc::Layer(l) = desc else { continue };
            let Ok(layer) = crate::graph::compile::parse_layer(&self.project.layers_dir.join(format!("{}.ron", l.layer))) else { continue };
            let enabled = self.options.enabled.get(node).copied().unwrap_or(l.enabled);
            let params = layer
                .params
                .iter()
                .map(|(name, decl)| {
                    let value =
                        self.options.params.get(&(node.clone(), name.clone())).or_else(|| l.params.get(name)).copied().unwrap_or_else(|| decl.default_value());
                    (name.clone(), decl.clone(), value)
                })
                .collect();
            out.push(NodeControls { node: node.clone(), layer: l.layer.clone(), enabled, params });
        }
        out
    }

    /// Renders a frame with the current plan, keeps its timings and updates [`Self::report`].
    pub fn render(&mut self, gpu: &Gpu, camera: &Camera) -> Result<(), String> {
        let exec = self.exec.as_mut().ok_or("no plan")?;
        let moved = self.last_camera.is_some_and(|c| c != *camera);
        self.last_camera = Some(*camera);
        if moved && self.reset_history_on_move && exec.plan().has_history() {
            exec.camera_cut();
            self.history_resets += 1;
        }
        self.clock.tick(&self.scene);
        if self.clock.clip().is_playing() {
            self.scene.pose_for_gpu(self.clock.clip(), self.clock.time());
        }
        let t = exec.render(gpu, camera, &self.scene).map_err(|e| e.to_string())?;
        self.history_frames = if exec.history_valid() { self.history_frames + 1 } else { 0 };
        self.frame_index += 1;
        if self.frames.len() == STATS_WINDOW {
            self.frames.pop_front();
        }
        self.frames.push_back(t);
        let names: Vec<(String, &'static str)> = exec.plan().passes.iter().map(|p| (p.name.clone(), p.kind.name())).collect();
        self.report = Some(Report::new(&names, self.size.0 as u64 * self.size.1 as u64, self.frames.make_contiguous()));
        Ok(())
    }

    /// Forgets the frames of another plan or workload.
    fn clear_frames(&mut self) {
        self.frames.clear();
        self.report = None;
    }
}
