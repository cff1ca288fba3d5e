//! raygraph in a browser: the library's compiler and executor on WebGPU, with the `compute`
//! traversal back-end (browsers have no ray queries), drawing into a canvas. Each frame's
//! output is read back and put into the canvas's 2D context: a WebGPU canvas context (a swap
//! chain) is not available everywhere WebGPU compute is (headless Chromium on SwiftShader loses
//! the device when it makes one), and a 2D canvas is. The page
//! (`web/index.html`, `web/app.js`) drives an [`App`]: one frame per animation frame, the mode,
//! the scene (built-in, or a glTF/GLB from the file picker), the fly camera, and the profiler
//! panel from each frame's timings.
//!
//! The page calls into an `App` between frames only: input (mode, scene, camera) goes to an
//! inbox that the next frame applies, so a frame in flight (which awaits the GPU) never sees
//! its state change under it.

mod log_lines;

use raygraph::graph::{self, Mode, Project};
use raygraph::runtime::profiler::FrameTimings;
use raygraph::runtime::{Executor, Gpu};
use raygraph::scene::fly::{FlyCamera, Motion};
use raygraph::scene::{self, LoadOptions, Scene};
use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// The mode a page names: `raster`, `hybrid` or `rt`.
fn parse_mode(name: &str) -> Result<Mode, String> {
    match name {
        "raster" => Ok(Mode::Raster),
        "hybrid" => Ok(Mode::Hybrid),
        "rt" | "full-rt" => Ok(Mode::FullRt),
        other => Err(format!("unknown mode `{other}`: use raster, hybrid or rt")),
    }
}

/// What the page asked for since the last frame.
#[derive(Default)]
struct Inbox {
    mode: Option<Mode>,
    /// A scene already loaded (on the CPU), and its name.
    scene: Option<(String, Scene)>,
    /// Mouse movement to turn the camera by, pixels.
    look: (f32, f32),
    /// Wheel notches.
    speed_notches: f32,
    keys: Motion,
    /// The profiler panel of the last frame (JSON).
    profile: String,
}

/// The GPU, the canvas and the running graph.
struct Renderer {
    gpu: Gpu,
    canvas: web_sys::CanvasRenderingContext2d,
    size: (u32, u32),
    mode: Mode,
    scene_name: String,
    scene: Scene,
    /// `None` until the first camera input: the scene's own camera, exactly.
    fly: Option<FlyCamera>,
    exec: Executor,
    last_frame: Option<f64>,
    frames: u64,
    /// Seconds of the scene's animation clock (animated scenes play their first clip).
    clock: f32,
}

/// The page's handle on raygraph.
#[wasm_bindgen]
pub struct App {
    renderer: Rc<RefCell<Renderer>>,
    inbox: Rc<RefCell<Inbox>>,
    info: String,
}

fn js_error(e: impl std::fmt::Display) -> JsValue {
    JsValue::from_str(&e.to_string())
}

/// Opens the browser's WebGPU adapter and device with what raygraph asks of a device (its
/// features where the adapter has them, the adapter's limits where WebGPU's defaults are too
/// low).
async fn open_gpu() -> Result<Gpu, String> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::BROWSER_WEBGPU;
    let instance = wgpu::Instance::new(desc);
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions::default())
        .await
        .map_err(|e| format!("this browser gives no WebGPU adapter ({e}); raygraph needs WebGPU"))?;
    let (device, queue) = adapter.request_device(&Gpu::device_descriptor(&adapter)).await.map_err(|e| format!("cannot open the WebGPU device: {e}"))?;
    Gpu::from_wgpu(instance, adapter, device, queue, None).map_err(|e| e.to_string())
}

/// The plan of `mode`'s built-in graph at `size`.
fn plan(gpu: &Gpu, mode: Mode, size: (u32, u32)) -> Result<graph::Plan, String> {
    let graph_file = Path::new(mode.graph());
    graph::compile::compile_with(graph_file, &Project::beside_graph(graph_file), size, &gpu.compile_options()).map_err(|e| e.to_string())
}

/// Opens a built-in scene, with its textures: the mode can change under it (only what the
/// graph reads is uploaded).
fn builtin_scene(name: &str) -> Result<Scene, String> {
    scene::open(name, &LoadOptions::default()).map(|(scene, _)| scene).map_err(|e| e.to_string())
}

impl Renderer {
    /// The executor for the current mode, scene and canvas size (its errors name the scene).
    fn executor(&self, mode: Mode, scene: &Scene) -> Result<Executor, String> {
        let plan = plan(&self.gpu, mode, self.size)?;
        Executor::new(&self.gpu, plan, scene).map_err(|e| format!("{}: {e}", scene.name()))
    }

    /// Applies the page's input: a new mode or scene gets a new executor (on failure the old
    /// one stays and the error is returned); camera input moves the fly camera.
    fn apply(&mut self, inbox: &mut Inbox, dt: f32) -> Result<(), String> {
        if let Some((name, scene)) = inbox.scene.take() {
            self.exec = self.executor(self.mode, &scene)?;
            (self.scene_name, self.scene, self.fly, self.clock) = (name, scene, None, 0.0);
        }
        if self.scene.rig().is_some() {
            self.clock += dt;
            self.scene.pose_for_gpu(None, self.clock);
        }
        if let Some(mode) = inbox.mode.take().filter(|m| *m != self.mode) {
            self.exec = self.executor(mode, &self.scene)?;
            self.mode = mode;
        }
        let moved = inbox.look != (0.0, 0.0)
            || inbox.speed_notches != 0.0
            || [inbox.keys.forward, inbox.keys.back, inbox.keys.left, inbox.keys.right, inbox.keys.up, inbox.keys.down].contains(&true);
        if moved {
            let radius = self.scene.bounds().diagonal() * 0.5;
            let fly = self.fly.get_or_insert_with(|| FlyCamera::from_camera(self.scene.camera(), radius));
            fly.look(inbox.look.0, inbox.look.1);
            fly.scale_speed(inbox.speed_notches);
            fly.advance(&inbox.keys, dt);
            (inbox.look, inbox.speed_notches) = ((0.0, 0.0), 0.0);
        }
        Ok(())
    }

    /// Renders one frame into the canvas; returns its timings.
    async fn frame(&mut self) -> Result<FrameTimings, String> {
        let camera = self.fly.map_or(*self.scene.camera(), |f| f.camera());
        let timings = self.exec.render_async(&self.gpu, &camera, &self.scene).await.map_err(|e| e.to_string())?;
        let image = self.exec.read_output_async(&self.gpu).await.map_err(|e| e.to_string())?;
        let pixels = web_sys::ImageData::new_with_u8_clamped_array_and_sh(wasm_bindgen::Clamped(image.as_raw()), image.width(), image.height())
            .map_err(|e| format!("the frame cannot become canvas pixels: {e:?}"))?;
        self.canvas.put_image_data(&pixels, 0.0, 0.0).map_err(|e| format!("the canvas refused the frame: {e:?}"))?;
        self.frames += 1;
        Ok(timings)
    }

    /// The profiler panel's data: per-pass GPU and CPU milliseconds, rays per pixel.
    fn profile(&self, t: &FrameTimings) -> String {
        let pixels = (self.size.0 as f64 * self.size.1 as f64).max(1.0);
        let passes: Vec<serde_json::Value> = self
            .exec
            .plan()
            .passes()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                serde_json::json!({
                    "name": p.name,
                    "kind": p.kind.name(),
                    "gpu_ms": t.gpu_ms.as_ref().and_then(|g| g.get(i)).copied(),
                    "cpu_ms": t.cpu_ms.get(i).copied(),
                    "rays_per_pixel": t.pass_rays.get(i).copied().flatten().map(|r| r.traced() as f64 / pixels),
                })
            })
            .collect();
        serde_json::json!({
            "frame": self.frames,
            "mode": self.mode.label(),
            "scene": self.scene_name,
            "triangles": self.scene.triangle_count(),
            "size": [self.size.0, self.size.1],
            "frame_ms": t.frame_ms,
            "timestamps": t.gpu_ms.is_some(),
            "rays_per_pixel": t.rays.map(|r| r.traced() as f64 / pixels),
            "accel": t.accel.as_ref().map(|a| a.describe()),
            "passes": passes,
        })
        .to_string()
    }
}

#[wasm_bindgen]
impl App {
    /// Opens WebGPU on `canvas` (`width` x `height` pixels) and shows built-in scene `scene` in
    /// mode `mode` (`raster`, `hybrid`, `rt`).
    pub async fn start(canvas: web_sys::HtmlCanvasElement, width: u32, height: u32, scene: String, mode: String) -> Result<App, JsValue> {
        console_error_panic_hook::set_once();
        log_lines::install();
        let mode = parse_mode(&mode).map_err(js_error)?;
        let size = (width.max(1), height.max(1));
        canvas.set_width(size.0);
        canvas.set_height(size.1);
        let context = canvas
            .get_context("2d")
            .ok()
            .flatten()
            .and_then(|c| c.dyn_into::<web_sys::CanvasRenderingContext2d>().ok())
            .ok_or_else(|| js_error("the canvas has no 2D context"))?;
        let gpu = open_gpu().await.map_err(js_error)?;
        let plan = plan(&gpu, mode, size).map_err(js_error)?;
        let scene_value = builtin_scene(&scene).map_err(js_error)?;
        let exec = Executor::new(&gpu, plan, &scene_value).map_err(|e| js_error(format!("{scene}: {e}")))?;
        let info = format!("{} | back-end {}", gpu.describe(), gpu.describe_backend());
        let renderer =
            Renderer { gpu, canvas: context, size, mode, scene_name: scene, scene: scene_value, fly: None, exec, last_frame: None, frames: 0, clock: 0.0 };
        let inbox = Inbox::default();
        Ok(App { renderer: Rc::new(RefCell::new(renderer)), inbox: Rc::new(RefCell::new(inbox)), info })
    }

    /// Renders one frame (after applying the input since the last); resolves when it is on the
    /// canvas and its timings are read. Rejects with the error's text; the page goes on with
    /// the last scene and mode that worked.
    // The renderer stays borrowed while the frame awaits the GPU: that is what keeps a second
    // frame out (`try_borrow_mut` refuses it); the page's other calls touch only the inbox.
    #[allow(clippy::await_holding_refcell_ref)]
    pub fn frame(&self) -> js_sys::Promise {
        let (renderer, inbox) = (self.renderer.clone(), self.inbox.clone());
        wasm_bindgen_futures::future_to_promise(async move {
            let Ok(mut r) = renderer.try_borrow_mut() else {
                return Err(js_error("a frame is already running: await each frame before the next"));
            };
            let now = js_sys::Date::now();
            let dt = r.last_frame.map_or(0.0, |t| ((now - t) / 1e3) as f32).min(0.1);
            r.last_frame = Some(now);
            r.apply(&mut inbox.borrow_mut(), dt).map_err(js_error)?;
            let timings = r.frame().await.map_err(js_error)?;
            inbox.borrow_mut().profile = r.profile(&timings);
            Ok(JsValue::from_f64(r.frames as f64))
        })
    }

    /// Switches to mode `mode` (`raster`, `hybrid`, `rt`) at the next frame.
    pub fn set_mode(&self, mode: &str) -> Result<(), JsValue> {
        self.inbox.borrow_mut().mode = Some(parse_mode(mode).map_err(js_error)?);
        Ok(())
    }

    /// Shows built-in scene `name` from the next frame.
    pub fn load_builtin(&self, name: &str) -> Result<(), JsValue> {
        let scene = builtin_scene(name).map_err(js_error)?;
        self.inbox.borrow_mut().scene = Some((name.to_string(), scene));
        Ok(())
    }

    /// Loads the glTF or GLB file `name` (its bytes, from the file picker) and shows it from
    /// the next frame. A bad file is refused with an error naming it; the current scene stays.
    pub fn load_file(&self, name: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let (scene, report) = scene::load::open_bytes(name, bytes, &LoadOptions::default()).map_err(js_error)?;
        for note in report.notes() {
            log::warn!("{name}: {note}");
        }
        self.inbox.borrow_mut().scene = Some((name.to_string(), scene));
        Ok(())
    }

    /// Turns the camera by a mouse movement of `dx`, `dy` pixels.
    pub fn look(&self, dx: f32, dy: f32) {
        let mut inbox = self.inbox.borrow_mut();
        inbox.look.0 += dx;
        inbox.look.1 += dy;
    }

    /// Wheel: scales the camera's speed (each notch by 1.2).
    pub fn scale_speed(&self, notches: f32) {
        self.inbox.borrow_mut().speed_notches += notches;
    }

    /// A key went down (`down`) or up: W A S D move, Q E down and up, Shift faster.
    pub fn key(&self, code: &str, down: bool) {
        let keys = &mut self.inbox.borrow_mut().keys;
        match code {
            "KeyW" | "ArrowUp" => keys.forward = down,
            "KeyS" | "ArrowDown" => keys.back = down,
            "KeyA" | "ArrowLeft" => keys.left = down,
            "KeyD" | "ArrowRight" => keys.right = down,
            "KeyE" => keys.up = down,
            "KeyQ" => keys.down = down,
            "ShiftLeft" | "ShiftRight" => keys.fast = down,
            _ => {}
        }
    }

    /// The last frame's profile (JSON): passes with GPU and CPU milliseconds and rays per
    /// pixel, the frame's rays per pixel, what the acceleration structures did.
    pub fn profile(&self) -> String {
        self.inbox.borrow().profile.clone()
    }

    /// The adapter and the back-end chosen, with the reason.
    pub fn info(&self) -> String {
        self.info.clone()
    }

    /// Log lines at warning level and above since the last call (features chosen out at
    /// start-up, import notes), for the page's log panel.
    pub fn take_log(&self) -> Vec<String> {
        log_lines::take()
    }

    /// The built-in scenes the page offers.
    pub fn builtin_scenes() -> Vec<String> {
        scene::load::BUILTIN_NAMES.iter().map(|n| n.to_string()).collect()
    }
}
