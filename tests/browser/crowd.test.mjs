// (9) Crowd mode: the character instanced on the ground, each instance with its own level and
// transitions (src/render/crowd/). On WebGPU and WebGL2: the crowd draws, every view shows
// instances at several levels at once (read back: the level overlay's colours), the per-level
// counts add up to the instances drawn, and views forced to one method are the same picture; the
// crowd meter's changes leave out the frame the crowd came on, and it has no FLIP numbers (not the
// single character's last ones).
// A small page and a small crowd: SwiftShader draws a few hundred thousand triangles per second.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, step, readPixels, crop, clock, savePng, decodePixels, SMALL_VIEWPORT } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// The level overlay's colours (src/render/overlay.rs LEVEL_COLORS), linear RGB.
const LEVEL_COLORS = [
  [0.10, 0.30, 0.90], [0.95, 0.40, 0.05], [0.10, 0.70, 0.15], [0.85, 0.08, 0.10],
  [0.50, 0.20, 0.80], [0.95, 0.85, 0.10], [0.05, 0.75, 0.80], [0.95, 0.45, 0.70],
];

function hue([r, g, b]) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max - min < 1e-6) return null;
  let h;
  if (max === r) h = ((g - b) / (max - min)) % 6;
  else if (max === g) h = (b - r) / (max - min) + 2;
  else h = (r - g) / (max - min) + 4;
  return (h * 60 + 360) % 360;
}

const LEVEL_HUES = LEVEL_COLORS.map(hue);

// Pixels of an RGB crop (`crop`'s three bytes per pixel) whose hue is within 10° of a level colour's (saturated pixels only: the
// grey background and unlit shadows do not count), per level.
function levelPixels(rgb, levels) {
  const counts = new Array(levels).fill(0);
  for (let i = 0; i < rgb.length; i += 3) {
    const c = [rgb[i] / 255, rgb[i + 1] / 255, rgb[i + 2] / 255];
    const max = Math.max(...c);
    if (max < 0.2 || (max - Math.min(...c)) / max < 0.45) continue;
    const h = hue(c);
    let best = -1;
    let bestDistance = 10;
    for (let l = 0; l < levels; l++) {
      const d = Math.min(Math.abs(h - LEVEL_HUES[l]), 360 - Math.abs(h - LEVEL_HUES[l]));
      if (d < bestDistance) { best = l; bestDistance = d; }
    }
    if (best >= 0) counts[best]++;
  }
  return counts;
}

// A crowd at rest: the camera still at the crowd's front, the animation paused, a strict
// threshold so that the rows span several levels in a view of this size.
const CROWD = { mode: 'crowd', count: 120, overlay: 'levels', meter: false, tolerance: 0.1, paused: true, time: 0.3, distanceMode: 'manual' };

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: the crowd draws instances at several levels in every view, and its counts add up`, async () => {
    const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
    const c = clock();
    let state = await frame(page, c.now, CROWD);
    // Let any transition from the first frame finish.
    for (let i = 0; i < 3; i++) state = await frame(page, c.tick(400));
    assert.equal(state.errors.length, 0, state.errors.join('\n'));
    assert.equal(state.mode, 'crowd');
    assert.equal(state.backend, backend);
    const crowd = state.crowd;
    assert.equal(crowd.instances, 120);
    assert.ok(crowd.drawn > 0 && crowd.drawn < crowd.instances, `frustum culling keeps some, not all: ${crowd.drawn}`);
    assert.equal(crowd.perLevel.reduce((a, b) => a + b, 0), crowd.drawn, `per level ${crowd.perLevel} vs ${crowd.drawn} drawn`);
    const occupied = crowd.perLevel.map((n, l) => [n, l]).filter(([n]) => n > 0).map(([, l]) => l);
    assert.ok(occupied.length >= 3, `instances at ${occupied.length} levels: ${crowd.perLevel}`);
    assert.ok(crowd.trianglesDrawn * 3 < crowd.trianglesFull, `LOD draws ${crowd.trianglesDrawn} of ${crowd.trianglesFull} triangles`);
    const pixels = await readPixels(page);
    await savePng(`/tmp/clod-crowd-${backend}.png`, pixels);
    for (const view of state.views) {
      const counts = levelPixels(crop(pixels, view.rect), state.levels.length);
      const seen = occupied.filter((l) => counts[l] >= 20);
      assert.ok(seen.length >= 2, `${view.method} view shows levels ${seen} (pixels per level colour ${counts}; occupied ${occupied})`);
      // Shading moves some hues towards a neighbouring level's colour: the occupied levels'
      // colours must still be most of what is seen.
      const total = counts.reduce((a, b) => a + b, 0);
      const inOccupied = occupied.reduce((a, l) => a + counts[l], 0);
      assert.ok(inOccupied > 0.7 * total, `${view.method}: ${inOccupied} of ${total} tinted pixels in the occupied levels' colours (${counts})`);
    }
    // Back to the single character: the crowd's state is gone.
    state = await frame(page, c.tick(100), { mode: 'single' });
    assert.equal(state.crowd, null);
    await page.close();
  });
}

test('webgpu: crowd views forced to one method are the same picture, mid-transitions', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const c = clock();
  // A fast dolly and slow transitions: many instances change level within a few frames.
  let state = await frame(page, c.now, { ...CROWD, overlay: 'none', distanceMode: 'dolly', dollyPeriod: 4, duration: 3, transition: 'time' });
  for (let i = 0; i < 40 && state.crowd.transitions < 3; i++) state = await frame(page, c.tick(150));
  assert.ok(state.crowd.transitions >= 3, `transitions running: ${state.crowd.transitions}`);
  for (const [method, variant] of [['geomorph', 'opaque-first'], ['alpha', 'opaque-first'], ['alpha', 'dither'], ['popping', 'opaque-first']]) {
    // The same clock time: nothing moves, only the method changes.
    state = await frame(page, c.now, { methods: [method, method, method], variant });
    const pixels = await readPixels(page);
    const [a, b, d] = state.views.map((v) => crop(pixels, v.rect));
    let differing = 0;
    for (let i = 0; i < a.length; i++) if (a[i] !== b[i] || a[i] !== d[i]) differing++;
    assert.equal(differing, 0, `${method} (${variant}): ${differing} channel values differ between the views`);
  }
  // And the methods differ from one another while transitions run (the comparison shows something).
  state = await frame(page, c.now, { methods: ['popping', 'alpha', 'geomorph'], variant: 'opaque-first' });
  const pixels = await readPixels(page);
  const [pop, , morph] = state.views.map((v) => crop(pixels, v.rect));
  let changed = 0;
  for (let i = 0; i < pop.length; i++) if (pop[i] !== morph[i]) changed++;
  assert.ok(changed > 0, 'popping and geomorphing draw different pictures mid-transition');
  await page.close();
});

test('crowd.html: the docs page with a crowd element loads, draws the crowd and shows its numbers', async (t) => {
  const page = await browser.newPage({ viewport: { width: 700, height: 600 }, deviceScaleFactor: 1 });
  t.after(() => page.close());
  const logs = [];
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  await page.addInitScript(() => {
    window.__events = [];
    for (const type of ['load', 'lod', 'error']) {
      document.addEventListener(type, (e) => { if (e.target.localName === 'clod-viewer') window.__events.push(type); }, true);
    }
  });
  await page.goto(new URL('crowd.html', (await import('./helpers.mjs')).baseUrl).href);
  await page.waitForFunction(() => window.__events.includes('lod') || window.__events.includes('error'), null, { timeout: 180_000 });
  assert.ok(!(await page.evaluate(() => window.__events)).includes('error'), logs.join('\n'));
  const { state, encoded } = await page.evaluate(async () => {
    const el = document.getElementById('crowd');
    el.pause();
    const state = el.renderFrame(performance.now());
    return { state, encoded: window.__encodePixels(await el.readPixels()) };
  });
  const pixels = decodePixels(encoded);
  assert.equal(state.mode, 'crowd');
  assert.equal(state.crowd.instances, 400);
  assert.equal(state.crowd.perLevel.reduce((a, b) => a + b, 0), state.crowd.drawn);
  for (const view of state.views) {
    const rgb = crop(pixels, view.rect);
    // Sky and ground are greys: saturated pixels are characters (the built-in one wears blue).
    let lit = 0;
    for (let i = 0; i < rgb.length; i += 3) {
      const max = Math.max(rgb[i], rgb[i + 1], rgb[i + 2]);
      if (max > 40 && (max - Math.min(rgb[i], rgb[i + 1], rgb[i + 2])) / max > 0.3) lit++;
    }
    assert.ok(lit > 0.02 * (rgb.length / 3), `${view.method}: ${lit} crowd pixels`);
  }
  await page.waitForFunction(() => /instances in view/.test(document.getElementById('numbers').textContent), null, { timeout: 10_000 });
  assert.deepEqual(logs, []);
});

test('webgpu: the crowd meter compares crowd frames only: turning the crowd on is no change of the crowd\'s; it reports no FLIP', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const c = clock();
  // Paused at a fixed distance: one crowd frame draws what the one before drew.
  // A small crowd: the meter's reference is every instance at full detail.
  let state = await step(page, c.now, { meter: true, flip: false, paused: true, time: 0.3, distanceMode: 'manual', tolerance: 0.1, count: 16 });
  state = await step(page, c.tick(100));
  state = await step(page, c.tick(100), { mode: 'crowd' });
  for (let i = 0; i < 3; i++) state = await step(page, c.tick(100));
  assert.equal(state.mode, 'crowd');
  // The history spans the switch: every view's difference from full detail jumped there.
  const { samples } = await page.evaluate(() => document.getElementById('viewer').meterHistory());
  const peaks = state.meter.changes.map((change) => change.silhouettePeak);
  state.views.forEach((_, v) => {
    const series = samples.map((s) => s[2 + 2 * v]);
    const jump = Math.max(...series.slice(1).map((x, i) => Math.abs(x - series[i])));
    console.log(`view ${v}: the switch moved the difference by ${jump.toFixed(4)} %, the crowd meter's peak ${peaks[v].toFixed(4)} %`);
    assert.ok(jump > 0.01, `the crowd changes the picture: ${series}`);
    assert.ok(peaks[v] <= 0.25 * jump, `view ${v}: the crowd's peak ${peaks[v]} % is the switch's ${jump} %`);
  });
  // The single character at its coarsest level (switch distances scale as 1 / tolerance), so
  // every view differs from full detail, with FLIP on: the meter has FLIP numbers. In crowd mode
  // again it has none, not the single character's last ones.
  const k = state.levels.length - 1;
  state = await step(page, c.tick(100), { mode: 'single', flip: true, distance: 1 });
  state = await step(page, c.tick(100), { duration: 0, tolerance: 0.1 * state.switch[k] / 0.5 });
  for (let i = 0; i < 2; i++) state = await step(page, c.tick(100));
  assert.deepEqual(state.views.map((v) => v.level), [k, k, k]);
  assert.ok(state.meter.flip?.views.length === 3, `FLIP in single mode: ${JSON.stringify(state.meter.flip)}`);
  state = await step(page, c.tick(100), { mode: 'crowd' });
  state = await step(page, c.tick(100));
  assert.equal(state.meter.flip, null);
  await page.close();
});
