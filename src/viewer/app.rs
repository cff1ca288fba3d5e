//! The viewer's window: winit event loop, wgpu surface, egui-winit input and egui-wgpu
//! drawing; each redraw runs the script's due steps, hot reload, the camera, one frame of the
//! graph, the viewport's texture and the overlay, and applies what the overlay asked for.

use super::camera::{FlyCamera, Motion, TrackState, RECORD_FPS};
use super::display::{format_of, Display, Mapping};
use super::script::{Action, Script};
use super::session::{Reload, Session};
use super::ui::{self, Frame, UiState, View};
use crate::backend::Backend;
use crate::graph::Mode;
use crate::runtime::Gpu;
use crate::scene::track::Track;
use crate::scene::{Camera, LoadOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// `raygraph view` arguments.
#[derive(Debug, Clone)]
pub struct ViewerOptions {
    /// Built-in scene name or glTF path.
    pub scene: String,
    /// A graph file; `None` uses the mode's.
    pub graph: Option<PathBuf>,
    /// The built-in mode (used without `graph`).
    pub mode: Mode,
    /// The traversal back-end (`None`: selected).
    pub backend: Option<Backend>,
    /// The GPU deadline of a frame ([`Gpu::gpu_timeout`]; `None`: the adapter's default).
    pub gpu_timeout: Option<Duration>,
    /// Render size (the window starts at this size; the image is scaled to the window).
    pub size: (u32, u32),
    /// A camera preset of the scene to start from.
    pub camera: Option<String>,
    /// Seed of the generated `atrium`.
    pub seed: u64,
    /// The glTF file's scene to draw, by index or name (`None`: the file's default).
    pub gltf_scene: Option<String>,
    /// Stop after this many frames.
    pub frames: Option<u64>,
    /// Screenshot written after the last frame (`--frames`).
    pub screenshot: Option<PathBuf>,
    /// A script of timed actions ([`crate::viewer::script`]).
    pub script: Option<PathBuf>,
    /// Print each frame's number and every reload to stdout.
    pub verbose: bool,
    /// The clip that plays, by name or index (`None`: the first, if the scene has any).
    pub animation: Option<String>,
    /// Seconds into the clip at the start.
    pub time: f32,
    /// An environment map lighting the scene in place of the sun and sky (`--env`).
    pub environment: Option<crate::scene::environment::Environment>,
}

/// Opens the window and runs until it is closed, the script quits or `--frames` is reached.
pub fn run(opts: ViewerOptions) -> Result<(), String> {
    let script = opts.script.as_deref().map(Script::load).transpose()?;
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    let mut gpu = Gpu::open(opts.backend, Some(Box::new(event_loop.owned_display_handle()))).map_err(|e| e.to_string())?;
    gpu.set_gpu_timeout(opts.gpu_timeout.unwrap_or(gpu.gpu_timeout()));
    println!("adapter: {}", gpu.describe());
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let graph_file = opts.graph.clone().unwrap_or_else(|| root.join(opts.mode.graph()));
    let (mut scene, _) =
        crate::scene::open(&opts.scene, &LoadOptions { textures: true, seed: opts.seed, gltf_scene: opts.gltf_scene.clone() }).map_err(|e| e.to_string())?;
    scene.set_environment(opts.environment.clone());
    let camera = match &opts.camera {
        Some(name) => scene.preset(name)?,
        None => *scene.camera(),
    };
    let radius = {
        let b = scene.bounds();
        (b.max - b.min).length() * 0.5
    };
    let mode = opts.graph.is_none().then_some(opts.mode);
    let backend = gpu.selection().backend;
    let choice = opts.animation.as_deref().map(|a| a.parse().unwrap_or_default()).unwrap_or_default();
    let mut clock = super::clock::AnimationClock::new(&scene, &choice, opts.time)?;
    // Scripted and counted runs advance the clock by a fixed step per frame.
    if opts.script.is_some() || opts.frames.is_some() {
        clock.set_fixed_step(Some(1.0 / 60.0));
    }
    let mut session = Session::new(&gpu, &root, graph_file, mode, backend, opts.size, scene)?;
    session.set_clock(clock);
    println!("graph: {} ({} passes), back-end {}", session.graph_file().display(), session.plan().map_or(0, |p| p.passes.len()), session.backend());
    let mut app = App {
        fly: FlyCamera::from_camera(&camera, radius),
        opts,
        script,
        gpu,
        session,
        window: None,
        motion: Motion::default(),
        looking: None,
        track: TrackState::Idle,
        view: View::Output,
        mapping: None,
        ui_state: UiState::default(),
        redraws: 0,
        last_frame: Instant::now(),
        result: Ok(()),
        exit: false,
    };
    event_loop.run_app(&mut app).map_err(|e| format!("window event loop: {e}"))?;
    if app.gpu.timed_out() {
        // The GPU is still busy with a frame past its deadline: releasing the session's GPU
        // objects could block in the driver, and the process is about to end.
        let result = app.result.clone();
        std::mem::forget(app);
        return result;
    }
    app.result
}

struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    display: Display,
    display_id: egui::TextureId,
}

struct App {
    opts: ViewerOptions,
    script: Option<Script>,
    gpu: Gpu,
    session: Session,
    window: Option<WindowState>,
    fly: FlyCamera,
    motion: Motion,
    /// Last cursor position while the right button is held.
    looking: Option<(f64, f64)>,
    track: TrackState,
    view: View,
    /// The mapping of the shown resource (range taken when it was selected).
    mapping: Option<Mapping>,
    ui_state: UiState,
    /// Redraws so far: script steps and `--frames` count these (a frame that fails still
    /// counts, so an automated run always ends).
    redraws: u64,
    last_frame: Instant,
    result: Result<(), String>,
    exit: bool,
}

impl App {
    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> Result<WindowState, String> {
        let (w, h) = self.opts.size;
        let attrs = Window::default_attributes().with_title("raygraph").with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| format!("cannot open a window: {e}"))?);
        let surface = self.gpu.instance().create_surface(window.clone()).map_err(|e| format!("cannot draw into the window: {e}"))?;
        let caps = surface.get_capabilities(self.gpu.adapter());
        // egui draws into an 8-bit gamma-space target; screenshots read these two back.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| matches!(f, wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Bgra8Unorm))
            .ok_or_else(|| format!("the window offers no Rgba8Unorm or Bgra8Unorm format (only {:?})", caps.formats))?;
        let size = window.inner_size();
        let automated = self.opts.frames.is_some() || self.script.is_some();
        let mut config =
            surface.get_default_config(self.gpu.adapter(), size.width.max(1), size.height.max(1)).ok_or("the adapter cannot present to this window")?;
        config.format = format;
        config.present_mode = if automated { wgpu::PresentMode::AutoNoVsync } else { wgpu::PresentMode::AutoVsync };
        surface.configure(self.gpu.device(), &config);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(self.gpu.device().limits().max_texture_dimension_2d as usize),
        );
        let mut renderer = egui_wgpu::Renderer::new(self.gpu.device(), format, egui_wgpu::RendererOptions::default());
        let shader =
            crate::graph::files::read(&self.session.root().join("shaders/viewer/visualize.wgsl")).map_err(|e| format!("shaders/viewer/visualize.wgsl: {e}"))?;
        let display = Display::new(&self.gpu, self.opts.size, &shader.text);
        let display_id = renderer.register_native_texture(self.gpu.device(), display.view(), wgpu::FilterMode::Linear);
        Ok(WindowState { window, surface, config, egui_ctx, egui_state, renderer, display, display_id })
    }

    fn log(&mut self, line: String) {
        println!("{line}");
        self.ui_state.status = line;
    }

    /// Applies one action (from the overlay or the script).
    fn apply(&mut self, action: Action) {
        let gpu = &self.gpu;
        let result: Result<(), String> = match action {
            Action::Mode(m) => self.session.set_mode(gpu, m.into()).map(|n| {
                self.view = View::Output;
                println!("mode: {} ({n} passes)", Mode::from(m).label());
            }),
            Action::Backend(name) => self.set_backend(&name),
            Action::Param { node, name, value } => self.session.set_param(gpu, &node, &name, value).map(|_| println!("parameter {node}.{name} = {value:?}")),
            Action::Enable { node, on } => self.session.set_enabled(gpu, &node, on).map(|_| println!("node {node}: {}", if on { "on" } else { "off" })),
            Action::ResetHistoryOnMove(on) => {
                self.session.set_reset_history_on_move(on);
                println!("reset the history when the camera moves: {}", if on { "on" } else { "off" });
                Ok(())
            }
            Action::SelectPass(pass) => self.select_pass(pass),
            Action::SelectResource(resource) => {
                self.select_resource(resource);
                Ok(())
            }
            Action::ShowOutput => {
                self.view = View::Output;
                self.mapping = None;
                Ok(())
            }
            Action::Preset(name) => self.session.scene().preset(&name).map(|c| self.fly_from(&c)),
            Action::Camera { position, target } => {
                let c = Camera { position: position.into(), target: target.into(), ..self.fly.camera() };
                self.fly_from(&c);
                Ok(())
            }
            Action::Screenshot(path) => self.screenshot(&path),
            Action::Overlay(on) => {
                self.ui_state.visible = on;
                Ok(())
            }
            Action::Record => {
                self.record();
                Ok(())
            }
            Action::SaveTrack(path) => self.save_track(&path),
            Action::PlayTrack(path) => Track::load(&path).map(|track| self.track = TrackState::Playing { track, seconds: 0.0 }).map_err(|e| e.to_string()),
            Action::Play(on) => {
                let playing = on && self.session.clock().clip().is_playing();
                self.session.clock_mut().set_playing(playing);
                println!("animation: {}", if self.session.clock().playing() { "playing" } else { "paused" });
                Ok(())
            }
            Action::Seek(t) => {
                self.session.seek(t);
                println!("animation at {:.3} s", self.session.clock().time());
                Ok(())
            }
            Action::Speed(x) if x.is_finite() && x >= 0.0 => {
                self.session.clock_mut().set_speed(x);
                println!("animation speed {x}x");
                Ok(())
            }
            Action::Speed(x) => Err(format!("animation speed {x}: give a number of at least 0")),
            Action::Clip(name) => self.set_clip(&name),
            Action::Quit => {
                self.exit = true;
                Ok(())
            }
        };
        if let Err(e) = result {
            self.log(format!("error: {e}"));
        }
    }

    /// Switches the traversal back-end, if the adapter can run it.
    fn set_backend(&mut self, name: &str) -> Result<(), String> {
        let gpu = &self.gpu;
        name.parse::<Backend>().and_then(|b| {
            if !gpu.backends().contains(&b) {
                return Err(format!("this adapter cannot run the {b} back-end"));
            }
            self.session.set_backend(gpu, b).map(|n| println!("back-end: {b} ({n} passes)"))
        })
    }

    /// Shows the first texture `pass` writes.
    fn select_pass(&mut self, pass: String) -> Result<(), String> {
        match self.session.plan().and_then(|p| ui::pass_texture(p, &pass)) {
            Some(resource) => {
                self.select(Some(pass.clone()), resource.clone());
                println!("showing {resource} (pass {pass})");
                Ok(())
            }
            None => Err(format!("no kept pass `{pass}` writing a texture")),
        }
    }

    /// Shows `resource`, keeping the pass selected (the resource may be one it writes).
    fn select_resource(&mut self, resource: String) {
        let pass = match &self.view {
            View::Resource { pass, .. } => pass.clone(),
            View::Output => None,
        };
        self.select(pass, resource.clone());
        println!("showing {resource}");
    }

    /// Flies on from camera `c`, at the speed flown so far.
    fn fly_from(&mut self, c: &Camera) {
        let speed = self.fly.speed();
        self.fly = FlyCamera::from_camera(c, 1.0).with_speed(speed);
    }

    /// Starts recording a track at the current camera.
    fn record(&mut self) {
        let mut track = Track::new(RECORD_FPS);
        track.record(0.0, &self.fly.camera());
        self.track = TrackState::Recording { track, seconds: 0.0 };
    }

    /// Stops recording and saves the track to `path`.
    fn save_track(&mut self, path: &std::path::Path) -> Result<(), String> {
        match std::mem::take(&mut self.track) {
            TrackState::Recording { mut track, seconds } => {
                // The camera where recording stopped is the last key.
                if seconds > track.duration() {
                    track.record(seconds, &self.fly.camera());
                }
                track.save(path).map(|_| println!("track saved to {} ({} keys)", path.display(), track.keys.len())).map_err(|e| e.to_string())
            }
            other => {
                self.track = other;
                Err("not recording".into())
            }
        }
    }

    /// Plays the clip `name` (by name, index or `all`), keeping the clock's fixed step.
    fn set_clip(&mut self, name: &str) -> Result<(), String> {
        crate::viewer::clock::AnimationClock::new(self.session.scene(), &name.parse().unwrap_or_default(), 0.0).map(|mut c| {
            c.set_fixed_step(self.session.clock().fixed_step());
            self.session.set_clock(c);
            println!("animation clip {name}");
        })
    }

    fn select(&mut self, pass: Option<String>, resource: String) {
        self.view = View::Resource { pass, resource };
        self.mapping = None;
    }

    /// Renders the overlay again into an offscreen texture of the window's size and format,
    /// reads it back and writes it as PNG, with the overlay's text beside it.
    fn screenshot(&mut self, path: &std::path::Path) -> Result<(), String> {
        let ws = self.window.as_mut().ok_or("no window")?;
        let gpu = &self.gpu;
        let (w, h) = (ws.config.width, ws.config.height);
        let target = gpu.device().create_texture(&wgpu::TextureDescriptor {
            label: Some("viewer screenshot"),
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: ws.config.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let frame = overlay_frame(&self.session, gpu, &self.view, &self.track);
        let text = ui::overlay_text(&frame);
        let (mut out, _) = run_overlay(ws, &frame, &mut self.ui_state, self.opts.size);
        draw_egui(gpu, ws, &mut out, &target.create_view(&Default::default()));
        let rgba = read_rgba(gpu, &target, ws.config.format)?;
        let img = image::RgbaImage::from_raw(w, h, rgba).ok_or("screenshot size")?;
        crate::runtime::exec::write_png(path, &img).map_err(|e| e.to_string())?;
        let mut txt = path.as_os_str().to_owned();
        txt.push(".overlay.txt");
        crate::util::write_atomic(std::path::Path::new(&txt), text.as_bytes()).map_err(|e| format!("{}: {e}", PathBuf::from(txt).display()))?;
        println!("screenshot: {}", path.display());
        Ok(())
    }

    /// A frame ran past the GPU deadline and the GPU is still busy with it: the window is
    /// drawn on the same queue, so nothing can be drawn any more. The viewer ends with the
    /// error (the overlay's error line, printed by `raygraph view`); the window's surface is
    /// leaked, since releasing it waits for the device to go idle.
    fn stop_after_gpu_timeout(&mut self) {
        let error = self.session.error().unwrap_or("a frame ran past the GPU deadline").to_string();
        self.result = Err(error);
        self.exit = true;
        std::mem::forget(self.window.take());
    }

    fn redraw(&mut self) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        let frame_no = self.redraws;
        self.redraws += 1;
        if let Some(script) = &self.script {
            let due: Vec<Action> = script.due(frame_no).cloned().collect();
            for a in due {
                self.apply(a);
            }
        }
        match self.session.poll_reload(&self.gpu, Duration::from_millis(200)) {
            Some(Reload::Reloaded { passes }) => {
                self.mapping = None;
                self.log(format!("reloaded {} ({passes} passes)", self.session.graph_file().display()));
            }
            Some(Reload::Failed(e)) => self.log(format!("reload failed, the last good graph keeps running: {e}")),
            None => {}
        }
        // Camera.
        let camera = match &mut self.track {
            TrackState::Playing { track, seconds } => {
                *seconds += dt;
                let c = track.camera_at(*seconds, &self.fly.camera()).fit_clip_planes(self.session.scene_bounds());
                if *seconds > track.duration() {
                    // Fly on from where the track ends.
                    self.fly_from(&c);
                    self.track = TrackState::Idle;
                }
                c
            }
            TrackState::Recording { track, seconds } => {
                self.fly.advance(&self.motion, dt);
                *seconds += dt;
                if *seconds - track.duration() >= 1.0 / RECORD_FPS {
                    track.record(*seconds, &self.fly.camera());
                }
                self.fly.camera()
            }
            TrackState::Idle => {
                self.fly.advance(&self.motion, dt);
                self.fly.camera()
            }
        };
        // Wherever the camera flies, the scene stays between its clip planes.
        let camera = camera.fit_clip_planes(self.session.scene_bounds());
        if let Err(e) = self.session.render(&self.gpu, &camera) {
            if self.session.error() != Some(e.as_str()) {
                self.log(format!("frame failed: {e}"));
            }
            self.session.set_error(Some(e));
        }
        if self.gpu.timed_out() {
            self.stop_after_gpu_timeout();
            return;
        }
        if self.opts.verbose {
            println!("frame {frame_no}");
        }
        self.draw_window();
        if self.opts.frames.is_some_and(|n| self.redraws >= n) {
            if let Some(path) = self.opts.screenshot.clone() {
                if let Err(e) = self.screenshot(&path) {
                    self.result = Err(format!("screenshot: {e}"));
                }
            }
            self.exit = true;
        }
    }

    fn draw_window(&mut self) {
        let Some(ws) = self.window.as_mut() else { return };
        let gpu = &self.gpu;
        // The viewport's texture.
        if let Some(exec) = self.session.exec() {
            let (r, mapping) = match &self.view {
                View::Output => {
                    let r = exec.plan().output;
                    (Some(r), format_of(exec, r).map(Mapping::identity))
                }
                View::Resource { resource, .. } => {
                    let r = exec.plan().resource_by_name(resource).filter(|&r| exec.plan().is_kept(r));
                    if self.mapping.is_none() {
                        self.mapping = r.and_then(|r| {
                            let format = format_of(exec, r)?;
                            exec.read_texture_f32(gpu, r).ok().map(|(_, _, texels)| Mapping::auto_range(format, &texels))
                        });
                    }
                    (r, self.mapping)
                }
            };
            match (r, mapping) {
                (Some(r), Some(m)) => {
                    if let Err(e) = ws.display.show(gpu, exec, r, &m) {
                        self.ui_state.status = format!("cannot show the texture: {e}");
                    }
                }
                _ => self.ui_state.status = "the selected texture is not in the running plan".into(),
            }
        }
        let surface_texture = match ws.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => {
                // Outdated or lost: the window may have changed size before its `Resized` event
                // came, so configure at the size it has now (the old size fails validation).
                let size = ws.window.inner_size();
                ws.config.width = size.width.max(1);
                ws.config.height = size.height.max(1);
                ws.surface.configure(gpu.device(), &ws.config);
                return;
            }
        };
        let frame = overlay_frame(&self.session, gpu, &self.view, &self.track);
        let (mut out, actions) = run_overlay(ws, &frame, &mut self.ui_state, self.opts.size);
        ws.egui_state.handle_platform_output(&ws.window, std::mem::take(&mut out.platform_output));
        let view = surface_texture.texture.create_view(&Default::default());
        draw_egui(gpu, ws, &mut out, &view);
        gpu.queue().present(surface_texture);
        for a in actions {
            self.apply(a);
        }
    }
}

/// What the overlay shows this frame.
fn overlay_frame<'a>(session: &'a Session, gpu: &'a Gpu, view: &'a View, track: &TrackState) -> Frame<'a> {
    Frame {
        session,
        gpu,
        view,
        presets: session.scene().presets(),
        recording: matches!(track, TrackState::Recording { .. }),
        playing: matches!(track, TrackState::Playing { .. }),
    }
}

/// Lays out one egui frame: the viewport and the overlay; returns it with the overlay's actions.
fn run_overlay(ws: &mut WindowState, frame: &Frame, state: &mut UiState, size: (u32, u32)) -> (egui::FullOutput, Vec<Action>) {
    let raw = ws.egui_state.take_egui_input(&ws.window);
    let display_id = ws.display_id;
    let mut actions = Vec::new();
    let out = ws.egui_ctx.run_ui(raw, |root| {
        viewport(root, display_id, size);
        let ctx = root.ctx().clone();
        actions = ui::draw(&ctx, frame, state);
    });
    (out, actions)
}

/// The viewport: the display texture scaled to fit the window, behind the overlay.
fn viewport(ui: &mut egui::Ui, id: egui::TextureId, size: (u32, u32)) {
    egui::CentralPanel::default().frame(egui::Frame::NONE).show(ui, |ui| {
        let avail = ui.available_size();
        let aspect = size.0 as f32 / size.1 as f32;
        let fit = if avail.x / avail.y > aspect { egui::vec2(avail.y * aspect, avail.y) } else { egui::vec2(avail.x, avail.x / aspect) };
        ui.centered_and_justified(|ui| ui.add(egui::Image::new(egui::load::SizedTexture::new(id, fit))));
    });
}

/// Draws an egui frame into `target`, applying (and so consuming) its texture changes.
fn draw_egui(gpu: &Gpu, ws: &mut WindowState, out: &mut egui::FullOutput, target: &wgpu::TextureView) {
    let jobs = ws.egui_ctx.tessellate(std::mem::take(&mut out.shapes), out.pixels_per_point);
    let screen = egui_wgpu::ScreenDescriptor { size_in_pixels: [ws.config.width, ws.config.height], pixels_per_point: out.pixels_per_point };
    for (id, deltas) in std::mem::take(&mut out.textures_delta.set) {
        for delta in &deltas {
            ws.renderer.update_texture(gpu.device(), gpu.queue(), id, delta);
        }
    }
    let mut encoder = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("viewer overlay") });
    let extra = ws.renderer.update_buffers(gpu.device(), gpu.queue(), &mut encoder, &jobs, &screen);
    {
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("viewer overlay"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.05, g: 0.05, b: 0.06, a: 1.0 }), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        ws.renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
    }
    gpu.queue().submit(extra.into_iter().chain([encoder.finish()]));
    for id in std::mem::take(&mut out.textures_delta.free) {
        ws.renderer.free_texture(&id);
    }
}

/// Reads a whole texture of a 4-byte RGBA or BGRA format back as opaque RGBA8 rows.
fn read_rgba(gpu: &Gpu, texture: &wgpu::Texture, format: wgpu::TextureFormat) -> Result<Vec<u8>, String> {
    let mut bytes = crate::runtime::exec::read_texture(gpu, texture, 4).map_err(|e| e.to_string())?;
    let bgra = matches!(format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    for px in bytes.chunks_exact_mut(4) {
        if bgra {
            px.swap(0, 2);
        }
        px[3] = 255;
    }
    Ok(bytes)
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        match self.open_window(event_loop) {
            Ok(ws) => {
                ws.window.request_redraw();
                self.window = Some(ws);
            }
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(ws) = self.window.as_mut() else { return };
        let consumed = ws.egui_state.on_window_event(&ws.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => self.exit = true,
            WindowEvent::Resized(size) => {
                ws.config.width = size.width.max(1);
                ws.config.height = size.height.max(1);
                ws.surface.configure(self.gpu.device(), &ws.config);
            }
            WindowEvent::RedrawRequested => {
                self.redraw();
                if let Some(ws) = &self.window {
                    ws.window.request_redraw();
                }
            }
            WindowEvent::Focused(false) => self.motion = Motion::default(),
            // Releases always count, so that a key held while the overlay takes the focus
            // does not stick.
            WindowEvent::KeyboardInput { event, .. } if !consumed || event.state == ElementState::Released => {
                let down = event.state == ElementState::Pressed;
                if let PhysicalKey::Code(code) = event.physical_key {
                    let m = &mut self.motion;
                    match code {
                        KeyCode::KeyW => m.forward = down,
                        KeyCode::KeyS => m.back = down,
                        KeyCode::KeyA => m.left = down,
                        KeyCode::KeyD => m.right = down,
                        KeyCode::KeyE => m.up = down,
                        KeyCode::KeyQ => m.down = down,
                        KeyCode::ShiftLeft | KeyCode::ShiftRight => m.fast = down,
                        KeyCode::F1 if down => self.ui_state.visible = !self.ui_state.visible,
                        KeyCode::Escape if down => self.exit = true,
                        _ => {}
                    }
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Right, .. } => {
                self.looking = (state == ElementState::Pressed).then_some((f64::NAN, f64::NAN))
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.looking {
                    if x.is_finite() {
                        self.fly.look((position.x - x) as f32, (position.y - y) as f32);
                    }
                    self.looking = Some((position.x, position.y));
                }
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.fly.scale_speed(notches);
            }
            _ => {}
        }
        if self.exit {
            event_loop.exit();
        }
    }
}
