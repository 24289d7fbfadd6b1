// Bootstrap and DOM wiring only: loading, LOD, schedule, camera and drawing live in the Rust
// `Viewer` (src/web/). This file picks the wasm build (WebGPU, or the WebGL2 fallback), sizes the
// canvas, forwards controls to `viewer.setState`, and copies `viewer.state()` into the labels.
//
// URL parameters: ?backend=webgpu|webgl2 forces a backend; ?model=URL loads another .glb;
// ?test=1 draws only on request and exposes window.__clod for the browser tests.

const params = new URLSearchParams(location.search);
const testMode = params.get('test') === '1';
const html = document.documentElement;
const canvas = document.getElementById('views');
const status = document.getElementById('status');
const alert = document.getElementById('error');
const labels = [...document.querySelectorAll('.label')];
const controls = document.getElementById('controls');
const readout = document.getElementById('readout');
const $ = (id) => document.getElementById(id);

let viewer = null;
let wasm = null;
let backend = null;

function showError(message) {
  alert.textContent = message;
  alert.hidden = false;
}

async function webgpuWorks() {
  if (!('gpu' in navigator)) return false;
  try { return (await navigator.gpu.requestAdapter()) !== null; } catch { return false; }
}

// Loads the wasm build for `which` ('webgpu' → pkg/, 'webgl2' → pkg-webgl/).
async function loadBuild(which) {
  const module = await import(which === 'webgpu' ? './pkg/clod_viewer.js' : './pkg-webgl/clod_viewer.js');
  await module.default();
  return module;
}

// Canvas size in CSS pixels: three square views side by side, or stacked on narrow screens.
function sizeCanvas() {
  const width = canvas.parentElement.clientWidth;
  const stacked = width < 640;
  const height = stacked ? 3 * width : Math.round(width / 3);
  canvas.style.height = `${height}px`;
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(width * dpr));
  const h = Math.max(1, Math.round(height * dpr));
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w;
    canvas.height = h;
    viewer?.resize(w, h);
  }
}

function updateLabels() {
  const state = viewer.state();
  const dpr = canvas.width / canvas.clientWidth || 1;
  state.views.forEach((view, i) => {
    const label = labels[i];
    const [x, y, w] = view.rect;
    label.style.left = `${x / dpr}px`;
    label.style.top = `${y / dpr}px`;
    label.style.maxWidth = `${w / dpr}px`;
    label.dataset.level = view.level;
    label.dataset.triangles = view.triangles;
    label.dataset.t = view.t.toFixed(3);
    label.dataset.method = view.method;
    const t = view.t > 0 ? ` → ${view.level + 1}, t = ${view.t.toFixed(2)}` : '';
    label.querySelector('.detail').textContent =
      `level ${view.level}${t} · ${view.triangles.toLocaleString()} triangles`;
  });
  if (state.errors.length) showError(state.errors.join('\n'));
  const levels = state.levels.map((l, i) => `${i}: ${l.triangles}`).join(', ');
  readout.textContent = `${state.backend} (${state.adapter}), ${state.format}, MSAA ${state.msaa}× · ` +
    `distance ${state.distance.toFixed(2)}× · levels ${levels} · LOD chain built in ${state.buildMs} ms` +
    (state.warnings.length ? ` · ${state.warnings.join('; ')}` : '');
  return state;
}

async function fetchModel(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

// Creates the viewer for `bytes`, falling back to WebGL2 when WebGPU fails (unless forced).
async function createViewer(bytes) {
  const forced = params.get('backend');
  if (forced && forced !== 'webgpu' && forced !== 'webgl2') {
    throw new Error(`?backend=${forced}: use webgpu or webgl2`);
  }
  const order = forced ? [forced] : (await webgpuWorks()) ? ['webgpu', 'webgl2'] : ['webgl2'];
  const failures = [];
  for (const which of order) {
    try {
      if (backend !== which) { wasm = await loadBuild(which); backend = which; }
      return await wasm.Viewer.create(canvas, bytes, { backend: which });
    } catch (e) {
      failures.push(`${which}: ${e.message ?? e}`);
    }
  }
  const none = forced ? `${forced} does not work here` : 'Neither WebGPU nor WebGL2 works in this browser';
  throw new Error(`${none} (${failures.join('; ')})`);
}

async function start(name, bytes) {
  html.dataset.state = 'loading';
  alert.hidden = true;
  status.textContent = `Building the LOD chain of ${name}…`;
  viewer?.free();
  viewer = null;
  sizeCanvas();
  viewer = await createViewer(bytes);
  setupControls(viewer.state());
  viewer.frame(performance.now());
  await viewer.finish();
  const state = updateLabels();
  if (state.errors.length) throw new Error(state.errors.join('\n'));
  status.textContent = `${name}: ${state.triangles.toLocaleString()} triangles, ${state.joints} joints, ` +
    `drawn with ${state.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}.`;
  html.dataset.state = 'ready';
}

function set(state) {
  try { viewer?.setState(state); } catch (e) { showError(e.message); }
}

function setupControls(state) {
  controls.hidden = false;
  $('clip').replaceChildren(...state.clips.map((c) => new Option(c, c)));
  $('continuous').max = 1;
}

// Log-scale sliders: 0..1 maps to lo..hi geometrically.
const logScale = (x, lo, hi) => lo * (hi / lo) ** x;

function wireControls() {
  $('play').addEventListener('click', () => {
    const paused = $('play').textContent === 'Pause';
    $('play').textContent = paused ? 'Play' : 'Pause';
    set({ paused });
  });
  $('clip').addEventListener('change', (e) => set({ clip: e.target.value }));
  $('speed').addEventListener('input', (e) => set({ speed: Number(e.target.value) }));
  for (const radio of document.querySelectorAll('[name=distanceMode]')) {
    radio.addEventListener('change', (e) => set({ distanceMode: e.target.value }));
  }
  $('distance').addEventListener('input', (e) => {
    const d = logScale(Number(e.target.value), 1, 100);
    $('distance-out').textContent = `${d.toFixed(1)}×`;
    document.querySelector('[name=distanceMode][value=manual]').checked = true;
    set({ distance: d });
  });
  $('yaw').addEventListener('input', (e) => set({ yaw: Number(e.target.value) }));
  $('tolerance').addEventListener('input', (e) => {
    $('tolerance-out').textContent = `${e.target.value} px`;
    set({ tolerance: Number(e.target.value) });
  });
  $('hysteresis').addEventListener('input', (e) => set({ hysteresis: Number(e.target.value) }));
  $('transition').addEventListener('change', (e) => set({ transition: e.target.value }));
  $('duration').addEventListener('input', (e) => set({ duration: Number(e.target.value) }));
  $('zone').addEventListener('input', (e) => set({ zone: Number(e.target.value) }));
  $('variant').addEventListener('change', (e) => set({ variant: e.target.value }));
  const continuous = () => {
    const on = $('continuous-on').checked;
    $('continuous').disabled = !on;
    const max = viewer?.state().maxTriangles ?? 0;
    const triangles = on ? Math.max(1, Math.round(logScale(Number($('continuous').value), 16, Math.max(16, max)))) : null;
    set({ continuousTriangles: triangles });
    $('continuous-out').textContent = on ? `${viewer.state().continuousTriangles} triangles` : '';
  };
  $('continuous-on').addEventListener('change', continuous);
  $('continuous').addEventListener('input', continuous);
  $('file').addEventListener('change', async (event) => {
    const file = event.target.files[0];
    if (!file) return;
    try {
      await start(file.name, new Uint8Array(await file.arrayBuffer()));
    } catch (e) {
      html.dataset.state = 'error';
      showError(`Could not show ${file.name}: ${e.message ?? e}`);
    }
  });
}

function loop(now) {
  if (viewer) {
    try {
      viewer.frame(now);
      updateLabels();
    } catch (e) {
      showError(e.message ?? String(e));
    }
  }
  requestAnimationFrame(loop);
}

// The browser tests' hook: deterministic frames on request, pixels read back by the renderer.
function exposeTestHook() {
  window.__clod = {
    setState: (state) => viewer.setState(state),
    renderFrame: (nowMs) => { viewer.frame(nowMs); return updateLabels(); },
    readPixels: () => viewer.readPixels(),
    finish: () => viewer.finish(),
    state: () => viewer.state(),
    load: (name, bytes) => start(name, bytes),
  };
}

wireControls();
new ResizeObserver(() => { if (viewer) { sizeCanvas(); } }).observe(canvas.parentElement);
if (testMode) exposeTestHook();
const modelUrl = params.get('model') ?? 'assets/character.glb';
try {
  await start(modelUrl.split('/').pop(), await fetchModel(modelUrl));
  if (!testMode) requestAnimationFrame(loop);
} catch (e) {
  html.dataset.state = 'error';
  status.textContent = 'The viewer could not start.';
  showError(e.message ?? String(e));
}
