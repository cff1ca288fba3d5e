//! Renders a built-in graph into a window the program owns: the program opens the winit
//! window, the wgpu instance, surface, adapter and device itself, hands the device to raygraph
//! (`Gpu::from_wgpu`), renders a frame with an `Executor` on every redraw, copies the graph's
//! output into the window's surface texture (`runtime::present::Presenter`), and presents. A resize
//! compiles the graph again at the new size.
//!
//! `cargo run --example winit_surface -- [raster|hybrid|full-rt] [--frames N] [--resize WxH]`
//! (`--frames`: present N frames, then exit; `--resize`: after the first frame, ask for a new
//! window size, and present the last frames at it). Runs from any directory: the graph, layers
//! and shaders are built into the library.

use anyhow::{bail, Context};
use raygraph::graph::{self, Mode, Project};
use raygraph::runtime::present::Presenter;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::{LoadOptions, Scene};
use std::sync::Arc;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// The window's first size.
pub const SIZE: (u32, u32) = (480, 270);

fn main() -> anyhow::Result<()> {
    run(std::env::args().skip(1)).map(|_| ())
}

/// Opens the window and renders until it is closed or `--frames` are presented; `args` are the
/// command line's, without the program name (arguments it does not know are ignored, so that
/// a test harness's own flags pass through). Returns the number of frames presented and the
/// size of the last one.
pub fn run(args: impl Iterator<Item = String>) -> anyhow::Result<(u64, (u32, u32))> {
    let mut app = App { options: Options::parse(args)?, window: None, presented: 0, result: Ok(()) };
    EventLoop::new().context("cannot open a window")?.run_app(&mut app).context("window event loop")?;
    app.result?;
    let size = app.window.as_ref().map_or((0, 0), |w| (w.config.width, w.config.height));
    println!("presented {} frames at {}x{} ({} graph)", app.presented, size.0, size.1, app.options.mode.label());
    Ok((app.presented, size))
}

/// Frames presented while waiting for a `--resize` before giving up.
const RESIZE_PATIENCE: u64 = 500;

/// The command line.
struct Options {
    mode: Mode,
    /// Exit after presenting this many frames.
    frames: Option<u64>,
    /// The window size to ask for after the first frame.
    resize: Option<(u32, u32)>,
}

impl Options {
    fn parse(mut args: impl Iterator<Item = String>) -> anyhow::Result<Options> {
        let mut options = Options { mode: Mode::Raster, frames: None, resize: None };
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "raster" => options.mode = Mode::Raster,
                "hybrid" => options.mode = Mode::Hybrid,
                "full-rt" => options.mode = Mode::FullRt,
                "--frames" => {
                    let n = args.next().context("--frames needs a number")?;
                    options.frames = Some(n.parse().with_context(|| format!("--frames {n}: not a number"))?);
                }
                "--resize" => {
                    let size = args.next().context("--resize needs a size, WxH")?;
                    let parsed = size.split_once('x').and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)));
                    options.resize = Some(parsed.with_context(|| format!("--resize {size}: not WxH"))?);
                }
                other if other.starts_with('-') => {}
                other => bail!("unknown mode `{other}`: use raster, hybrid or full-rt"),
            }
        }
        Ok(options)
    }
}

struct App {
    options: Options,
    /// Everything that needs the window; made when the event loop resumes.
    window: Option<WindowRenderer>,
    presented: u64,
    result: anyhow::Result<()>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.result = Err(error);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        match WindowRenderer::open(event_loop, self.options.mode) {
            Ok(w) => {
                w.window.request_redraw();
                self.window = Some(w);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(w) = self.window.as_mut() else { return };
        let done = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(size) => w.resize(size),
            WindowEvent::RedrawRequested => w.draw().and_then(|presented| {
                self.presented += u64::from(presented);
                let size = (w.config.width, w.config.height);
                let resize_pending = self.options.resize.is_some_and(|wanted| wanted != size);
                if self.presented == 1 {
                    if let Some((width, height)) = self.options.resize {
                        let _ = w.window.request_inner_size(PhysicalSize::new(width, height));
                    }
                }
                if resize_pending && self.presented > RESIZE_PATIENCE {
                    bail!("the window stayed at {}x{}: the resize to {:?} never came", size.0, size.1, self.options.resize);
                }
                if self.options.frames.is_some_and(|n| self.presented >= n) && !resize_pending {
                    event_loop.exit();
                } else {
                    w.window.request_redraw();
                }
                Ok(())
            }),
            _ => Ok(()),
        };
        if let Err(e) = done {
            self.fail(event_loop, e);
        }
    }
}

/// The window with its surface, the raygraph device and the executor of the graph at the
/// window's size.
struct WindowRenderer {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    mode: Mode,
    scene: Scene,
    /// The executor, compiled for the window's size.
    exec: Executor,
    presenter: Presenter,
}

impl WindowRenderer {
    fn open(event_loop: &ActiveEventLoop, mode: Mode) -> anyhow::Result<WindowRenderer> {
        let attributes = Window::default_attributes().with_title("raygraph in a winit window").with_inner_size(PhysicalSize::new(SIZE.0, SIZE.1));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot open a window")?);
        // The program's own wgpu objects. raygraph runs on Vulkan (the `WGPU_BACKEND` variable
        // picks another, as it does for raygraph's own device).
        let mut desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(event_loop.owned_display_handle()));
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::VULKAN;
        }
        let instance = wgpu::Instance::new(desc);
        let surface = instance.create_surface(window.clone()).context("cannot draw into the window")?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions { compatible_surface: Some(&surface), ..Default::default() }))
            .context("no adapter can present to the window")?;
        // The device with what raygraph needs of it, then raygraph's view of it.
        let (device, queue) = pollster::block_on(adapter.request_device(&Gpu::device_descriptor(&adapter))).context("cannot open the device")?;
        let gpu = Gpu::from_wgpu(instance, adapter, device, queue, None)?;
        println!("adapter: {}", gpu.describe());

        // The graph's output holds display-encoded (sRGB) values: the presenter writes them through
        // a view without the sRGB conversion.
        let size = window.inner_size();
        let mut config =
            surface.get_default_config(gpu.adapter(), size.width.max(1), size.height.max(1)).context("the adapter cannot present to this window")?;
        config.view_formats = vec![config.format.remove_srgb_suffix()];
        surface.configure(gpu.device(), &config);
        let presenter = Presenter::new(&gpu, config.format);

        let textures = graph_plan(&gpu, mode, (config.width, config.height))?.scene_usage().textures;
        let (scene, _report) = raygraph::scene::open("default", &LoadOptions { textures, ..LoadOptions::default() })?;
        let exec = Executor::new(&gpu, graph_plan(&gpu, mode, (config.width, config.height))?, &scene)?;
        Ok(WindowRenderer { window, surface, config, gpu, mode, scene, exec, presenter })
    }

    /// A new size: the surface is configured again and the graph compiled at that size.
    fn resize(&mut self, size: PhysicalSize<u32>) -> anyhow::Result<()> {
        let size = (size.width.max(1), size.height.max(1));
        if size == (self.config.width, self.config.height) {
            return Ok(());
        }
        (self.config.width, self.config.height) = size;
        self.surface.configure(self.gpu.device(), &self.config);
        self.exec = Executor::new(&self.gpu, graph_plan(&self.gpu, self.mode, size)?, &self.scene)?;
        Ok(())
    }

    /// Renders a frame and presents it; `false` when the surface had no texture to give (it
    /// is configured again and the next redraw presents).
    fn draw(&mut self) -> anyhow::Result<bool> {
        let surface_texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => {
                // Outdated or lost: the window may have changed size before its `Resized`
                // event came, so configure at the size it has now.
                let size = self.window.inner_size();
                if (size.width.max(1), size.height.max(1)) == (self.config.width, self.config.height) {
                    self.surface.configure(self.gpu.device(), &self.config);
                } else {
                    self.resize(size)?;
                }
                return Ok(false);
            }
        };
        let gpu = &self.gpu;
        self.exec.render(gpu, self.scene.camera(), &self.scene)?;
        self.presenter.present(gpu, &self.exec, &surface_texture.texture)?;
        gpu.queue().present(surface_texture);
        Ok(true)
    }
}

/// The plan of `mode`'s built-in graph at `size`.
fn graph_plan(gpu: &Gpu, mode: Mode, size: (u32, u32)) -> anyhow::Result<graph::Plan> {
    let graph_file = std::path::Path::new(mode.graph());
    Ok(graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), size, &gpu.compile_options())?)
}
