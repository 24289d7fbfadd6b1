// The `<clod-viewer>` custom element: one canvas with the three views (popping | alpha-blending |
// geomorphing) of a skinned glTF character, for the viewer page and for any documentation page.
//
//   <script type="module" src="…/clod-viewer.js"></script>
//   <clod-viewer src="model.glb" clip="Walk" modes="pop blend morph" autoplay loading="lazy"></clod-viewer>
//
// DOM wiring only: loading, LOD, schedule, camera and drawing live in the Rust `Viewer` (src/web/).
// This file finds its wasm builds relative to its own URL (so a docs site can host it under any
// path), picks WebGPU or the WebGL2 fallback, builds the LOD chain in a Web Worker
// (clod-worker.js, the same wasm) so the page never freezes, sizes the canvas from CSS, turns
// mouse, touch and keyboard input into camera settings, and copies `viewer.state()` into labels.
//
// Attributes: src (default: the built-in character), clip, modes (`pop blend morph`, one to three,
// in order), mode (`single` | `crowd`: the character instanced `count` times, default 400, up to
// 4096, each instance with its own level and transitions), variant (`opaque-first | naive | dither`), tolerance (pixels),
// preset (`demonstration`: exaggerated settings that show the changes, see `state().preset`; `realistic`: the defaults), backend
// (`webgpu | webgl2`), autoplay (absent: paused at t = 0), loading (`lazy`: nothing is fetched
// before the element is scrolled into view; GPU work always waits for that), manual-frames (draw
// only on `renderFrame`, for tests).
// Events: `progress` (detail `{ phase, fraction }`, fraction rising to 1 across the phases
// `fetch`, `gpu`, `build`, `ready`), `load` (detail: the viewer's state; the full mesh is drawn
// from then on), `lod` (detail: the state once the levels are attached, `lodFrom` "build" or
// "cache"; the chain bytes are kept in IndexedDB, keyed by the file's SHA-256), `error` (detail
// `{ code, message }`, once per failure; `code` is one of ERROR_CODES), `meter` (detail: `meter()`,
// when the live meter has measured a transition).
// Methods: play(), pause(), setTime(seconds), setState({...}), state(), link(), applyLink(pairs), meter(), meterHistory(),
// load({ name, bytes, resources }), readPixels(), screenshot(), measurePopSpike(), textureLevels(i),
// flipImages(reference, test, width, height, ppd).

import { drawReplay } from './clod-replay.js';
import {
  buildOffMainThread, buildWorker, cacheGet, cachePut, chainKey, loadBuild, loadDraco, resolverFor, webgpuWorks,
} from './clod-loading.js';

export { drawReplay, METHOD_COLORS } from './clod-replay.js';
export { loadBuild, loadDraco, resolverFor, webgpuWorks } from './clod-loading.js';

// Every file the element loads is named relative to this module as a literal `import('./…')` or
// `new URL('./…', import.meta.url)`: a browser resolves them next to this file wherever a site
// hosts it (a copy of www/, or node_modules/clod-viewer/), and bundlers (Vite, webpack, Parcel)
// recognise the same forms and emit the files with the bundle.
const DEFAULT_SRC = new URL('./assets/character.glb', import.meta.url).href;
// The attributes that change the viewer's settings, in the order they are applied (the preset
// first: an explicit tolerance attribute then overrides its threshold); the viewer reads their
// values (`applyAttribute`), and `autoplay` is applied absent too (paused).
const SETTING_ATTRIBUTES = ['autoplay', 'preset', 'clip', 'modes', 'variant', 'tolerance', 'mode', 'count'];
const METHOD_LABELS = { popping: 'popping', alpha: 'alpha-blending', geomorph: 'geomorphing' };
// Labels of narrow views (the `modes` attribute's names).
const SHORT_METHOD_LABELS = { popping: 'pop', alpha: 'blend', geomorph: 'morph' };
// The label forms, longest first: `full` spells everything out, `compact` keeps the method's
// name and abbreviates the rest, `short` abbreviates the name too.
const LABEL_FORMS = ['full', 'compact', 'short'];

// A view's label in one of LABEL_FORMS: the method, the level or change shown (in crowd mode the
// instances drawn, each at its own level), the triangles drawn and the magnifier.
function labelText(state, view, form) {
  const full = form === 'full';
  const name = (form === 'short' ? SHORT_METHOD_LABELS : METHOD_LABELS)[view.method] ?? view.method;
  const triangles = `${view.triangles.toLocaleString()} ${full ? 'triangles' : 'tris'}`;
  if (state.crowd) {
    const drawn = `${state.crowd.drawn.toLocaleString()} of ${state.crowd.instances.toLocaleString()} drawn`;
    return full ? `${name} · ${drawn} · ${triangles}` : `${name} · ${triangles}`;
  }
  const t = view.t.toFixed(2);
  const morph = view.to === view.level ? '' : full ? `, t = ${t}` : ` (${t})`;
  // The continuous slider's two states are levels `levels.length` and one more: no level a
  // reader knows, so the label names the slider instead.
  let where;
  if (state.continuousTriangles !== null) where = `${full ? 'continuous' : 'cont.'}${morph}`;
  else if (full) where = `level ${view.level}${morph && ` → ${view.to}${morph}`}`;
  else where = `L${view.level}${morph && `→${view.to}${morph}`}`;
  // Magnified views say so: what is seen is the real size's change, enlarged.
  const magnified = state.magnify > 1 ? ` · ${full ? 'magnified ' : ''}×${state.magnify}` : '';
  return `${name} · ${where} · ${triangles}${magnified}`;
}

// What a reader sees when the browser gives the canvas neither a WebGPU nor a WebGL2 context
// (the backends' own reports go to the console).
const NO_GPU_MESSAGE = 'This browser could not start WebGPU or WebGL2 for the viewer. Turn on hardware ' +
  'acceleration in the browser settings, or open the page in a current Chrome, Edge, Firefox or Safari.';

// The `code` of every `error` event, and what it means to a page (the README lists them too).
export const ERROR_CODES = {
  fetch: 'the model could not be downloaded (HTTP status or network)',
  model: 'the file cannot be shown: the importer refused it, a .gltf resource is missing, or it exceeds this GPU\'s limits',
  levels: 'the LOD levels could not be built or attached; the full mesh keeps playing',
  'no-gpu': 'the browser gives the canvas neither WebGPU nor WebGL2',
  wasm: 'the viewer\'s own files (pkg/, pkg-webgl/, or pkg-draco/ for a Draco file) could not be loaded',
  attribute: 'an attribute holds a value the viewer does not take',
  render: 'the GPU reported an error while drawing',
};

/** `error` with `code` set (kept when it already has one of ERROR_CODES). */
function coded(error, code) {
  const e = error instanceof Error ? error : new Error(String(error));
  if (!(e.code in ERROR_CODES)) e.code = code;
  return e;
}

// Where each phase's progress lands on the overall 0..1 bar, in the order they run: the model is
// drawn at full detail after `gpu` (the `load` event), and the LOD build fills the rest (the
// `lod` event, then `ready`).
const PHASES = { fetch: [0, 0.1], gpu: [0.1, 0.2], build: [0.2, 1], ready: [1, 1] };

// --- the element ---------------------------------------------------------------------------------

const STYLE = `
clod-viewer { display: block; position: relative; aspect-ratio: 3 / 1; min-height: 120px; contain: layout paint; }
clod-viewer > canvas { display: block; position: absolute; inset: 0; width: 100%; height: 100%;
  background: #8a96a6; touch-action: none; }
clod-viewer > canvas:focus-visible { outline: 3px solid Highlight; outline-offset: -3px; }
clod-viewer > .clod-label { position: absolute; box-sizing: border-box; padding: 0.15rem 0.45rem; font: 0.8rem system-ui, sans-serif; color: #fff;
  background: rgb(0 0 0 / 0.45); border-radius: 0 0 0.3rem 0; pointer-events: none; white-space: nowrap;
  overflow: hidden; text-overflow: ellipsis; font-variant-numeric: tabular-nums; }
clod-viewer > .clod-progress { position: absolute; left: 10%; width: 80%; top: 50%; height: 0.5rem; margin: 0; }
clod-viewer > .clod-progress.clod-building { top: auto; bottom: 0.4rem; height: 0.3rem; opacity: 0.8; }
clod-viewer > .clod-alert { position: absolute; inset: auto 0 0 0; margin: 0; padding: 0.4rem 0.6rem;
  font: 600 0.85rem system-ui, sans-serif; color: #fff; background: rgb(150 30 20 / 0.9); }
clod-viewer > [hidden] { display: none; }
`;

function installStyle() {
  if (document.getElementById('clod-viewer-style')) return;
  const style = document.createElement('style');
  style.id = 'clod-viewer-style';
  style.textContent = STYLE;
  document.head.append(style);
}

export class ClodViewerElement extends HTMLElement {
  static observedAttributes = ['src', ...SETTING_ATTRIBUTES];

  #canvas = null;
  #labels = [];
  #bar = null;
  #alert = null;
  #viewer = null;
  #backend = null;
  #visible = false;
  #source = null; // { name, bytes, resources } of the model shown (or being loaded); + draco while loading
  #pending = null; // the load in progress
  #frameId = 0;
  #progress = 0;
  #lastFrameMs = 0;
  #frameMs = 0;
  #observers = [];
  #pointers = new Map();
  #lastState = null;
  #meterSeen = 0;
  #loadId = 0;
  #ignored = [];
  #errorsSeen = 0; // renderer errors of the current viewer already reported
  #broken = false; // the current viewer threw while drawing: no more frames until another loads
  #cancels = new Set(); // rejections of the calls waiting on the current viewer (#whileShown)

  connectedCallback() {
    if (!this.#canvas) this.#buildDom();
    const io = new IntersectionObserver((entries) => {
      this.#visible = entries.at(-1).isIntersecting;
      if (this.#visible) this.#startWhenVisible();
      this.#schedule();
    });
    io.observe(this);
    const ro = new ResizeObserver(() => this.#resize());
    ro.observe(this);
    this.#observers = [io, ro];
    if (this.getAttribute('loading') !== 'lazy') this.#prepare();
  }

  disconnectedCallback() {
    for (const o of this.#observers) o.disconnect();
    this.#observers = [];
    cancelAnimationFrame(this.#frameId);
    this.#frameId = 0;
  }

  attributeChangedCallback(name, old, value) {
    if (old === value || !this.#viewer) return;
    if (name === 'src') { this.#source = null; this.#pending = null; this.#prepare(); this.#startWhenVisible(); return; }
    try {
      // The viewer reads the attribute (src/js_api/attributes.rs); a value it does not take
      // throws a sentence quoting it.
      this.#viewer.applyAttribute(name, value, this.getAttribute('preset'));
      this.#schedule();
    } catch (e) {
      this.#fail(coded(e, 'attribute'));
    }
  }

  // --- public API ---

  /** The canvas the views are drawn on. */
  get canvas() { return this.#canvas; }
  /** `webgpu` or `webgl2` once loaded. */
  get backend() { return this.#backend; }
  /** Mean time between drawn frames, ms (0 before two frames). */
  get frameMs() { return this.#frameMs; }
  play() { this.setState({ paused: false }); }
  pause() { this.setState({ paused: true }); }
  /** Moves the animation clock to `seconds`. */
  setTime(seconds) { this.setState({ time: Number(seconds) }); }
  /** Changes viewer settings (the keys: docs/viewer.md); throws on an unknown key or bad value. */
  setState(state) { this.#requireViewer().setState(state); this.#schedule(); }
  /**
   * What the views show: levels, triangles, `level → to` and `t` of the transition every view
   * shows, backend, … (see docs/viewer.md). While a readback or a pop-spike measurement holds the
   * viewer, the last state read.
   */
  state() {
    this.#lastState = this.#requireViewer().state();
    return this.#lastState;
  }
  /**
   * Attribute values the model shown cannot take (a clip it does not have, say), each with the
   * reason: they were ignored, the rest applied.
   */
  get ignoredSettings() { return this.#ignored; }
  /**
   * The settings as a link carries them: `{ preset, pairs }`, the preset a link names and the
   * `[key, value]` pairs (setState's keys) that differ from it. See docs/viewer.md, "Links".
   */
  link() { return this.#requireViewer().link(); }
  /**
   * Applies a link's `[key, value]` pairs (e.g. `[...new URLSearchParams(location.search)]`),
   * each on its own, after its preset; other keys are left alone. Returns a message for each
   * pair whose value was not taken.
   */
  applyLink(pairs) {
    const ignored = this.#requireViewer().applyLink(pairs);
    this.#schedule();
    return ignored;
  }
  /** Draws one frame at `nowMs` (for `manual-frames`) and returns the state. */
  renderFrame(nowMs) { this.#requireViewer().frame(nowMs); return this.#updateLabels(); }
  /** The current frame read back: `{ width, height, data }` (RGBA8, top row first). */
  readPixels() { return this.#whileShown(this.#requireViewer().readPixels()); }
  /** Mip levels of material `i`'s texture read back: `[{ width, height, mean }]` (linear light). */
  textureLevels(i) { return this.#whileShown(this.#requireViewer().textureLevels(i)); }
  /** Resolves when the GPU has finished the submitted frames. */
  finish() { return this.#whileShown(this.#requireViewer().finish()); }
  /**
   * LDR-FLIP of two RGBA8 sRGB pictures on the viewer's GPU (flip.wgsl): resolves to
   * `{ mean, p99, max, ppd }`, or null where the GPU cannot render into float targets.
   */
  flipImages(reference, test, width, height, ppd = 67.02) { return this.#whileShown(this.#requireViewer().flipImages(reference, test, width, height, ppd)); }
  /**
   * The live meter's last completed transition per method: `{ popping, alpha, geomorph }`, each
   * `{ silhouette, shading, transitions }` (silhouette: the largest frame-to-frame change, in % of
   * the view's pixels, of the area where the view and the full-detail reference differ in
   * coverage; shading: the same for mean |ΔRGB| per pixel, 0..765), or null until one was seen.
   */
  meter() {
    const m = this.state().meter;
    return { popping: m.popping, alpha: m.alpha, geomorph: m.geomorph };
  }
  /** The meter's recent samples for a strip chart (see docs/viewer.md). */
  meterHistory() { return this.#requireViewer().meterHistory(); }
  /**
   * The last transition's replay, or null: each view's meter pictures across it cropped to the
   * region of its largest change, and each view's per-frame curves (see the README).
   */
  replay() { return this.#requireViewer().replay(); }
  /** The replay as one PNG (film strip and curves, see `drawReplay`), or null before a transition. */
  async replayPng() {
    const replay = this.replay();
    if (!replay) return null;
    const canvas = document.createElement('canvas');
    drawReplay(canvas, replay);
    return new Promise((resolve, reject) => canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png'));
  }
  /** Measures each view's largest frame-to-frame change through one LOD switch. */
  measurePopSpike(options = {}) { return this.#whileShown(this.#requireViewer().measurePopSpike(options)); }

  /** A PNG of the current frame with the views' labels. */
  async screenshot() {
    const { width, height, data } = await this.readPixels();
    const canvas = document.createElement('canvas');
    canvas.width = width;
    canvas.height = height;
    const ctx = canvas.getContext('2d');
    ctx.putImageData(new ImageData(new Uint8ClampedArray(data.buffer, data.byteOffset, data.length), width, height), 0, 0);
    const dpr = width / this.#canvas.clientWidth || 1;
    ctx.font = `${Math.round(13 * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'top';
    for (const label of this.#labels) {
      if (label.hidden) continue;
      const x = label.offsetLeft * dpr;
      const y = label.offsetTop * dpr;
      const text = label.textContent;
      // Within the label's box, which is at most its view's width: narrow views squeeze the text.
      const boxWidth = Math.min(ctx.measureText(text).width + 12 * dpr, label.offsetWidth * dpr);
      ctx.fillStyle = 'rgb(0 0 0 / 0.45)';
      ctx.fillRect(x, y, boxWidth, 20 * dpr);
      ctx.fillStyle = '#fff';
      ctx.fillText(text, x + 6 * dpr, y + 3 * dpr, Math.max(1, boxWidth - 12 * dpr));
    }
    return new Promise((resolve, reject) => canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png'));
  }

  /**
   * Shows another model: `{ name, bytes: Uint8Array, resources?: Map<name, Uint8Array> }` (a
   * `.gltf`'s buffers and images). Resolves with the new state; on failure it rejects, shows the
   * error, and the previous model keeps playing.
   */
  load(source) {
    this.#source = source;
    this.#pending = null;
    return this.#prepare(true);
  }

  // --- loading ---

  #buildDom() {
    installStyle();
    this.#canvas = document.createElement('canvas');
    this.#canvas.tabIndex = 0;
    this.#canvas.setAttribute('aria-label', 'LOD transitions of an animated character. Drag to orbit, shift-drag or two fingers to pan, wheel or pinch to zoom; arrow keys orbit, shift+arrows pan, + and − zoom, 0 resets the camera.');
    this.#bar = document.createElement('progress');
    this.#bar.className = 'clod-progress';
    this.#bar.max = 1;
    this.#bar.value = 0;
    this.#alert = document.createElement('p');
    this.#alert.className = 'clod-alert';
    this.#alert.setAttribute('role', 'alert');
    this.#alert.hidden = true;
    this.#labels = [0, 1, 2].map((i) => {
      const label = document.createElement('div');
      label.className = 'clod-label label';
      label.dataset.view = i;
      label.hidden = true;
      return label;
    });
    this.append(this.#canvas, ...this.#labels, this.#bar, this.#alert);
    this.#wireInput();
  }

  #emit(type, detail) { this.dispatchEvent(new CustomEvent(type, { detail })); }

  #reportProgress(phase, fraction) {
    const [lo, hi] = PHASES[phase];
    const overall = Math.max(this.#progress, lo + (hi - lo) * Math.min(1, Math.max(0, fraction)));
    this.#progress = overall;
    this.#bar.value = overall;
    this.#emit('progress', { phase, fraction: overall });
  }

  // Fetches and builds the current source (once); the GPU part waits for visibility.
  #prepare(replace = false) {
    if (this.#pending) return this.#pending;
    // A newer load supersedes this one: its progress stops counting and its viewer is dropped.
    const id = ++this.#loadId;
    const report = (phase, fraction) => { if (this.#loadId === id) this.#reportProgress(phase, fraction); };
    this.#progress = 0;
    this.#bar.hidden = false;
    this.#bar.value = 0;
    let showGpu;
    const visible = new Promise((resolve) => { showGpu = resolve; });
    const pending = (async () => {
      const { module, backend, fallbacks } = await this.#chooseBuild();
      this.#source ??= await this.#fetchSource(this.getAttribute('src') || DEFAULT_SRC, report);
      // Draco-compressed geometry: the decoder is a module of its own, fetched for such files only.
      const draco = module.usesDraco(this.#source.bytes) ? await loadDraco().catch((e) => { throw coded(e, 'wasm'); }) : null;
      const source = { ...this.#source, draco };
      report('fetch', 1);
      await visible;
      // With a worker the full mesh is drawn at once and the levels follow (#attachLevels);
      // without one, the chain is built inline before the first frame.
      const later = buildWorker() !== null;
      const attach = (state) => { if (later) this.#attachLevels(module, backend, source, id); return state; };
      try {
        return attach(await this.#createViewer(module, backend, source, later, id));
      } catch (e) {
        // WebGPU has an adapter but no usable device (or the surface fails): the WebGL2 build.
        // The LOD bytes are the same whichever build made them.
        if (e.code !== 'no-gpu') throw e;
        if (!fallbacks.length) throw coded(new Error(NO_GPU_MESSAGE), 'no-gpu');
        const fallback = await loadBuild(fallbacks[0]).catch((e2) => { throw coded(e2, 'wasm'); });
        try {
          return attach(await this.#createViewer(fallback.module, fallbacks[0], source, later, id));
        } catch (e2) {
          throw e2.code === 'no-gpu' ? coded(new Error(NO_GPU_MESSAGE), 'no-gpu') : e2;
        }
      }
    })();
    pending.showGpu = showGpu;
    this.#pending = pending;
    const done = pending.then((state) => {
      this.#alert.hidden = true;
      if (state.lodFrom) this.#levelsReady(id);
      else this.#bar.classList.add('clod-building');
      this.#emit('load', state);
      this.#schedule();
      return state;
    }, (e) => {
      if (this.#pending === pending) this.#pending = null;
      if (this.#loadId !== id) throw Object.assign(e instanceof Error ? e : new Error(String(e)), { superseded: true }); // the newer load reports
      this.#bar.hidden = true;
      const error = coded(e, 'model');
      this.#fail(error);
      throw error;
    });
    // The GPU part waits until the element is seen, unless a model is already on the GPU: the
    // next one a reader opens (say, scrolled down to the page's controls) is then ready when they
    // look, its levels built meanwhile.
    if (this.#visible || this.#viewer) showGpu();
    if (!replace) done.catch(() => {});
    return done;
  }

  // Gets the LOD chain of the model shown (the cache, else the worker) and attaches it; fires
  // `lod` with the state. A newer load makes it stop.
  async #attachLevels(module, backend, source, id) {
    const viewer = this.#viewer;
    const current = () => this.#loadId === id && this.#viewer === viewer;
    try {
      const key = await chainKey(source, module.chainCacheTag());
      const cached = key && (await cacheGet(key));
      if (cached && current()) {
        try {
          await viewer.attachLod(cached.clod, cached.buildMs, 'cache');
          if (current()) this.#levelsReady(id);
          return;
        } catch { /* a stale entry: build again */ }
      }
      const built = await buildOffMainThread(backend, source.draco !== null, source, (f) => { if (current()) this.#reportProgress('build', f); });
      if (!current()) return;
      if (!built) throw new Error('no worker could build the LOD chain');
      await viewer.attachLod(built.clod, built.buildMs, 'build');
      if (key) cachePut(key, { clod: built.clod, buildMs: built.buildMs });
      if (current()) this.#levelsReady(id);
    } catch (e) {
      if (!current()) return;
      this.#bar.hidden = true;
      this.#fail(coded(new Error(`${source.name}: the levels could not be built (${e.message ?? e}); showing the full mesh`), 'levels'));
    }
  }

  #levelsReady(id) {
    if (this.#loadId !== id) return;
    this.#bar.hidden = true;
    this.#bar.classList.remove('clod-building');
    this.#reportProgress('build', 1);
    this.#reportProgress('ready', 1);
    this.#emit('lod', this.state());
  }

  #startWhenVisible() {
    if (!this.#pending && !this.#viewer) this.#prepare();
    if (this.#visible) this.#pending?.showGpu();
  }

  async #chooseBuild() {
    const forced = this.getAttribute('backend');
    if (forced && forced !== 'webgpu' && forced !== 'webgl2') throw coded(new Error(`backend="${forced}": must be one of "webgpu", "webgl2"`), 'attribute');
    const order = forced ? [forced] : (await webgpuWorks()) ? ['webgpu', 'webgl2'] : ['webgl2'];
    const failures = [];
    for (const backend of order) {
      try {
        return { ...(await loadBuild(backend)), backend, fallbacks: order.slice(order.indexOf(backend) + 1) };
      } catch (e) {
        failures.push(`${backend}: ${e.message ?? e}`);
      }
    }
    throw coded(new Error(`could not load the viewer's wasm (${failures.join('; ')})`), 'wasm');
  }

  async #fetchSource(src, report) {
    const url = new URL(src, document.baseURI);
    const name = decodeURIComponent(url.pathname.split('/').pop());
    const chunks = [];
    let received = 0;
    try {
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
      const total = Number(response.headers.get('content-length')) || 0;
      const reader = response.body.getReader();
      for (;;) {
        const { done, value } = await reader.read();
        if (done) break;
        chunks.push(value);
        received += value.length;
        if (total) report('fetch', received / total);
      }
    } catch (e) {
      // The network's own words (a TypeError) do not say which file: the message does.
      throw coded(e.message?.startsWith(name) ? e : new Error(`${name} could not be downloaded (${e.message ?? e})`), 'fetch');
    }
    const bytes = new Uint8Array(received);
    let at = 0;
    for (const c of chunks) { bytes.set(c, at); at += c.length; }
    return { name, bytes, resources: null };
  }

  // Creates the viewer on a fresh canvas and swaps it in only when it works, so a model that
  // fails leaves the previous one playing.
  async #createViewer(module, backend, source, later, id) {
    const canvas = this.#canvas.cloneNode();
    delete canvas.dataset.wired;
    const [w, h] = this.#pixelSize();
    canvas.width = w;
    canvas.height = h;
    const options = { backend, resolve: resolverFor(source.resources) };
    if (source.draco) options.draco = source.draco.decode;
    if (later) options.lod = 'later';
    if (this.#loadId === id) this.#reportProgress('gpu', 0);
    let viewer;
    try {
      viewer = await module.Viewer.create(canvas, source.bytes, options);
    } catch (e) {
      // `code: "no-gpu"`: this backend has no GPU here (another may); the details are in the console.
      throw coded(new Error(`Could not show ${source.name} with ${backend}: ${e.message ?? e}`), e?.code in ERROR_CODES ? e.code : 'model');
    }
    if (this.#loadId !== id) {
      viewer.free();
      throw Object.assign(new Error(`${source.name}: superseded by a newer load`), { superseded: true });
    }
    this.#reportProgress('gpu', 0.5);
    // Each attribute on its own: a value this model cannot take (say a clip of the previous
    // model, kept in the page's URL) is ignored and reported, never fatal.
    const ignored = [];
    for (const name of SETTING_ATTRIBUTES) {
      if (name !== 'autoplay' && !this.hasAttribute(name)) continue;
      try { viewer.applyAttribute(name, this.getAttribute(name), this.getAttribute('preset')); } catch (e) { ignored.push(e.message ?? String(e)); }
    }
    this.#ignored = ignored;
    // Another model in the same viewer keeps what the reader chose for the comparison. It starts
    // from the attributes instead after a frame threw (what was set may be why) and on another
    // backend (the old viewer is another wasm module's object).
    if (this.#viewer && this.#backend === backend && !this.#broken) viewer.keepSettingsOf(this.#viewer);
    for (const cancel of this.#cancels) cancel();
    this.#cancels.clear();
    this.#viewer?.free();
    this.#viewer = viewer;
    this.#meterSeen = 0;
    this.#errorsSeen = 0;
    this.#broken = false;
    this.#backend = backend;
    this.#canvas.replaceWith(canvas);
    this.#canvas = canvas;
    this.#wireInput();
    viewer.frame(performance.now());
    await viewer.finish();
    if (this.#loadId === id) this.#pending = null;
    const state = this.#updateLabels();
    state.name = source.name;
    return state;
  }

  // Shows a failure (an Error with one of ERROR_CODES, see `coded`) and fires `error`.
  #fail(e) {
    this.#alert.textContent = e.message;
    this.#alert.hidden = false;
    this.#emit('error', { code: e.code, message: e.message });
  }

  // A call on the current viewer that a model change ends: it rejects, with `superseded: true`,
  // when another model replaces this one (the old viewer is freed, and on WebGL2 its readbacks
  // would never complete: the page's Measure button waited for ever).
  #whileShown(promise) {
    return new Promise((resolve, reject) => {
      const cancel = () => reject(Object.assign(new Error('another model replaced the one this call was reading'), { superseded: true }));
      this.#cancels.add(cancel);
      promise.then(resolve, reject).finally(() => this.#cancels.delete(cancel));
    });
  }

  #requireViewer() {
    if (!this.#viewer) throw new Error('the viewer has not loaded yet');
    return this.#viewer;
  }

  // --- drawing ---

  #pixelSize() {
    const dpr = window.devicePixelRatio || 1;
    return [Math.max(1, Math.round(this.clientWidth * dpr)), Math.max(1, Math.round(this.clientHeight * dpr))];
  }

  #resize() {
    const [w, h] = this.#pixelSize();
    if (!this.#viewer || (this.#canvas.width === w && this.#canvas.height === h)) return;
    this.#canvas.width = w;
    this.#canvas.height = h;
    this.#viewer.resize(w, h);
    this.#schedule();
  }

  // Runs the frame loop while the element is on screen and the tab visible.
  #schedule() {
    if (this.#frameId || !this.#viewer || this.#broken || !this.#visible || this.hasAttribute('manual-frames')) return;
    this.#frameId = requestAnimationFrame((now) => this.#tick(now));
  }

  #tick(now) {
    this.#frameId = 0;
    // A frame asked for before the viewer broke (a lost context's event arrives between frames)
    // is not drawn.
    if (!this.#viewer || this.#broken || !this.#visible || !this.isConnected) return;
    if (this.#lastFrameMs) this.#frameMs += 0.1 * (now - this.#lastFrameMs - this.#frameMs);
    this.#lastFrameMs = now;
    try {
      this.#viewer.frame(now);
      this.#updateLabels();
    } catch (e) {
      // A frame that throws would throw again: report it once and stop drawing this viewer
      // (loading a model starts a new one).
      this.#broken = true;
      this.#fail(coded(e, 'render'));
      return;
    }
    this.#schedule();
  }

  #updateLabels() {
    const state = this.state();
    const dpr = this.#canvas.width / this.#canvas.clientWidth || 1;
    this.#labels.forEach((label, i) => {
      const view = state.views[i];
      label.hidden = !view;
      if (!view) return;
      const [x, y, w] = view.rect;
      label.style.left = `${x / dpr}px`;
      label.style.top = `${y / dpr}px`;
      label.style.maxWidth = `${w / dpr}px`;
      label.dataset.method = view.method;
      label.dataset.level = view.level;
      label.dataset.triangles = view.triangles;
      label.dataset.to = view.to;
      label.dataset.t = view.t.toFixed(3);
    });
    // One form for every label, the longest whose every label fits its view (three views in a
    // narrow column take the short form); one still too wide ends in an ellipsis (CSS). Each form
    // is written first and measured after: one layout per form tried.
    const shown = this.#labels.slice(0, state.views.length);
    for (const form of LABEL_FORMS) {
      shown.forEach((label, i) => { label.textContent = labelText(state, state.views[i], form); });
      if (shown.every((label) => label.scrollWidth <= label.clientWidth)) break;
    }
    if (state.errors.length > this.#errorsSeen) {
      this.#fail(coded(new Error(state.errors.slice(this.#errorsSeen).join('\n')), 'render'));
      this.#errorsSeen = state.errors.length;
    }
    if (state.meter.transitions > this.#meterSeen) {
      this.#meterSeen = state.meter.transitions;
      this.#emit('meter', { popping: state.meter.popping, alpha: state.meter.alpha, geomorph: state.meter.geomorph });
    }
    return state;
  }

  // --- camera input: drag orbits, shift-drag / two fingers pan, wheel / pinch zoom, keys ---

  #camera(update) {
    if (!this.#viewer) return;
    const s = this.state();
    const next = {};
    if (update.yaw || update.pitch) {
      next.yaw = ((s.yaw + (update.yaw ?? 0) + 540) % 360) - 180;
      next.pitch = s.pitch + (update.pitch ?? 0);
    }
    if (update.pan) next.pan = [s.pan[0] + update.pan[0], s.pan[1] + update.pan[1]];
    if (update.zoom) { next.distanceMode = 'manual'; next.distance = Math.min(100, Math.max(0.2, s.distance * update.zoom)); }
    if (update.reset) next.resetCamera = true;
    this.setState(next); // queued by the viewer while a measurement holds it
    this.dispatchEvent(new CustomEvent('camerachange'));
  }

  // CSS pixels per framing distance in the plane looked at, so a pan moves the character with the
  // pointer: a view spans 2 tan(fovy / 2) × the camera distance (fovy from the viewer's state).
  #viewHeight() {
    const state = this.#lastState;
    const dpr = this.#canvas.width / this.#canvas.clientWidth || 1;
    const pixels = state?.views[0] ? state.views[0].rect[3] / dpr : this.#canvas.clientHeight;
    const span = 2 * Math.tan((state?.fovy ?? Math.PI / 4) / 2);
    return Math.max(1, pixels) / (span * (state?.distance ?? 1));
  }

  #wireInput() {
    const canvas = this.#canvas;
    if (canvas.dataset.wired) return;
    canvas.dataset.wired = '1';
    // WebGL2 tells the page, not wgpu, when the GPU takes its context away (a driver reset, too
    // many contexts): the canvas stays blank from then on. (WebGPU's device loss reaches
    // `state().errors` from the renderer.)
    canvas.addEventListener('webglcontextlost', () => {
      if (canvas !== this.#canvas) return;
      this.#broken = true;
      this.#fail(coded(new Error('The GPU took the viewer\'s WebGL2 context away (a driver reset, or too many 3D pages open); reload the page to draw again.'), 'render'));
    });
    const DEGREES_PER_PIXEL = 0.4;
    canvas.addEventListener('pointerdown', (e) => {
      this.#pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
      // Keeps the drag when the pointer leaves the canvas; a pointer the browser no longer
      // tracks (already lifted) cannot be captured, and the drag works without it.
      try { canvas.setPointerCapture(e.pointerId); } catch { /* not capturable */ }
    });
    const up = (e) => this.#pointers.delete(e.pointerId);
    canvas.addEventListener('pointerup', up);
    canvas.addEventListener('pointercancel', up);
    canvas.addEventListener('pointermove', (e) => {
      const last = this.#pointers.get(e.pointerId);
      if (!last) return;
      const dx = e.clientX - last.x;
      const dy = e.clientY - last.y;
      if (this.#pointers.size === 2) {
        const [a, b] = [...this.#pointers.values()];
        const other = a === last ? b : a;
        const before = Math.hypot(last.x - other.x, last.y - other.y);
        const after = Math.hypot(e.clientX - other.x, e.clientY - other.y);
        const viewHeight = this.#viewHeight();
        // The pinch's midpoint moves by half of this finger's motion: the view pans with it.
        if (before > 0 && after > 0) this.#camera({ zoom: before / after, pan: [-dx / 2 / viewHeight, dy / 2 / viewHeight] });
      } else if (e.shiftKey || e.buttons === 4 || e.buttons === 2) {
        const viewHeight = this.#viewHeight();
        this.#camera({ pan: [-dx / viewHeight, dy / viewHeight] });
      } else {
        this.#camera({ yaw: -dx * DEGREES_PER_PIXEL, pitch: dy * DEGREES_PER_PIXEL });
      }
      last.x = e.clientX;
      last.y = e.clientY;
    });
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.#camera({ zoom: Math.exp(e.deltaY * 0.001) });
    }, { passive: false });
    canvas.addEventListener('keydown', (e) => {
      const step = e.shiftKey ? 0.05 : 5;
      const keys = {
        ArrowLeft: e.shiftKey ? { pan: [-step, 0] } : { yaw: -step },
        ArrowRight: e.shiftKey ? { pan: [step, 0] } : { yaw: step },
        ArrowUp: e.shiftKey ? { pan: [0, step] } : { pitch: step },
        ArrowDown: e.shiftKey ? { pan: [0, -step] } : { pitch: -step },
        '+': { zoom: 1 / 1.1 }, '=': { zoom: 1 / 1.1 }, '-': { zoom: 1.1 }, '0': { reset: true }, Home: { reset: true },
      };
      const update = keys[e.key];
      if (!update) return;
      e.preventDefault();
      this.#camera(update);
    });
  }
}

if (!customElements.get('clod-viewer')) customElements.define('clod-viewer', ClodViewerElement);
