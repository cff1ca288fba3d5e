#!/usr/bin/env python3
"""Writes a screenshot of the page (web/dist, built by web/build.sh) as headless Chromium shows
it: the README's picture of the page.

    python3 web/screenshot.py OUT.png [QUERY] [--window W,H] [--seconds S]

QUERY is the page's URL parameters (default: the atrium in hybrid mode at 960x540, 3 frames).
The page is opened inside a wrapper whose hidden image (/__hold) is answered only once the page
has POSTed its report, so Chromium's --screenshot (taken at the load event) shows the finished
frames, as tests/browser.rs does. Chromium runs with the flags of tests/browser.rs."""
import http.server, os, subprocess, sys, tempfile, threading

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dist")
TYPES = {".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm", ".css": "text/css"}
reported = threading.Event()


class Handler(http.server.BaseHTTPRequestHandler):
    def send(self, status, kind, body):
        self.send_response(status)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def do_GET(self):
        path = self.path.split("?", 1)[0]
        if path == "/__harness.html":
            page = self.path.split("?", 1)[1].replace("&", "&amp;").replace('"', "&quot;")
            body = (f'<!doctype html><body style="margin:0;overflow:hidden"><iframe src="{page}" '
                    'style="position:fixed;left:0;top:0;width:100vw;height:100vh;border:0"></iframe>'
                    '<img src="/__hold" style="display:none"></body>')
            return self.send(200, "text/html", body.encode())
        if path == "/__hold":
            reported.wait(600)
            return self.send(404, "text/plain", b"")
        name = os.path.normpath(path.lstrip("/"))
        file = os.path.join(ROOT, name)
        if name.startswith("..") or not os.path.isfile(file):
            return self.send(404, "text/plain", b"not found")
        with open(file, "rb") as f:
            self.send(200, TYPES.get(os.path.splitext(file)[1], "application/octet-stream"), f.read())

    def do_POST(self):
        body = self.rfile.read(int(self.headers.get("Content-Length", 0)))
        print("report:", body.decode()[:600])
        self.send(200, "text/plain", b"")
        reported.set()

    def log_message(self, *args):
        pass


def main():
    args = sys.argv[1:]
    window, seconds = "1430,600", 300
    for flag in ("--window", "--seconds"):
        if flag in args:
            i = args.index(flag)
            value = args[i + 1]
            del args[i:i + 2]
            window, seconds = (value, seconds) if flag == "--window" else (window, int(value))
    out = os.path.abspath(args[0])
    query = args[1] if len(args) > 1 else "scene=atrium&mode=hybrid&width=960&height=540&frames=3"
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = f"http://127.0.0.1:{server.server_address[1]}/__harness.html?index.html?{query}&report=/report"
    with tempfile.TemporaryDirectory() as profile:
        env = {k: v for k, v in os.environ.items() if not k.startswith("VK_")}
        subprocess.run(["chromium", "--headless=new", "--no-sandbox", "--enable-unsafe-webgpu",
                        "--enable-features=Vulkan,SkiaGraphite", "--enable-dawn-features=allow_unsafe_apis",
                        "--ignore-gpu-blocklist", "--use-webgpu-adapter=swiftshader", f"--timeout={seconds * 1000}",
                        f"--window-size={window}", f"--screenshot={out}", f"--user-data-dir={profile}",
                        "--no-first-run", "--disable-background-networking", "--disable-component-update",
                        "--disable-sync", "--disable-quic", url],
                       env=env, stderr=subprocess.DEVNULL, timeout=seconds + 60, check=True)
    if not reported.is_set():
        sys.exit("the page sent no report before the screenshot")
    print("wrote", out)


main()
