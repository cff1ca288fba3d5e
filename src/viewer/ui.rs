//! The egui overlay: mode, back-end, camera and track controls; the parameters panel made from
//! the layer files' declarations; the profiler (per-pass GPU and CPU ms over a rolling
//! window, rays per pixel and GigaRays/s, acceleration-structure builds, transient memory,
//! adapter and back-end, a frame-time history); the compiled graph drawn as a graph; and the
//! last error. Everything the user does comes back as [`Action`]s, the same ones a script
//! runs.

use super::script::{Action, ScriptMode};
use super::session::Session;
use crate::graph::compile::{fmt_bytes, Plan};
use crate::graph::desc::{ParamDecl, ParamValue, ResourceDecl};
use crate::graph::Mode;
use crate::runtime::profiler::FramePhases;
use crate::runtime::Gpu;
use egui::{Color32, RichText};
use std::fmt::Write;

/// What the viewport shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum View {
    /// The graph's output.
    #[default]
    Output,
    /// A texture of the plan.
    Resource {
        /// The pass that writes it, when one was selected.
        pass: Option<String>,
        /// The resource's name.
        resource: String,
    },
}

/// State of the overlay's own widgets.
#[derive(Debug)]
pub struct UiState {
    pub(crate) visible: bool,
    pub(crate) track_path: String,
    pub(crate) status: String,
}

impl Default for UiState {
    fn default() -> Self {
        Self { visible: true, track_path: "track.ron".into(), status: String::new() }
    }
}

/// Everything the overlay shows about the current frame.
pub struct Frame<'a> {
    pub(crate) session: &'a Session,
    pub(crate) gpu: &'a Gpu,
    pub(crate) view: &'a View,
    pub(crate) presets: &'a [(String, crate::scene::Camera)],
    pub(crate) recording: bool,
    pub(crate) playing: bool,
}

fn script_mode(m: Mode) -> ScriptMode {
    match m {
        Mode::Raster => ScriptMode::Raster,
        Mode::Hybrid => ScriptMode::Hybrid,
        Mode::FullRt => ScriptMode::FullRt,
    }
}

/// The first texture a pass writes (what clicking it shows).
pub(crate) fn pass_texture(plan: &Plan, pass: &str) -> Option<String> {
    let p = plan.passes.iter().find(|p| p.name == pass)?;
    p.writes.iter().map(|(_, r)| &plan.resources[*r]).find(|r| matches!(r.decl, ResourceDecl::Texture(_))).map(|r| r.name.clone())
}

/// One line per pass of the profiler: name, kind, GPU ms (mean / median / min / max), CPU ms,
/// rays per pixel, GigaRays/s.
pub(crate) fn pass_rows(f: &Frame) -> Vec<(String, String, Option<f64>)> {
    let Some(report) = f.session.report() else { return Vec::new() };
    report
        .passes
        .iter()
        .map(|p| {
            let mut s = String::new();
            match &p.gpu_ms {
                Some(g) => {
                    let _ = write!(s, "GPU {:.3} ms (mean {:.3}, min {:.3}, max {:.3})", g.median, g.mean, g.min, g.max);
                }
                None => s.push_str("GPU n/a"),
            }
            if let Some(c) = &p.cpu_ms {
                let _ = write!(s, "  CPU {:.3} ms", c.median);
            }
            if let Some(r) = p.rays_per_pixel {
                let _ = write!(s, "  {r:.2} rays/px");
            }
            if let Some(g) = p.grays_per_s {
                let _ = write!(s, "  {g:.3} GR/s");
            }
            (p.name.clone(), s, p.gpu_ms.as_ref().map(|g| g.median))
        })
        .collect()
}

/// The overlay as text (written beside screenshots, so an automated run can check what the
/// overlay showed).
pub(crate) fn overlay_text(f: &Frame) -> String {
    let mut s = String::new();
    let session = f.session;
    let _ = writeln!(s, "adapter: {}", f.gpu.describe());
    let _ = writeln!(s, "back-end: {}", session.backend());
    let _ = writeln!(s, "graph: {}", session.graph_file().display());
    let _ = writeln!(s, "mode: {}", session.mode().map(|m| m.label()).unwrap_or("custom graph"));
    let _ = writeln!(
        s,
        "view: {}",
        match f.view {
            View::Output => "output".to_string(),
            View::Resource { resource, .. } => resource.clone(),
        }
    );
    let _ = writeln!(s, "frame: {}", session.frame_index());
    if let Some(plan) = session.plan() {
        let _ = writeln!(s, "passes:");
        for (name, line, _) in pass_rows(f) {
            let _ = writeln!(s, "  {name}: {line}");
        }
        let _ = writeln!(s, "culled: {}", if plan.culled.is_empty() { "none".into() } else { plan.culled.join(", ") });
        let controls = session.controls();
        let _ = writeln!(s, "parameters:");
        for c in controls.iter().filter(|c| c.enabled) {
            for (name, _, value) in &c.params {
                let v = match value {
                    ParamValue::Float(x) => format!("{x}"),
                    ParamValue::Int(x) => format!("{x}"),
                    ParamValue::Bool(x) => format!("{x}"),
                };
                let _ = writeln!(s, "  {}.{name} = {v}", c.node);
            }
        }
        let off: Vec<&str> = controls.iter().filter(|c| !c.enabled).map(|c| c.node.as_str()).collect();
        let _ = writeln!(s, "switched off: {}", if off.is_empty() { "none".into() } else { off.join(", ") });
        let _ = writeln!(s, "transient memory: {}", memory(session, plan));
        if let Some(line) = history_line(session, plan) {
            let _ = writeln!(s, "{line}");
        }
    }
    if let Some(line) = session.clock().describe(session.scene()) {
        let _ = writeln!(s, "{line}");
    }
    if let Some(a) = session.frames().back().and_then(|t| t.accel.as_ref()) {
        let _ = writeln!(s, "acceleration structures this frame: {}", a.describe());
    }
    if let Some(e) = &session.error() {
        let _ = writeln!(s, "error: {e}");
    }
    s
}

/// Play/pause, the time slider (scrubbing), the speed and the clip, for a scene with clips.
fn animation_controls(ui: &mut egui::Ui, session: &Session, actions: &mut Vec<Action>) {
    let (Some(line), Some(rig)) = (session.clock().describe(session.scene()), session.scene().rig()) else { return };
    ui.label(line);
    ui.horizontal(|ui| {
        let clock = session.clock();
        if ui.button(if clock.playing() { "pause" } else { "play" }).clicked() {
            actions.push(Action::Play(!clock.playing()));
        }
        let mut t = clock.time();
        if ui.add(egui::Slider::new(&mut t, 0.0..=clock.duration(session.scene())).text("s")).changed() {
            actions.push(Action::Seek(t));
        }
        let mut speed = clock.speed();
        if ui.add(egui::Slider::new(&mut speed, 0.0..=4.0).text("speed")).changed() {
            actions.push(Action::Speed(speed));
        }
    });
    if rig.animations.len() > 1 {
        ui.horizontal(|ui| {
            for (i, a) in rig.animations.iter().enumerate() {
                if ui.selectable_label(session.clock().clip() == crate::scene::animation::ClipSet::One(i), &a.name).clicked() {
                    actions.push(Action::Clip(i.to_string()));
                }
            }
            if ui.selectable_label(session.clock().clip() == crate::scene::animation::ClipSet::All, "all").clicked() {
                actions.push(Action::Clip("all".into()));
            }
        });
    }
}

/// The state of the plan's history resources, if it has any: how many frames it has been valid
/// for, and how often a camera move reset it.
fn history_line(session: &Session, plan: &crate::graph::compile::Plan) -> Option<String> {
    plan.has_history().then(|| {
        format!(
            "history: valid for {} frames; reset by camera moves {} times ({})",
            session.history_frames(),
            session.history_resets(),
            if session.reset_history_on_move() { "resets when the camera moves" } else { "kept across camera moves" }
        )
    })
}

/// The plan's transient memory: the viewer allocates each resource on its own so that any
/// texture can be inspected after the frame.
fn memory(session: &Session, plan: &Plan) -> String {
    let with = session.reuse_bytes().map(fmt_bytes).unwrap_or_else(|| "?".into());
    format!("{with} with reuse, {} without (the viewer's allocation)", fmt_bytes(plan.bytes_without_reuse()))
}

/// Draws the overlay; returns what the user asked for.
pub fn draw(ctx: &egui::Context, f: &Frame, state: &mut UiState) -> Vec<Action> {
    let mut actions = Vec::new();
    if !state.visible {
        return actions;
    }
    controls_window(ctx, f, state, &mut actions);
    profiler_window(ctx, f, &mut actions);
    parameters_window(ctx, f, &mut actions);
    graph_window(ctx, f, &mut actions);
    if let Some(e) = f.session.error() {
        egui::Window::new("Error").anchor(egui::Align2::LEFT_BOTTOM, [12.0, -12.0]).default_width(620.0).show(ctx, |ui| {
            ui.label(RichText::new(e).color(Color32::from_rgb(255, 110, 110)).monospace());
            ui.label("The last graph that compiled keeps running; saving a fixed file reloads it.");
        });
    }
    actions
}

fn controls_window(ctx: &egui::Context, f: &Frame, state: &mut UiState, actions: &mut Vec<Action>) {
    egui::Window::new("raygraph").default_pos([16.0, 16.0]).show(ctx, |ui| {
        ui.horizontal(|ui| {
            ui.label("mode");
            for m in Mode::ALL {
                if ui.selectable_label(f.session.mode() == Some(m), m.label()).clicked() && f.session.mode() != Some(m) {
                    actions.push(Action::Mode(script_mode(m)));
                }
            }
        });
        ui.horizontal(|ui| {
            ui.label("back-end");
            for b in f.gpu.backends() {
                if ui.selectable_label(f.session.backend() == *b, b.to_string()).clicked() && f.session.backend() != *b {
                    actions.push(Action::Backend(b.to_string()));
                }
            }
        });
        ui.horizontal(|ui| {
            ui.label("camera");
            for (p, _) in f.presets {
                if ui.button(p).clicked() {
                    actions.push(Action::Preset(p.clone()));
                }
            }
        });
        ui.horizontal(|ui| {
            ui.label("track");
            ui.text_edit_singleline(&mut state.track_path);
        });
        ui.horizontal(|ui| {
            if f.recording {
                if ui.button("stop and save").clicked() {
                    actions.push(Action::SaveTrack(state.track_path.clone().into()));
                }
            } else if ui.button("record").clicked() {
                actions.push(Action::Record);
            }
            if ui.add_enabled(!f.playing && !f.recording, egui::Button::new("play")).clicked() {
                actions.push(Action::PlayTrack(state.track_path.clone().into()));
            }
            if ui.button("screenshot").clicked() {
                actions.push(Action::Screenshot(format!("raygraph-{}.png", f.session.frame_index()).into()));
            }
        });
        ui.label("WASD fly, Q/E down/up, Shift fast, right mouse button look, wheel speed, F1 overlay");
        if !state.status.is_empty() {
            ui.label(&state.status);
        }
    });
}

fn profiler_window(ctx: &egui::Context, f: &Frame, actions: &mut Vec<Action>) {
    let session = f.session;
    egui::Window::new("Profiler").default_pos([16.0, 210.0]).show(ctx, |ui| {
        let rows = pass_rows(f);
        profiler_totals(ui, f, &rows);
        let selected = match f.view {
            View::Resource { pass, .. } => pass.clone(),
            View::Output => None,
        };
        pass_table(ui, f, &rows, selected.as_deref(), actions);
        pass_textures(ui, f, selected.as_deref(), actions);
        if let Some(plan) = session.plan() {
            ui.label(format!("culled: {}", if plan.culled.is_empty() { "none".into() } else { plan.culled.join(", ") }));
            ui.label(format!("transient memory: {}", memory(session, plan)));
            if let Some(line) = history_line(session, plan) {
                ui.label(line);
                let mut on = session.reset_history_on_move();
                if ui.checkbox(&mut on, "reset the history when the camera moves").changed() {
                    actions.push(Action::ResetHistoryOnMove(on));
                }
            }
        }
        animation_controls(ui, session, actions);
        let builds = session.frames().back().and_then(|t| t.accel.as_ref()).map(|a| a.describe()).unwrap_or_else(|| "no acceleration structure".into());
        ui.label(format!("acceleration structures this frame: {builds}"));
        frame_time_history(ui, session);
    });
}

/// The profiler's head: adapter, back-end and graph file, the passes' GPU total and the frame's
/// wall time, and the frame's time outside the passes.
fn profiler_totals(ui: &mut egui::Ui, f: &Frame, rows: &[(String, String, Option<f64>)]) {
    let session = f.session;
    ui.label(f.gpu.describe());
    ui.label(format!("back-end {}  |  {}", session.backend(), session.graph_file().file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()));
    let total: f64 = rows.iter().filter_map(|r| r.2).sum();
    let wall = session.frames().back().map(|t| t.frame_ms).unwrap_or(0.0);
    ui.label(format!("GPU {total:.3} ms (passes, median of {} frames)  |  frame {wall:.2} ms wall", session.frames().len()));
    let frames: Vec<_> = session.frames().iter().cloned().collect();
    ui.label(RichText::new(format!("outside the passes: {}", FramePhases::describe_frames(&frames))).small());
}

/// The table of passes: a name to click (showing its output), a bar of its GPU time against the
/// slowest pass's, and its times and rays.
fn pass_table(ui: &mut egui::Ui, f: &Frame, rows: &[(String, String, Option<f64>)], selected: Option<&str>, actions: &mut Vec<Action>) {
    let max = rows.iter().filter_map(|r| r.2).fold(0.0f64, f64::max).max(1e-9);
    let report = &f.session.report();
    egui::Grid::new("passes").striped(true).show(ui, |ui| {
        for h in ["pass (click: show its output)", "GPU ms", "median", "mean", "min", "max", "CPU ms", "rays/px", "GR/s"] {
            ui.label(RichText::new(h).small());
        }
        ui.end_row();
        let cell = |ui: &mut egui::Ui, v: Option<f64>, digits: usize| {
            ui.label(RichText::new(v.map(|v| format!("{v:.digits$}")).unwrap_or_default()).monospace().size(11.0))
        };
        for (i, (name, _, gpu)) in rows.iter().enumerate() {
            if ui.selectable_label(selected == Some(name), name).clicked() {
                actions.push(Action::SelectPass(name.clone()));
            }
            let frac = (gpu.unwrap_or(0.0) / max) as f32;
            let (rect, _) = ui.allocate_exact_size(egui::vec2(90.0, 10.0), egui::Sense::hover());
            ui.painter().rect_filled(egui::Rect::from_min_size(rect.min, egui::vec2(90.0 * frac, 10.0)), 2.0, Color32::from_rgb(90, 170, 255));
            let p = report.as_ref().and_then(|r| r.passes.get(i));
            let g = p.and_then(|p| p.gpu_ms.as_ref());
            cell(ui, g.map(|g| g.median), 3);
            cell(ui, g.map(|g| g.mean), 3);
            cell(ui, g.map(|g| g.min), 3);
            cell(ui, g.map(|g| g.max), 3);
            cell(ui, p.and_then(|p| p.cpu_ms.as_ref()).map(|c| c.median), 3);
            cell(ui, p.and_then(|p| p.rays_per_pixel), 2);
            cell(ui, p.and_then(|p| p.grays_per_s), 3);
            ui.end_row();
        }
    });
}

/// `output`, then every texture the selected pass writes (a G-buffer pass has several) and the
/// history textures it reads, each shown when clicked.
fn pass_textures(ui: &mut egui::Ui, f: &Frame, selected: Option<&str>, actions: &mut Vec<Action>) {
    ui.horizontal_wrapped(|ui| {
        if ui.selectable_label(matches!(f.view, View::Output), "output").clicked() {
            actions.push(Action::ShowOutput);
        }
        let Some(plan) = f.session.plan() else { return };
        let Some(pass) = selected.and_then(|s| plan.passes.iter().find(|p| p.name == s)) else { return };
        let histories = pass.reads.iter().filter(|(_, r)| plan.resources[*r].history_of.is_some());
        for (_, r) in pass.writes.iter().chain(histories) {
            let res = &plan.resources[*r];
            if matches!(res.decl, ResourceDecl::Texture(_)) {
                let shown = matches!(f.view, View::Resource { resource, .. } if *resource == res.name);
                if ui.selectable_label(shown, &res.name).clicked() {
                    actions.push(Action::SelectResource(res.name.clone()));
                }
            }
        }
    });
}

/// Frame-time history: GPU total per frame over the window, as a line under its peak.
fn frame_time_history(ui: &mut egui::Ui, session: &Session) {
    let history: Vec<f64> = session.frames().iter().map(|t| t.gpu_ms.as_ref().map(|g| g.iter().sum()).unwrap_or(t.frame_ms)).collect();
    let peak = history.iter().copied().fold(1e-9f64, f64::max);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(360.0, 50.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, Color32::from_black_alpha(120));
    let n = super::session::STATS_WINDOW as f32;
    let points: Vec<egui::Pos2> = history
        .iter()
        .enumerate()
        .map(|(i, ms)| egui::pos2(rect.left() + rect.width() * i as f32 / n, rect.bottom() - rect.height() * (*ms / peak) as f32))
        .collect();
    ui.painter().add(egui::Shape::line(points, egui::Stroke::new(1.5, Color32::from_rgb(120, 220, 120))));
    ui.label(format!("frame GPU time, last {} frames (peak {peak:.2} ms)", history.len()));
}

fn parameters_window(ctx: &egui::Context, f: &Frame, actions: &mut Vec<Action>) {
    egui::Window::new("Parameters").anchor(egui::Align2::RIGHT_TOP, [-12.0, 12.0]).default_width(300.0).show(ctx, |ui| {
        egui::ScrollArea::vertical().max_height(420.0).show(ui, |ui| {
            for c in f.session.controls() {
                let mut on = c.enabled;
                if ui.checkbox(&mut on, RichText::new(format!("{} ({})", c.node, c.layer)).strong()).changed() {
                    actions.push(Action::Enable { node: c.node.clone(), on });
                }
                if !c.enabled {
                    continue;
                }
                for (name, decl, value) in &c.params {
                    let set = |v: ParamValue| Action::Param { node: c.node.clone(), name: name.clone(), value: v };
                    ui.horizontal(|ui| {
                        ui.add_space(16.0);
                        match (decl, *value) {
                            (ParamDecl::Float { min, max, .. }, ParamValue::Float(v)) => {
                                let mut x = v;
                                let r = ui.add(egui::Slider::new(&mut x, *min..=*max).text(name).logarithmic(*max > 100.0 * min.abs().max(1.0)));
                                if r.changed() {
                                    actions.push(set(ParamValue::Float(x)));
                                }
                            }
                            (ParamDecl::Int { min, max, .. }, ParamValue::Int(v)) => {
                                let mut x = v;
                                let r = ui.add(
                                    egui::Slider::new(&mut x, *min..=*max).text(name).logarithmic(*max > min.saturating_abs().max(1).saturating_mul(1000)),
                                );
                                if r.changed() {
                                    actions.push(set(ParamValue::Int(x)));
                                }
                            }
                            (ParamDecl::Bool { .. }, ParamValue::Bool(v)) => {
                                let mut x = v;
                                if ui.checkbox(&mut x, name).changed() {
                                    actions.push(set(ParamValue::Bool(x)));
                                }
                            }
                            (ParamDecl::Enum { values, .. }, ParamValue::Int(v)) => {
                                let mut x = v as usize;
                                egui::ComboBox::from_id_salt((&c.node, name)).selected_text(values.get(x).cloned().unwrap_or_default()).show_ui(ui, |ui| {
                                    for (i, label) in values.iter().enumerate() {
                                        ui.selectable_value(&mut x, i, label);
                                    }
                                });
                                ui.label(name);
                                if x as i64 != v {
                                    actions.push(set(ParamValue::Int(x as i64)));
                                }
                            }
                            _ => {
                                ui.label(format!("{name}: {value:?}"));
                            }
                        }
                    });
                }
            }
        });
    });
}

/// Passes as boxes in columns by dependency depth, an arrow per resource a pass reads from
/// another, a dashed one from the writer of a resource to each pass that reads it as a history
/// on the next frame; culled passes listed under them.
fn graph_window(ctx: &egui::Context, f: &Frame, actions: &mut Vec<Action>) {
    let Some(plan) = f.session.plan() else { return };
    egui::Window::new("Graph").anchor(egui::Align2::RIGHT_BOTTOM, [-12.0, -12.0]).default_open(false).show(ctx, |ui| {
        let layout = GraphLayout::new(ui, plan);
        let responses: Vec<egui::Response> =
            (0..plan.passes.len()).map(|i| ui.interact(layout.at(i), ui.scope_id().with(("pass", i)), egui::Sense::click())).collect();
        let hovered = responses.iter().position(|r| r.hovered());
        let painter = ui.painter();
        layout.draw_reads(painter, plan, hovered);
        layout.draw_history_reads(painter, plan, hovered);
        for (i, (p, resp)) in plan.passes.iter().zip(&responses).enumerate() {
            let r = layout.at(i);
            painter.rect_filled(r, 4.0, if resp.hovered() { Color32::from_rgb(60, 90, 140) } else { Color32::from_rgb(40, 60, 95) });
            painter.text(r.center(), egui::Align2::CENTER_CENTER, format!("{}\n{}", p.name, p.kind.name()), egui::FontId::proportional(11.0), Color32::WHITE);
            if resp.clicked() {
                actions.push(Action::SelectPass(p.name.clone()));
            }
        }
        if let Some(i) = hovered {
            let names = |list: &[(String, usize)]| list.iter().map(|(_, r)| plan.resources[*r].name.clone()).collect::<Vec<_>>().join(", ");
            let p = &plan.passes[i];
            responses[i].clone().on_hover_text(format!("{} ({})\nreads: {}\nwrites: {}", p.name, p.shader.path.display(), names(&p.reads), names(&p.writes)));
        }
        ui.label(format!(
            "{} passes, {} resources ({} allocated in {} slots); culled: {}",
            plan.passes.len(),
            plan.resources.len(),
            plan.resources.iter().filter(|r| r.slot.is_some()).count(),
            plan.slots.len(),
            if plan.culled.is_empty() { "none".into() } else { plan.culled.join(", ") }
        ));
    });
}

/// Width and height of a pass's box in the graph window, and the gaps between columns and rows.
const BOX_W: f32 = 150.0;
const BOX_H: f32 = 34.0;
const GAP_X: f32 = 40.0;
const GAP_Y: f32 = 14.0;

/// The pass that writes resource `r`.
fn producer(plan: &Plan, r: usize) -> Option<usize> {
    plan.passes.iter().position(|p| p.writes.iter().any(|(_, w)| *w == r))
}

/// Where the graph window draws each pass: a column per dependency depth, the passes of a depth
/// one under the other.
struct GraphLayout {
    /// The area taken in the window.
    rect: egui::Rect,
    /// (column, row) of each pass.
    slots: Vec<(usize, usize)>,
}

impl GraphLayout {
    /// Lays out the plan's passes and takes the space they need from `ui`.
    fn new(ui: &mut egui::Ui, plan: &Plan) -> Self {
        let mut depth = vec![0usize; plan.passes.len()];
        for (i, p) in plan.passes.iter().enumerate() {
            depth[i] = p.reads.iter().filter_map(|(_, r)| producer(plan, *r)).filter(|&j| j < i).map(|j| depth[j] + 1).max().unwrap_or(0);
        }
        let columns = depth.iter().max().map_or(1, |d| d + 1);
        let mut rows = vec![0usize; columns];
        let slots: Vec<(usize, usize)> = depth
            .iter()
            .map(|&d| {
                rows[d] += 1;
                (d, rows[d] - 1)
            })
            .collect();
        let height = rows.iter().max().copied().unwrap_or(1) as f32 * (BOX_H + GAP_Y);
        let (rect, _) = ui.allocate_exact_size(egui::vec2(columns as f32 * (BOX_W + GAP_X), height), egui::Sense::hover());
        Self { rect, slots }
    }

    /// The box of pass `i`.
    fn at(&self, i: usize) -> egui::Rect {
        let (c, r) = self.slots[i];
        egui::Rect::from_min_size(self.rect.min + egui::vec2(c as f32 * (BOX_W + GAP_X), r as f32 * (BOX_H + GAP_Y)), egui::vec2(BOX_W, BOX_H))
    }

    /// One arrow per resource a pass reads from another pass; the hovered pass's edges are
    /// highlighted and named.
    fn draw_reads(&self, painter: &egui::Painter, plan: &Plan, hovered: Option<usize>) {
        for (i, p) in plan.passes.iter().enumerate() {
            for (_, r) in &p.reads {
                if let Some(j) = producer(plan, *r).filter(|&j| j != i) {
                    let (a, b) = (self.at(j).right_center(), self.at(i).left_center());
                    let lit = hovered == Some(i) || hovered == Some(j);
                    let color = if lit { Color32::from_rgb(255, 200, 90) } else { Color32::GRAY };
                    painter.arrow(a, b - a, egui::Stroke::new(if lit { 2.0 } else { 1.0 }, color));
                    if lit {
                        painter.text(a + (b - a) * 0.5, egui::Align2::CENTER_BOTTOM, &plan.resources[*r].name, egui::FontId::proportional(10.0), color);
                    }
                }
            }
        }
    }

    /// History reads: from this frame's writer of the kept resource to the reader, dashed.
    fn draw_history_reads(&self, painter: &egui::Painter, plan: &Plan, hovered: Option<usize>) {
        for (i, p) in plan.passes.iter().enumerate() {
            for (_, r) in &p.reads {
                let Some(j) = plan.resources[*r].history_of.and_then(|h| producer(plan, h)) else { continue };
                let (a, b) = (self.at(j).center_bottom(), self.at(i).center_bottom());
                let lit = hovered == Some(i) || hovered == Some(j);
                let color = if lit { Color32::from_rgb(140, 220, 255) } else { Color32::from_rgb(110, 150, 170) };
                let below = egui::vec2(0.0, BOX_H * 0.4 + GAP_Y * 0.3);
                let path = [a, a + below, b + below, b];
                painter.extend(egui::Shape::dashed_line(&path, egui::Stroke::new(if lit { 2.0 } else { 1.0 }, color), 5.0, 3.0));
                painter.text(
                    a + below + (b - a) * 0.5,
                    egui::Align2::CENTER_TOP,
                    format!("{} (next frame)", plan.resources[*r].name),
                    egui::FontId::proportional(10.0),
                    color,
                );
            }
        }
    }
}
