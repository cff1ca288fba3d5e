// The page: starts raygraph on the canvas, runs one frame per animation frame, and wires the
// mode switch, the scene list, the file picker, the camera and the profiler panel.
// URL parameters: scene, mode (raster|hybrid|rt), width, height, test=1 (canvas only),
// frames=N and report=PATH (POST a JSON report after N frames or on an error), gltf=URL
// (load that file as the picker would).
import init, { App } from './raygraph_web.js';

const params = new URLSearchParams(location.search);
const test = params.get('test') === '1';
const reportPath = params.get('report');
const framesWanted = Number(params.get('frames') || 4);
const errorBox = document.getElementById('error');
let app = null;
let reported = false;
let markReportSent;
const reportSent = new Promise((resolve) => { markReportSent = resolve; });

function showError(e) {
  errorBox.textContent = String(e && e.message ? e.message : e);
}

async function report(status, message, frames) {
  if (!reportPath || reported) return;
  reported = true;
  const body = {
    status, message, frames,
    adapter: app ? app.info() : '',
    shown: errorBox.textContent,
    profile: app ? app.profile() : '',
  };
  await fetch(reportPath, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  markReportSent();
}

function fmt(v, digits) {
  return v === null || v === undefined ? '–' : v.toFixed(digits);
}

function showProfile() {
  const text = app.profile();
  if (!text) return;
  const p = JSON.parse(text);
  document.getElementById('summary').textContent =
    `${p.scene}, ${p.triangles.toLocaleString()} triangles, ${p.mode}, ${p.size[0]}x${p.size[1]}: ` +
    `frame ${fmt(p.frame_ms, 1)} ms, ${fmt(p.rays_per_pixel, 2)} rays/px` +
    (p.timestamps ? '' : ' (no GPU timestamps in this browser)') + (p.accel ? `; ${p.accel}` : '');
  const rows = p.passes.map((s) =>
    `<tr><td>${s.name}</td><td>${s.kind}</td><td>${fmt(s.gpu_ms, 3)}</td><td>${fmt(s.cpu_ms, 2)}</td><td>${fmt(s.rays_per_pixel, 2)}</td></tr>`);
  document.querySelector('#passes tbody').innerHTML = rows.join('');
  const lines = app.take_log();
  if (lines.length) document.getElementById('log').textContent += lines.join('\n') + '\n';
}

async function loadFile(name, bytes) {
  try {
    app.load_file(name, bytes);
    errorBox.textContent = '';
    framesSinceLoad = 0;
  } catch (e) {
    showError(e);
    await report('error', String(e), 0);
  }
}

// The next frame: at the display's next refresh, or at once in a test (a headless browser
// under a virtual-time budget runs no animation frames).
const next = test ? (f) => setTimeout(f, 0) : (f) => requestAnimationFrame(f);
let framesSinceLoad = 0;
let failures = 0;
async function loop() {
  try {
    await app.frame();
    framesSinceLoad += 1;
    console.log(`frame ${framesSinceLoad} drawn`);
    failures = 0;
    if (framesSinceLoad % 10 === 1 || framesSinceLoad === framesWanted) showProfile();
    if (framesSinceLoad === framesWanted) await report('rendered', '', framesSinceLoad);
  } catch (e) {
    showError(e);
    await report('error', String(e), framesSinceLoad);
    failures += 1;
  }
  if (failures < 3) next(loop);
}

function wireControls(canvas) {
  for (const input of document.querySelectorAll('input[name=mode]')) {
    input.checked = input.value === (params.get('mode') || 'hybrid');
    input.addEventListener('change', () => { try { app.set_mode(input.value); } catch (e) { showError(e); } });
  }
  const select = document.getElementById('scene');
  for (const name of App.builtin_scenes()) select.add(new Option(name, name, false, name === (params.get('scene') || 'default')));
  select.addEventListener('change', () => {
    try { app.load_builtin(select.value); errorBox.textContent = ''; } catch (e) { showError(e); }
  });
  document.getElementById('file').addEventListener('change', async (event) => {
    const file = event.target.files[0];
    if (file) await loadFile(file.name, new Uint8Array(await file.arrayBuffer()));
  });
  let dragging = false;
  canvas.addEventListener('pointerdown', (e) => { dragging = true; canvas.setPointerCapture(e.pointerId); canvas.focus(); });
  canvas.addEventListener('pointerup', () => { dragging = false; });
  canvas.addEventListener('pointermove', (e) => { if (dragging) app.look(e.movementX, e.movementY); });
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); app.scale_speed(-Math.sign(e.deltaY)); }, { passive: false });
  canvas.addEventListener('keydown', (e) => { app.key(e.code, true); e.preventDefault(); });
  canvas.addEventListener('keyup', (e) => app.key(e.code, false));
}

async function main() {
  if (test) document.body.classList.add('test');
  const canvas = document.getElementById('view');
  const width = Number(params.get('width') || 960);
  const height = Number(params.get('height') || 540);
  canvas.style.width = `${width}px`;
  canvas.style.height = `${height}px`;
  try {
    await init();
    app = await App.start(canvas, width, height, params.get('scene') || 'default', params.get('mode') || 'hybrid');
  } catch (e) {
    showError(e);
    await report('error', String(e), 0);
    return;
  }
  document.getElementById('info').textContent = app.info();
  wireControls(canvas);
  const gltf = params.get('gltf');
  if (gltf) {
    const response = await fetch(gltf);
    const name = gltf.split('/').pop();
    if (!response.ok) {
      showError(`${name}: ${response.status} ${response.statusText}`);
      await report('error', errorBox.textContent, 0);
    } else {
      await loadFile(name, new Uint8Array(await response.arrayBuffer()));
    }
  }
  next(loop);
  // With a report wanted (the browser test), the module's evaluation, and so the page's load
  // event that headless Chromium's screenshot waits for, ends only once the frames are drawn.
  if (reportPath) await reportSent;
}

await main();
