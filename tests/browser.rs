//! The web page (`web/`) in a real browser: headless Chromium on SwiftShader's WebGPU adapter.
//!
//! - The page is built once per test binary with `bash web/build.sh` into `web/dist/` (it needs
//!   what `.ci/install-browser.sh` installs). `RAYGRAPH_WEB_DIST=DIR` serves `DIR` instead and
//!   skips the build: a way to check this harness against another page.
//! - Each test starts its own static server on `127.0.0.1:0`: `web/dist/` at `/`,
//!   `tests/fixtures/web/` at `/fixtures/`, and `POST /report`, where the page sends its JSON
//!   report (`status`, `message`, `frames`, `adapter`, `shown`) once it has rendered or failed.
//! - Chromium opens `/__harness.html?PAGE`: `PAGE` in a full-window iframe, and a hidden image
//!   from `/__hold`, which the server answers only once a report has arrived. `--screenshot`
//!   waits for the load event, and the pending image holds it until the page has reported, so
//!   the screenshot shows the finished frames (a page's own top-level `await` does not hold
//!   the load event). Chromium's flags are in [`chromium_command`]; it is killed after
//!   [`CHROMIUM_TIME_LIMIT`].
//! - The screenshot is compared with `raygraph render` of the same scene, mode and size by
//!   the ꟻLIP mean and 99th percentile (nv-flip's default viewing conditions), in each of the
//!   three modes, which must stay under their [`MODES`] limits. On a failure the page's image, the native one and the ꟻLIP map are
//!   kept in a temporary folder, whose path the failure prints.
//! - A corrupt GLB (`tests/fixtures/web/corrupt.glb`) must give an error report naming the file
//!   whose message the page shows; a test without a browser checks that the server stays
//!   inside its folders.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::{Arc, Condvar, Mutex, OnceLock};
use std::thread;
use std::time::{Duration, Instant};

/// The canvas (and window) size of the tests, in pixels.
const SIZE: (u32, u32) = (320, 240);
/// Chromium's own limit (`--timeout`, ms): it takes the screenshot then, finished or not.
/// Measured on the 2-core CI machine, 2026-11-29: the box page's hybrid and full-RT modes took
/// 18.4-20.8 and 21.3-24.0 s until Chromium ended (SwiftShader compiling every pipeline,
/// the GPU builder's radix sort and single-dispatch rounds among them), past the 20 s this was;
/// 60 s leaves them room and still ends a hung page long before `CHROMIUM_TIME_LIMIT`.
const PAGE_TIMEOUT_MS: u32 = 60_000;
/// The wall-clock limit on the Chromium process, past which it is killed and the test fails, so
/// that a hung browser fails CI instead of stalling it. Chromium's `--timeout` should end it
/// well before this: a run took about 1 s for a trivial page and 6 to 7 s for the box scene
/// page up to its first frame (4.4 s at 320x240 on SwiftShader) on the 2-core CI machine.
const CHROMIUM_TIME_LIMIT: Duration = Duration::from_secs(120);
/// How long after Chromium has exited a report may still arrive.
const REPORT_GRACE: Duration = Duration::from_secs(2);
/// Per mode (the page's name, the native `--mode`): the largest ꟻLIP mean and 99th percentile
/// (per pixel) allowed between the page's screenshot and the native render of the box.
/// Measured 2026-11-29 (Chromium on SwiftShader against lavapipe, Mesa 25.0.7): mean 0.0039,
/// 0.0040 and 0.0026, 99th percentile 0.0378, 0.0399 and 0.0236 (raster, hybrid, full RT): the
/// crate's texture is filtered a little differently across its faces, and a few AO samples
/// differ. The limits leave 2.5x each.
const MODES: [(&str, &str, f32, f32); 3] = [("raster", "raster", 0.01, 0.095), ("hybrid", "hybrid", 0.01, 0.1), ("rt", "full-rt", 0.0065, 0.06)];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The folder the page is served from: `RAYGRAPH_WEB_DIST`, or `web/dist/` built once.
fn web_dist() -> &'static Path {
    static DIST: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let dist = DIST.get_or_init(|| match std::env::var_os("RAYGRAPH_WEB_DIST") {
        Some(dir) => Ok(PathBuf::from(dir)),
        None => build_page(),
    });
    match dist {
        Ok(dir) => dir,
        Err(e) => panic!("{e}"),
    }
}

/// Runs `bash web/build.sh`; the error has its status, the end of its stderr and a hint.
fn build_page() -> Result<PathBuf, String> {
    let started = Instant::now();
    let out = Command::new("bash").arg("web/build.sh").current_dir(repo()).output().map_err(|e| format!("cannot run bash web/build.sh: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "`bash web/build.sh` failed ({}):\n{}\nhint: `bash .ci/install-browser.sh` installs Chromium, the wasm32-unknown-unknown target and wasm-bindgen-cli",
            out.status,
            tail(&String::from_utf8_lossy(&out.stderr), 60)
        ));
    }
    println!("built the page in {:.1} s", started.elapsed().as_secs_f64());
    Ok(repo().join("web/dist"))
}

/// The last `lines` lines of `text`.
fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

/// A fresh, empty folder under the system's temporary folder.
fn fresh_temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raygraph-browser-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The report bodies POSTed to the server, and a signal for whoever waits for the first.
#[derive(Default)]
struct Reports {
    bodies: Mutex<Vec<String>>,
    arrived: Condvar,
}

impl Reports {
    fn push(&self, body: String) {
        self.bodies.lock().unwrap().push(body);
        self.arrived.notify_all();
    }

    /// The first report, waiting for it until `deadline`.
    fn first(&self, deadline: Instant) -> Option<String> {
        let mut bodies = self.bodies.lock().unwrap();
        while bodies.is_empty() {
            let left = deadline.checked_duration_since(Instant::now())?;
            bodies = self.arrived.wait_timeout(bodies, left).unwrap().0;
        }
        bodies.first().cloned()
    }
}

/// The test's HTTP server: files, the harness page, the hold and the reports.
struct PageServer {
    port: u16,
    reports: Arc<Reports>,
}

/// What the server needs to answer a request.
struct Site {
    dist: PathBuf,
    fixtures: PathBuf,
    reports: Arc<Reports>,
}

impl PageServer {
    fn start(dist: &Path) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let reports = Arc::new(Reports::default());
        let site = Arc::new(Site { dist: dist.to_path_buf(), fixtures: repo().join("tests/fixtures/web"), reports: reports.clone() });
        thread::spawn(move || {
            for stream in listener.incoming().flatten() {
                let site = site.clone();
                thread::spawn(move || site.answer(stream));
            }
        });
        PageServer { port, reports }
    }

    /// The address Chromium opens for `page` (a path and query of the page's folder).
    fn harness_url(&self, page: &str) -> String {
        format!("http://127.0.0.1:{}/__harness.html?{page}", self.port)
    }
}

/// A request's method, target and body.
struct Request {
    method: String,
    target: String,
    body: Vec<u8>,
}

fn read_request(stream: &TcpStream) -> Option<Request> {
    let mut reader = BufReader::new(stream);
    let mut line = String::new();
    reader.read_line(&mut line).ok()?;
    let mut parts = line.split_whitespace();
    let (method, target) = (parts.next()?.to_string(), parts.next()?.to_string());
    let mut content_length = 0;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header).ok()? == 0 || header.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = header.split_once(':') {
            if name.trim().eq_ignore_ascii_case("content-length") {
                content_length = value.trim().parse().ok()?;
            }
        }
    }
    let mut body = vec![0; content_length];
    reader.read_exact(&mut body).ok()?;
    Some(Request { method, target, body })
}

/// One response; `Connection: close`, so one request per connection.
fn respond(mut stream: &TcpStream, status: &str, content_type: &str, body: &[u8]) {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nAccess-Control-Allow-Origin: *\r\nAccess-Control-Allow-Headers: *\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let _ = stream.write_all(head.as_bytes()).and_then(|_| stream.write_all(body));
}

impl Site {
    fn answer(&self, stream: TcpStream) {
        let Some(request) = read_request(&stream) else { return };
        let (path, query) = request.target.split_once('?').unwrap_or((&request.target, ""));
        match (request.method.as_str(), path) {
            ("POST", "/report") => {
                self.reports.push(String::from_utf8_lossy(&request.body).into_owned());
                respond(&stream, "200 OK", "text/plain", b"ok");
            }
            ("OPTIONS", _) => respond(&stream, "204 No Content", "text/plain", b""),
            ("GET", "/__harness.html") => respond(&stream, "200 OK", "text/html", harness_page(query).as_bytes()),
            ("GET", "/__hold") => {
                self.reports.first(Instant::now() + CHROMIUM_TIME_LIMIT);
                respond(&stream, "204 No Content", "text/plain", b"");
            }
            ("GET", _) => self.serve_file(&stream, path),
            _ => respond(&stream, "405 Method Not Allowed", "text/plain", b"method not allowed"),
        }
    }

    fn serve_file(&self, stream: &TcpStream, path: &str) {
        let found = match path.strip_prefix("/fixtures/") {
            Some(rel) => file_under(&self.fixtures, rel),
            None => file_under(&self.dist, if path == "/" { "index.html" } else { &path[1..] }),
        };
        match found.and_then(|file| Some((std::fs::read(&file).ok()?, file))) {
            Some((bytes, file)) => respond(stream, "200 OK", content_type(&file), &bytes),
            None => respond(stream, "404 Not Found", "text/plain", b"not found"),
        }
    }
}

/// The page Chromium opens: `page` in an iframe filling the window, and an image whose
/// answer, and so the load event, waits for the report.
fn harness_page(page: &str) -> String {
    let src = page.replace('&', "&amp;").replace('"', "&quot;");
    format!(
        "<!doctype html><html><head><meta charset=\"utf-8\"></head><body style=\"margin:0;overflow:hidden\">\
         <iframe src=\"{src}\" style=\"position:fixed;left:0;top:0;width:100vw;height:100vh;border:0\"></iframe>\
         <img src=\"/__hold\" alt=\"\" style=\"display:none\"></body></html>"
    )
}

/// The file `rel` (URL-encoded) under `root`, if it is a file inside `root`.
fn file_under(root: &Path, rel: &str) -> Option<PathBuf> {
    let rel = percent_decode(rel)?;
    if rel.split('/').any(|part| part == ".." || part.contains('\\')) {
        return None;
    }
    let file = root.join(rel.trim_start_matches('/')).canonicalize().ok()?;
    (file.starts_with(root.canonicalize().ok()?) && file.is_file()).then_some(file)
}

fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            out.push(u8::from_str_radix(text.get(i + 1..i + 3)?, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok().filter(|s| !s.contains('\0'))
}

fn content_type(file: &Path) -> &'static str {
    match file.extension().and_then(|e| e.to_str()) {
        Some("wasm") => "application/wasm",
        Some("js") => "text/javascript",
        Some("html") => "text/html",
        Some("css") => "text/css",
        Some("glb") => "model/gltf-binary",
        _ => "application/octet-stream",
    }
}

/// Headless Chromium with SwiftShader's WebGPU adapter, kept off the network, writing a
/// screenshot of a `SIZE` window.
fn chromium_command(url: &str, screenshot: &Path, profile: &Path) -> Command {
    let mut c = Command::new("chromium");
    c.args([
        "--headless=new",
        "--no-sandbox",
        "--enable-unsafe-webgpu",
        "--enable-features=Vulkan,SkiaGraphite",
        "--enable-dawn-features=allow_unsafe_apis",
        "--ignore-gpu-blocklist",
        "--use-webgpu-adapter=swiftshader",
    ]);
    c.arg(format!("--timeout={PAGE_TIMEOUT_MS}"));
    c.arg(format!("--window-size={},{}", SIZE.0, SIZE.1));
    c.arg(format!("--screenshot={}", screenshot.display()));
    c.arg(format!("--user-data-dir={}", profile.display()));
    c.args(["--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-quic"]);
    c.arg(url);
    // The test suite runs under the Vulkan validation layer with validation errors made fatal
    // (`.ci/vk_layer_settings.txt`): inherited, they stop Chromium's GPU process at start and
    // the page gets no adapter.
    for var in ["VK_INSTANCE_LAYERS", "VK_LAYER_SETTINGS_PATH", "VK_LOADER_LAYERS_ENABLE"] {
        c.env_remove(var);
    }
    c
}

/// What one Chromium run left: its exit status (`None`: killed at the time limit), the end of
/// its stderr, how long it took and the report the page sent, if any.
struct Visit {
    url: String,
    status: Option<ExitStatus>,
    stderr_tail: String,
    elapsed: Duration,
    screenshot: PathBuf,
    report: Option<String>,
}

impl Visit {
    /// Opens `page` (path and query of the page's folder) in Chromium; files go into `dir`.
    fn open(page: &str, dir: &Path) -> Visit {
        let server = PageServer::start(web_dist());
        let url = server.harness_url(page);
        let screenshot = dir.join("page.png");
        let stderr_file = dir.join("chromium-stderr.txt");
        let started = Instant::now();
        let status = run_with_time_limit(chromium_command(&url, &screenshot, &dir.join("profile")), &stderr_file, dir);
        let elapsed = started.elapsed();
        let report = server.reports.first(Instant::now() + REPORT_GRACE);
        let stderr_tail = chromium_stderr_tail(&stderr_file);
        let _ = std::fs::remove_dir_all(dir.join("profile"));
        println!("chromium took {:.1} s for {url}", elapsed.as_secs_f64());
        Visit { url, status, stderr_tail, elapsed, screenshot, report }
    }

    /// The run, for a failure message.
    fn describe(&self) -> String {
        let status = match self.status {
            Some(s) => s.to_string(),
            None => format!("killed after the {} s limit", CHROMIUM_TIME_LIMIT.as_secs()),
        };
        let report = match &self.report {
            Some(r) => format!("report: {r}"),
            None => "no report arrived within the time limit".into(),
        };
        format!("url: {}\nchromium: {status} after {:.1} s\n{report}\nchromium's stderr (end):\n{}", self.url, self.elapsed.as_secs_f64(), self.stderr_tail)
    }

    /// The report as JSON, failing the test with the run's description if there is none.
    fn report_json(&self) -> serde_json::Value {
        let text = self.report.as_deref().unwrap_or_else(|| panic!("the page sent no report\n{}", self.describe()));
        serde_json::from_str(text).unwrap_or_else(|e| panic!("the report is not JSON ({e})\n{}", self.describe()))
    }
}

/// The end of Chromium's stderr, without its complaints about the missing D-Bus.
fn chromium_stderr_tail(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap_or_default();
    let useful: Vec<&str> = text.lines().filter(|l| !l.contains(":ERROR:dbus/")).collect();
    tail(&useful.join("\n"), 25)
}

/// Runs `command` in its own process group, stdout and stderr into files; kills the group
/// at `CHROMIUM_TIME_LIMIT`.
fn run_with_time_limit(mut command: Command, stderr_file: &Path, dir: &Path) -> Option<ExitStatus> {
    command.stdin(Stdio::null()).stdout(std::fs::File::create(dir.join("chromium-stdout.txt")).unwrap());
    command.stderr(std::fs::File::create(stderr_file).unwrap()).process_group(0);
    let mut child = command.spawn().unwrap_or_else(|e| panic!("cannot start chromium ({e}); run `bash .ci/install-browser.sh`"));
    let deadline = Instant::now() + CHROMIUM_TIME_LIMIT;
    while Instant::now() < deadline {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(status);
        }
        thread::sleep(Duration::from_millis(50));
    }
    // SAFETY: kill(2) on the process group this test started; no memory is involved.
    unsafe { libc::kill(-(child.id() as i32), libc::SIGKILL) };
    let _ = child.wait();
    None
}

/// The page's address for `extra` parameters, at `SIZE`, in test mode, reporting to `/report`.
fn page_url(extra: &str) -> String {
    format!("index.html?{extra}&width={}&height={}&test=1&report=/report", SIZE.0, SIZE.1)
}

/// `raygraph render` of the box scene in hybrid mode at `SIZE`, written to `out`.
fn render_native(mode: &str, out: &Path) -> image::RgbImage {
    let size = [SIZE.0.to_string(), SIZE.1.to_string()];
    let args = ["render", "--mode", mode, "--scene", "box", "--backend", "compute", "--width", &size[0], "--height", &size[1], "--out"];
    let run = Command::new(env!("CARGO_BIN_EXE_raygraph"))
        .args(args)
        .arg(out)
        .current_dir(repo())
        // The browser has no texture binding arrays: the native render samples the same
        // resampled texture array (the ꟻLIP mean was the same either way, 0.0040).
        .env("RAYGRAPH_NO_BINDLESS", "1")
        .output()
        .unwrap();
    assert!(run.status.success(), "raygraph render failed ({}):\n{}", run.status, String::from_utf8_lossy(&run.stderr));
    image::open(out).unwrap().to_rgb8()
}

/// The screenshot's top-left `SIZE` corner (the canvas).
fn screenshot_canvas(visit: &Visit) -> image::RgbImage {
    let shot =
        image::open(&visit.screenshot).unwrap_or_else(|e| panic!("no screenshot at {} ({e})\n{}", visit.screenshot.display(), visit.describe())).to_rgb8();
    assert!(
        shot.width() >= SIZE.0 && shot.height() >= SIZE.1,
        "the screenshot is {}x{}, smaller than {SIZE:?}\n{}",
        shot.width(),
        shot.height(),
        visit.describe()
    );
    image::imageops::crop_imm(&shot, 0, 0, SIZE.0, SIZE.1).to_image()
}

/// The ꟻLIP mean of `test` against `reference`, and the error map in the magma colours.
/// The ꟻLIP mean and 99th percentile of `test` against `reference`, and the ꟻLIP map.
fn flip(reference: &image::RgbImage, test: &image::RgbImage) -> (f32, f32, image::RgbImage) {
    let (w, h) = reference.dimensions();
    let map =
        nv_flip::flip(nv_flip::FlipImageRgb8::with_data(w, h, reference), nv_flip::FlipImageRgb8::with_data(w, h, test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let mut pool = nv_flip::FlipPool::from_image(&map);
    let (mean, p99) = (pool.mean(), pool.get_percentile(0.99, false));
    let colours = map.apply_color_lut(&nv_flip::magma_lut());
    (mean, p99, image::RgbImage::from_raw(w, h, colours.to_vec()).unwrap())
}

#[test]
fn page_matches_native_render_in_every_mode() {
    let mut failures = Vec::new();
    for &(page_mode, native_mode, max_mean, max_p99) in &MODES {
        let dir = fresh_temp_dir(&format!("native-{page_mode}"));
        let visit = Visit::open(&page_url(&format!("scene=box&mode={page_mode}&frames=4")), &dir);
        let report = visit.report_json();
        println!("{page_mode}: report: {report:#}");
        assert_eq!(report["status"], "rendered", "{page_mode}: {}", visit.describe());
        let page = screenshot_canvas(&visit);
        let native = render_native(native_mode, &dir.join("native.png"));
        let (mean, p99, map) = flip(&native, &page);
        println!("{page_mode}: ꟻLIP of the page against the native render: mean {mean:.4} (limit {max_mean}), 99th percentile {p99:.4} (limit {max_p99})");
        if mean > max_mean || p99 > max_p99 {
            page.save(dir.join("page-canvas.png")).unwrap();
            map.save(dir.join("flip.png")).unwrap();
            failures.push(format!(
                "{page_mode}: the page differs from the native render: ꟻLIP mean {mean:.4} (limit {max_mean}), 99th percentile {p99:.4} (limit {max_p99})\nimages: {0}/page-canvas.png, {0}/native.png, {0}/flip.png\n{1}",
                dir.display(),
                visit.describe()
            ));
        } else {
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn corrupt_glb_shows_an_error() {
    let dir = fresh_temp_dir("corrupt");
    let visit = Visit::open(&page_url("gltf=/fixtures/corrupt.glb&mode=hybrid"), &dir);
    let report = visit.report_json();
    println!("report: {report:#}");
    assert_eq!(report["status"], "error", "{}", visit.describe());
    let message = report["message"].as_str().unwrap_or_default();
    assert!(message.contains("corrupt.glb"), "the error does not name the file: {message:?}\n{}", visit.describe());
    let shown = report["shown"].as_str().unwrap_or_default();
    assert!(shown.contains(message), "the page does not show the error: shown {shown:?}, message {message:?}\n{}", visit.describe());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn server_keeps_requests_inside_its_folders() {
    let fixtures = repo().join("tests/fixtures/web");
    assert!(file_under(&fixtures, "corrupt.glb").is_some());
    for escape in ["../../../Cargo.toml", "%2e%2e/%2e%2e/%2e%2e/Cargo.toml", "/..%2f..%2f..%2fCargo.toml", "..\\README.md", "missing.glb", ""] {
        assert_eq!(file_under(&fixtures, escape), None, "{escape:?} was served");
    }
    assert_eq!(content_type(Path::new("a/raygraph_web_bg.wasm")), "application/wasm");
    assert_eq!(content_type(Path::new("corrupt.glb")), "model/gltf-binary");
}
