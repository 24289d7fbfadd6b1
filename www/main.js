// The viewer page: DOM wiring around one <clod-viewer> (www/clod-viewer.js). Loading, LOD,
// schedule, camera and drawing live in the Rust `Viewer`; this file forwards the controls to
// `setState`, shows the numbers, opens dropped or picked files, keeps the view in the URL, and
// saves screenshots.
//
// URL parameters: model (a .glb URL), clip, t (animation seconds; the page starts paused there),
// mode (the views' methods, e.g. `pop+morph`), backend (webgpu | webgl2), distance (× framing;
// turns the dolly off), lod (continuous triangle count), crowd (instances), settings (`realistic`:
// the engine's defaults; absent or `demonstration`: the exaggerated demonstration the page opens
// with, see `state().preset`), and the settings moved off that preset under setState's keys
// (`viewer.link()`, docs/viewer.md); test=1 draws only on request, starts on the realistic
// settings unless `settings` says otherwise, and exposes window.__clod for the browser tests.

const params = new URLSearchParams(location.search);
const testMode = params.get('test') === '1';
const html = document.documentElement;
const viewer = document.getElementById('viewer');
const status = document.getElementById('status');
const stats = document.getElementById('stats');
const controls = document.getElementById('controls');
const $ = (id) => document.getElementById(id);

let loaded = false;
let clips = [];
let spike = null;
let measuring = false;
// The URL's `lod` (a continuous triangle count), applied once the levels are there.
let deferredLod = null;

// --- start-up from the URL ----------------------------------------------------------------------

if (testMode) viewer.setAttribute('manual-frames', '');
// The page opens on the demonstration; the tests' pages on the realistic defaults they measure.
const pagePreset = testMode ? 'realistic' : 'demonstration';
const preset = params.get('settings') ?? pagePreset;
viewer.setAttribute('preset', preset === 'realistic' ? 'realistic' : 'demonstration');
if (params.get('backend')) viewer.setAttribute('backend', params.get('backend'));
if (params.get('mode')) viewer.setAttribute('modes', params.get('mode'));
if (params.get('clip')) viewer.setAttribute('clip', params.get('clip'));
if (params.has('t') || testMode) viewer.removeAttribute('autoplay');
if (params.get('model')) viewer.setAttribute('src', params.get('model'));
if (params.get('crowd')) { viewer.setAttribute('mode', 'crowd'); viewer.setAttribute('count', params.get('crowd')); }
// The element starts loading when it is defined: only now, with the URL's attributes set.
const { METHOD_COLORS, drawReplay } = await import('./clod-viewer.js');

viewer.addEventListener('progress', (e) => {
  const { phase, fraction } = e.detail;
  if (!loaded || html.dataset.state === 'loading') {
    status.textContent = `${{ fetch: 'Downloading', build: 'Building the LOD chain', gpu: 'Starting the GPU', ready: 'Ready' }[phase]}… ${Math.round(100 * fraction)} %`;
  } else if (phase === 'build') {
    $('stat-lod-build')?.replaceChildren(`building the levels… ${Math.round(100 * fraction)} % (full detail meanwhile)`);
  }
});

viewer.addEventListener('load', (e) => {
  const state = e.detail;
  const first = !loaded;
  loaded = true;
  spike = null;
  setupControls(state, first);
  status.textContent = `${state.name}: ${state.triangles.toLocaleString()} triangles, ${state.joints} joints, ` +
    `drawn with ${state.backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}.`;
  if (first) applyUrlState();
  html.dataset.state = 'ready';
  html.dataset.lod = state.lodFrom ? 'ready' : 'pending';
  showPreset(state);
  showStats();
});

// The levels arrive after the first frame (built in the worker, or from the cache).
viewer.addEventListener('lod', (e) => {
  html.dataset.lod = 'ready';
  if (deferredLod !== null) {
    try { viewer.setState({ continuousTriangles: deferredLod }); } catch (err) { status.textContent += ` Ignored from the URL: lod: ${err.message}.`; }
    deferredLod = null;
  }
  syncControls(e.detail);
  showStats();
});

viewer.addEventListener('error', (e) => {
  // A failed replacement leaves the previous model playing: the page stays ready.
  if (!loaded) {
    html.dataset.state = 'error';
    status.textContent = 'The viewer could not start.';
  }
  html.dataset.lastError = e.detail.message;
});

// Each URL value on its own: one that does not fit the model shown is ignored, and said so.
function applyUrlState() {
  const updates = [];
  if (params.has('t')) updates.push(['t', { time: Number(params.get('t')), paused: true }]);
  if (params.has('distance')) updates.push(['distance', { distanceMode: 'manual', distance: Number(params.get('distance')) }]);
  if (params.has('lod')) {
    if (viewer.state().lodFrom) updates.push(['lod', { continuousTriangles: Number(params.get('lod')) }]);
    else deferredLod = Number(params.get('lod'));
  }
  // The settings the link carries (threshold, magnifier, speeds, overlay, meter, camera, …).
  const ignored = [...(viewer.ignoredSettings ?? []), ...viewer.applyLink([...params])];
  for (const [name, state] of updates) {
    try { viewer.setState(state); } catch (e) { ignored.push(`${name}: ${e.message}`); }
  }
  if (ignored.length) {
    status.textContent += ` Ignored from the URL: ${ignored.join('; ')}.`;
    writeUrl(); // the link now says what is shown
  }
  syncControls(viewer.state());
}

// --- controls -----------------------------------------------------------------------------------

function set(state) {
  try {
    viewer.setState(state);
    writeUrl();
    showPreset(viewer.state());
  } catch (e) {
    status.textContent = e.message;
  }
}

// --- the preset: what the demonstration exaggerates, and the one control to leave it --------------

const PRESET_WORDS = {
  tolerance: (v) => `a ${v} px threshold`,
  magnify: (v) => (v > 1 ? `magnified ×${v}` : 'real size'),
  transitionSpeed: (v) => (v < 1 ? `transitions slowed to ×${v}` : 'real-time transitions'),
  dollyPeriod: (v) => `a dolly of ${v} s`,
};

// Says which settings are in force and what the demonstration exaggerates (the values come from
// `state().preset`), and offers the other preset.
function showPreset(state) {
  const p = state.preset;
  const toggle = $('preset-toggle');
  const words = (which) => p.values.map((v) => PRESET_WORDS[v.key]?.(v[which]) ?? `${v.key} ${v[which]}`).join(', ');
  let text;
  if (p.name === 'demonstration') {
    // The demonstration's threshold scales with the view: say what it is in this one.
    const shown = (v) => (v.key === 'tolerance' ? `a ${p.tolerancePx.toFixed(1)} px threshold (${v.demonstration} px per 400 px of view height)` : PRESET_WORDS[v.key]?.(v.demonstration));
    text = `Exaggerated for demonstration: ${p.values.map((v) => `${shown(v)} (realistic: ${PRESET_WORDS[v.key]?.(v.realistic)})`).join(', ')}, ` +
      'and the difference from full detail tinted (magenta: outline, amber: shading). The views still differ only in the transition method.';
  } else if (p.name === 'realistic') {
    text = `Realistic settings: ${words('realistic')}. At these settings the level changes stay below a pixel: good LOD shows nothing.`;
  } else {
    text = `Your own settings: ${words('value')}.`;
  }
  $('preset-text').textContent = text;
  toggle.hidden = false;
  toggle.dataset.to = p.name === 'demonstration' ? 'realistic' : 'demonstration';
  toggle.textContent = p.name === 'demonstration' ? 'Show realistic settings' : 'Show the exaggerated demonstration';
  html.dataset.preset = p.name ?? 'custom';
  syncPresetControls(state);
}

// The controls a preset moves follow it.
function syncPresetControls(state) {
  $('tolerance').value = state.preset.values.find((v) => v.key === 'tolerance').value;
  $('tolerance-out').textContent = `${$('tolerance').value} px`;
  $('magnify').value = String(state.magnify);
  $('transition-speed').value = String(state.transitionSpeed);
  $('overlay').value = state.overlay;
}

function setupControls(state, first) {
  controls.hidden = false;
  clips = state.clips.map((name, i) => ({ name, duration: state.clipDurations[i] }));
  $('clip').replaceChildren(...clips.map((c, i) => new Option(c.name, i)));
  $('clip').disabled = clips.length === 0;
  $('measure').disabled = false;
  if (!first) { $('continuous-on').checked = false; $('continuous').disabled = true; $('continuous-out').textContent = ''; }
  syncControls(state);
  syncSettingControls(state);
}

// Puts the controls where the viewer's state says (after a load, the URL or a camera gesture).
function syncControls(state) {
  if (state.clip !== null) $('clip').value = state.clip;
  $('play').textContent = state.paused ? 'Play' : 'Pause';
  $('play').setAttribute('aria-pressed', String(state.paused));
  $('dolly').checked = state.distanceMode === 'dolly';
  $('distance').value = Math.log(Math.max(1, state.distance)) / Math.log(100);
  $('distance-out').textContent = `${state.distance.toFixed(1)}×`;
  $('crowd-on').checked = state.mode === 'crowd';
  if (state.crowd) showCrowdCount(state.crowd.instances);
}

// The select offers a few counts; a link or the element may ask for any other (1 to 4,096): it
// gets an option of its own, in order, rather than a blank select.
function showCrowdCount(instances) {
  const select = $('crowd-count');
  const value = String(instances);
  if (![...select.options].some((o) => o.value === value)) {
    const option = new Option(instances.toLocaleString('en-US'), value);
    select.add(option, [...select.options].find((o) => Number(o.value) > instances) ?? null);
  }
  select.value = value;
}

// After a load: the settings the new model kept (or, after a failure, started afresh), as they are.
function syncSettingControls(state) {
  $('speed').value = String(state.speed);
  $('speed-out').textContent = `${state.speed.toFixed(2)}×`;
  $('transition').value = state.transition;
  $('duration').value = String(state.duration);
  $('duration-out').textContent = `${Number(state.duration.toFixed(2))} s`;
  $('zone').value = String(state.zone);
  $('variant').value = state.variant;
  $('meter-on').checked = state.meter.on;
  $('flip-on').checked = state.meter.flipOn;
}

// Log-scale sliders: 0..1 maps to lo..hi geometrically.
const logScale = (x, lo, hi) => lo * (hi / lo) ** x;

function wireControls() {
  $('play').addEventListener('click', () => {
    const paused = !viewer.state().paused;
    set({ paused });
    syncControls(viewer.state());
  });
  $('clip').addEventListener('change', (e) => set({ clip: clips[Number(e.target.value)].name, time: 0 }));
  $('scrub').addEventListener('input', (e) => {
    const clip = clips[viewer.state().clip];
    if (clip) set({ time: Number(e.target.value) * clip.duration, paused: true });
    syncControls(viewer.state());
  });
  $('speed').addEventListener('input', (e) => {
    $('speed-out').textContent = `${Number(e.target.value).toFixed(2)}×`;
    set({ speed: Number(e.target.value) });
  });
  $('dolly').addEventListener('change', (e) => set({ distanceMode: e.target.checked ? 'dolly' : 'manual' }));
  $('distance').addEventListener('input', (e) => {
    const d = logScale(Number(e.target.value), 1, 100);
    set({ distanceMode: 'manual', distance: d });
    syncControls(viewer.state());
  });
  $('reset-camera').addEventListener('click', () => { set({ resetCamera: true }); syncControls(viewer.state()); });
  $('tolerance').addEventListener('input', (e) => {
    $('tolerance-out').textContent = `${e.target.value} px`;
    set({ tolerance: Number(e.target.value) });
  });
  $('transition').addEventListener('change', (e) => set({ transition: e.target.value }));
  $('duration').addEventListener('input', (e) => {
    $('duration-out').textContent = `${e.target.value} s`;
    set({ duration: Number(e.target.value) });
  });
  $('zone').addEventListener('input', (e) => set({ zone: Number(e.target.value) }));
  $('transition-speed').addEventListener('change', (e) => set({ transitionSpeed: Number(e.target.value) }));
  $('magnify').addEventListener('change', (e) => set({ magnify: Number(e.target.value) }));
  $('meter-on').addEventListener('change', (e) => set({ meter: e.target.checked }));
  $('flip-on').addEventListener('change', (e) => set({ flip: e.target.checked }));
  $('variant').addEventListener('change', (e) => set({ variant: e.target.value }));
  $('overlay').addEventListener('change', (e) => set({ overlay: e.target.value }));
  const crowd = () => set({ mode: $('crowd-on').checked ? 'crowd' : 'single', count: Number($('crowd-count').value) });
  $('crowd-on').addEventListener('change', crowd);
  $('crowd-count').addEventListener('change', crowd);
  const continuous = () => {
    const on = $('continuous-on').checked;
    $('continuous').disabled = !on;
    const max = viewer.state().maxTriangles;
    const triangles = on ? Math.max(1, Math.round(logScale(Number($('continuous').value), 16, Math.max(16, max)))) : null;
    set({ continuousTriangles: triangles });
    $('continuous-out').textContent = on ? `${viewer.state().continuousTriangles.toLocaleString()} triangles` : '';
  };
  $('continuous-on').addEventListener('change', continuous);
  $('continuous').addEventListener('input', continuous);
  $('preset-toggle').addEventListener('click', (e) => set({ preset: e.target.dataset.to }));
  viewer.addEventListener('meter', showReplay);
  $('replay-png').addEventListener('click', async () => {
    const blob = await viewer.replayPng();
    if (!blob) return;
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `clod-viewer-replay-${new Date().toISOString().slice(0, 19).replaceAll(':', '-')}.png`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
  });
  $('file').addEventListener('change', (e) => openFiles([...e.target.files]));
  $('screenshot').addEventListener('click', screenshot);
  $('measure').addEventListener('click', measureSpike);
  $('share').addEventListener('click', async () => {
    writeUrl();
    try { await navigator.clipboard.writeText(location.href); status.textContent = 'Link copied.'; } catch { status.textContent = location.href; }
  });
  viewer.addEventListener('camerachange', () => { syncControls(viewer.state()); writeUrl(); });
}

// --- files --------------------------------------------------------------------------------------

// Picks so far: a pick whose files are still being read when a newer one arrives gives way, so
// the file picked last is the one shown even when an earlier, larger file reads slower.
let picks = 0;

/**
 * Opens picked or dropped files: one `.glb`, or one `.gltf` with the buffers and images it names
 * (matched by file name).
 */
async function openFiles(files) {
  const pick = ++picks;
  const main = files.find((f) => /\.(glb|gltf)$/i.test(f.name)) ?? (files.length === 1 ? files[0] : null);
  if (!main) {
    showFailure(`No .glb or .gltf among ${files.map((f) => f.name).join(', ')}`);
    return;
  }
  const resources = new Map();
  for (const f of files) if (f !== main) resources.set(f.name, new Uint8Array(await f.arrayBuffer()));
  const bytes = new Uint8Array(await main.arrayBuffer());
  if (pick !== picks) return;
  status.textContent = `Opening ${main.name}…`;
  try {
    await viewer.load({ name: main.name, bytes, resources });
    params.delete('model');
    writeUrl();
  } catch (e) {
    if (!e.superseded) showFailure(e.message ?? String(e)); // a newer file is on its way
  }
}

function showFailure(message) {
  status.textContent = loaded ? 'That file could not be shown; the previous model is still playing.' : 'The viewer could not start.';
  html.dataset.lastError = message;
  const alert = viewer.querySelector('[role=alert]');
  alert.textContent = message;
  alert.hidden = false;
}

function wireDrop() {
  const hint = $('drop-hint');
  let depth = 0;
  document.addEventListener('dragenter', (e) => { e.preventDefault(); depth++; hint.hidden = false; });
  document.addEventListener('dragleave', () => { if (--depth <= 0) { depth = 0; hint.hidden = true; } });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    hint.hidden = true;
    openFiles([...e.dataTransfer.files]);
  });
}

// --- numbers, URL, screenshot, pop spike -----------------------------------------------------------

function showStats() {
  if (!loaded) return;
  const s = viewer.state();
  const levels = s.levels.map((l, i) => `${i}: ${l.triangles.toLocaleString()}`).join(' · ');
  // In crowd mode each instance has its own level (the Crowd row counts them): a view's level
  // would be the single character's, which is not drawn.
  // The continuous slider's states are no level a reader knows (levels.length and one more).
  const morph = (v) => (v.to !== v.level ? `, t ${v.t.toFixed(2)}` : '');
  const level = (v) => {
    if (s.crowd) return '';
    return s.continuousTriangles !== null ? ` (continuous${morph(v)})` : ` (level ${v.level}${morph(v) && ` → ${v.to}${morph(v)}`})`;
  };
  const views = s.views.map((v) => `${v.method} ${v.triangles.toLocaleString()}${level(v)}`).join(' · ');
  const rows = [
    ['Drawn', views],
    ['Levels', s.levelsStop ? `${levels} (${s.levelsStop})` : levels],
    ['LOD build', lodBuildText(s)],
    ['Frame', viewer.frameMs ? `${viewer.frameMs.toFixed(1)} ms` : '–'],
    ['Backend', [s.backend === 'webgpu' ? 'WebGPU' : 'WebGL2', s.adapter, `MSAA ${s.msaa}×`].filter(Boolean).join(' · ')],
    ['Pop spike', spike ? formatSpike(spike) : measuring ? 'measuring…' : 'press “Measure pop spike” (the views pause for a few seconds)'],
  ];
  if (s.crowd) rows.splice(1, 0, ['Crowd', crowdText(s.crowd)]);
  if (s.crowd && s.meter.on && s.meter.changes.length) {
    // Many transitions at once: how much each view's difference from full detail jumps between
    // frames (popping's peak is a whole change in one frame; a geomorph spreads it).
    rows.splice(2, 0, ['Crowd meter', s.meter.changes.map((c, i) =>
      `${s.views[i]?.method}: silhouette ${c.silhouettePerSecond.toFixed(2)} %/s (peak ${c.silhouettePeak.toFixed(3)} % in a frame)`).join(' · ')]);
  }
  if (s.warnings.length) rows.push(['Warnings', s.warnings.join('; ')]);
  rows.push(['Meter', s.meter.on ? `measured at ${s.meter.size.join(' × ')} px per view, ${s.meter.transitions} transitions` : 'off']);
  if (s.meter.on) {
    rows.push(['FLIP', s.meter.flip
      ? `LDR-FLIP against full detail, mean per view at ${s.meter.flip.ppd.toFixed(1)} px per degree (the meter's picture when the view is seen at 67 px per degree): ${s.views.map((v, i) => `${v.method} ${(s.meter.flip.views[i] ?? 0).toFixed(4)}`).join(' · ')}`
      : !s.meter.flipOn ? 'off'
        : s.crowd ? 'not measured in crowd mode (the crowd meter compares silhouettes and shading)'
          : 'not measured (this GPU cannot render into float targets, or nothing to compare yet)']);
  }
  drawMeterChart();
  // A crowd has no single transition to tabulate: its numbers are the Crowd meter row.
  $('meter-table').hidden = Boolean(s.crowd);
  showMeterTable(s.meter);
  stats.replaceChildren(...rows.flatMap(([k, v]) => [
    Object.assign(document.createElement('dt'), { textContent: k }),
    Object.assign(document.createElement('dd'), { textContent: v, id: `stat-${k.toLowerCase().replaceAll(' ', '-')}` }),
  ]));
  if (s.distanceMode === 'dolly' && document.activeElement !== $('distance')) syncControls(s);
  const clip = clips[s.clip];
  if (clip && clip.duration > 0 && document.activeElement !== $('scrub')) {
    $('scrub').value = (s.animTime % clip.duration) / clip.duration;
    $('scrub-out').textContent = `${(s.animTime % clip.duration).toFixed(2)} s`;
  }
}

function crowdText(c) {
  const perLevel = c.perLevel.map((n, i) => `L${i} ${n}`).join(' · ');
  const share = c.trianglesFull ? (100 * c.trianglesDrawn / c.trianglesFull).toFixed(1) : '–';
  return `${c.drawn.toLocaleString()} of ${c.instances.toLocaleString()} instances drawn (${perLevel}) · ` +
    `${c.transitions} in transition · ${c.trianglesDrawn.toLocaleString()} triangles, ${share} % of full detail`;
}

function lodBuildText(s) {
  const ms = `${Math.round(s.buildMs).toLocaleString()} ms`;
  switch (s.lodFrom) {
    case 'build': return `${ms} (worker)`;
    case 'cache': return `from the cache (built in ${ms} on a first visit)`;
    case 'inline': return `${ms} (main thread)`;
    default: return 'building the levels… (full detail meanwhile)';
  }
}

function formatSpike(r) {
  const pop = r.popping;
  const pct = (x) => (pop > 0 ? ` (${((100 * x) / pop).toFixed(0)} % of popping)` : '');
  const parts = [
    pop !== null && `popping ${pop.toFixed(2)}`,
    r.alpha !== null && `alpha-blend, ${r.variant}: ${r.alpha.toFixed(2)}${pct(r.alpha)}`,
    r.geomorph !== null && `geomorph ${r.geomorph.toFixed(2)}${pct(r.geomorph)}`,
  ].filter(Boolean);
  return `${parts.join(' · ')} — largest frame-to-frame change through the switch to level ${r.level}, mean |ΔRGB| per pixel`;
}

async function measureSpike() {
  if (measuring || !loaded) return;
  measuring = true;
  $('measure').disabled = true;
  try {
    spike = await viewer.measurePopSpike();
  } catch (e) {
    if (!e.superseded) status.textContent = `Pop spike: ${e.message ?? e}`; // else another model is shown
  } finally {
    measuring = false;
    $('measure').disabled = false;
    showStats();
  }
}

// --- the live transition meter ---------------------------------------------------------------------

// The film strip of the last transition, drawn again when the meter completes another.
function showReplay() {
  const replay = viewer.replay();
  $('replay').hidden = !replay;
  if (!replay) return;
  drawReplay($('replay-strip'), replay);
}

// Draws the meter's last ten seconds: each view's silhouette difference from the reference (% of
// pixels), one line per method, with a tick where each transition starts.
function drawMeterChart() {
  const canvas = $('meter-chart');
  const ctx = canvas.getContext('2d');
  const { methods, samples } = viewer.meterHistory();
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (samples.length < 2) return;
  const t1 = samples.at(-1)[0];
  const t0 = t1 - 10;
  const top = Math.max(0.5, ...samples.flatMap((s) => methods.map((_, i) => s[2 + 2 * i])));
  const x = (t) => ((t - t0) / 10) * canvas.width;
  const y = (v) => canvas.height - 4 - (v / top) * (canvas.height - 16);
  ctx.strokeStyle = 'rgb(255 255 255 / 0.35)';
  for (let k = 1; k < samples.length; k++) {
    if (samples[k][1] && !samples[k - 1][1]) { ctx.beginPath(); ctx.moveTo(x(samples[k][0]), 0); ctx.lineTo(x(samples[k][0]), canvas.height); ctx.stroke(); }
  }
  methods.forEach((method, i) => {
    ctx.strokeStyle = METHOD_COLORS[method];
    ctx.beginPath();
    samples.forEach((s, k) => (k ? ctx.lineTo : ctx.moveTo).call(ctx, x(s[0]), y(s[2 + 2 * i])));
    ctx.stroke();
  });
  ctx.fillStyle = '#fff';
  ctx.font = '11px system-ui, sans-serif';
  ctx.fillText(`silhouette difference from full detail, 0–${top.toFixed(1)} % of pixels, last 10 s`, 6, 12);
}

function showMeterTable(meter) {
  const rows = ['popping', 'alpha', 'geomorph'].map((method) => {
    const m = meter[method];
    const flip = meter.flip?.pop?.[method];
    const cells = m ? [m.silhouette.toFixed(3), m.shading.toFixed(2), flip == null ? '–' : flip.toFixed(4), m.uncontrolled.silhouette.toFixed(3)] : ['–', '–', '–', '–'];
    const tr = document.createElement('tr');
    tr.dataset.method = method;
    tr.append(Object.assign(document.createElement('th'), { textContent: method, style: `color: ${METHOD_COLORS[method]}` }),
      ...cells.map((c) => Object.assign(document.createElement('td'), { textContent: c })));
    return tr;
  });
  $('meter-table').tBodies[0].replaceChildren(...rows);
}

let urlTimer = 0;
function writeUrl() {
  clearTimeout(urlTimer);
  urlTimer = setTimeout(() => {
    if (!loaded) return;
    const s = viewer.state();
    const next = new URLSearchParams();
    if (params.get('model')) next.set('model', params.get('model'));
    if (s.clip !== null && clips[s.clip]) next.set('clip', clips[s.clip].name);
    next.set('t', s.animTime.toFixed(2));
    next.set('mode', s.views.map((v) => ({ popping: 'pop', alpha: 'blend', geomorph: 'morph' }[v.method])).join('+'));
    if (params.get('backend')) next.set('backend', params.get('backend'));
    if (s.distanceMode === 'manual') next.set('distance', s.distance.toFixed(2));
    if (s.continuousTriangles) next.set('lod', s.continuousTriangles);
    if (s.crowd) next.set('crowd', s.crowd.instances);
    // The preset, unless it is the page's default, and the settings that differ from it.
    const link = viewer.link();
    if (link.preset !== pagePreset) next.set('settings', link.preset);
    for (const [key, value] of link.pairs) next.set(key, value);
    if (testMode) next.set('test', '1');
    history.replaceState(null, '', `?${next.toString().replaceAll('%2B', '+')}`);
  }, 300);
}

async function screenshot() {
  try {
    const blob = await viewer.screenshot();
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `clod-viewer-${new Date().toISOString().slice(0, 19).replaceAll(':', '-')}.png`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
  } catch (e) {
    status.textContent = `Screenshot: ${e.message ?? e}`;
  }
}

// The browser tests' hook: deterministic frames on request, pixels read back by the renderer.
function exposeTestHook() {
  window.__clod = {
    setState: (state) => viewer.setState(state),
    renderFrame: (nowMs) => viewer.renderFrame(nowMs),
    readPixels: () => viewer.readPixels(),
    textureLevels: (i) => viewer.textureLevels(i),
    finish: () => viewer.finish(),
    state: () => viewer.state(),
    measurePopSpike: (options) => viewer.measurePopSpike(options),
    flipImages: (reference, test, width, height, ppd) => viewer.flipImages(reference, test, width, height, ppd),
    replay: () => viewer.replay(),
    replayPng: async () => {
      const blob = await viewer.replayPng();
      return blob && { size: blob.size, type: blob.type, head: [...new Uint8Array(await blob.slice(0, 8).arrayBuffer())] };
    },
    load: (name, bytes) => viewer.load({ name, bytes, resources: null }),
  };
}

wireControls();
wireDrop();
if (testMode) exposeTestHook();
if (!testMode) setInterval(showStats, 250);
