// (1) The page starts, says which backend runs, and all three views show the character.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, readPixels, crop, foregroundFraction, meanAbsDiff, savePng, SMALL_VIEWPORT, FINEST_TOLERANCE, viewChanges, baseUrl } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

test('every view shows the character, labelled with its level, triangles and t', async () => {
  const page = await openPage(browser);
  const state = await frame(page, 1000, { paused: true, time: 0.4 });
  assert.equal(state.backend, 'webgpu');
  assert.equal(state.errors.length, 0, state.errors.join('\n'));
  const pixels = await readPixels(page);
  await savePng('/tmp/clod-views.png', pixels);
  state.views.forEach((view, i) => {
    const fraction = foregroundFraction(crop(pixels, view.rect));
    // The character covers about a tenth of a framed view; 3 % leaves room for thin poses.
    assert.ok(fraction > 0.03, `view ${i} (${view.method}) is nearly empty: ${fraction}`);
  });
  const labels = await page.$$eval('.label', (ls) => ls.map((l) => ({ ...l.dataset, text: l.textContent })));
  assert.deepEqual(labels.map((l) => l.method), ['popping', 'alpha', 'geomorph']);
  for (const [i, l] of labels.entries()) {
    assert.equal(Number(l.level), state.views[i].level);
    assert.equal(Number(l.triangles), state.views[i].triangles);
    assert.ok(Number.isFinite(Number(l.t)));
  }
  assert.match(await page.locator('#status').textContent(), /WebGPU/);
  assert.equal(await page.locator('[role=alert]').isHidden(), true);
  const largest = await page.$$eval('canvas', (cs) => cs.sort((a, b) => b.width * b.height - a.width * a.height)[0].parentElement.id);
  assert.equal(largest, 'viewer');
});

test('a file that is not a glTF is reported in the alert, not thrown away', async () => {
  const page = await openPage(browser);
  await page.setInputFiles('#file', { name: 'broken.glb', mimeType: 'model/gltf-binary', buffer: Buffer.from('not a glb') });
  await page.waitForFunction(() => document.documentElement.dataset.lastError !== undefined);
  assert.match(await page.locator('[role=alert]').textContent(), /broken\.glb/);
  assert.equal(await page.locator('[role=alert]').isVisible(), true);
});

test('a model URL that does not exist leaves the page in the error state with a message', async () => {
  const page = await browser.newPage();
  const params = new URLSearchParams({ test: '1', model: '/models/no-such-model.glb' });
  await page.goto(`${baseUrl}?${params}`);
  await page.waitForFunction(() => document.documentElement.dataset.state !== 'loading', null, { timeout: 60_000 });
  assert.equal(await page.evaluate(() => document.documentElement.dataset.state), 'error');
  assert.match(await page.locator('[role=alert]').textContent(), /no-such-model\.glb: HTTP 404/);
});

test('the continuous LOD slider: every view draws about n triangles, coarser n change the picture more', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  let now = 1000;
  // The finest level in every view (a tolerance so small that the schedule never coarsens);
  // duration 0: each count is shown at once (the morph between counts is checked below).
  const start = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE, duration: 0 });
  assert.equal(start.views[0].triangles, start.maxTriangles);
  const finest = crop(await readPixels(page), start.views[0].rect);
  const rows = [];
  let previous = 0;
  for (const n of [20000, 5000, 2000, 1000]) {
    const state = await frame(page, now += 16, { continuousTriangles: n });
    // The progressive mesh moves one collapse (one or two triangles) at a time.
    assert.ok(Math.abs(state.continuousTriangles - n) <= 2, `asked ${n}, got ${state.continuousTriangles}`);
    for (const view of state.views) assert.equal(view.triangles, state.continuousTriangles);
    const pixels = await readPixels(page);
    const crops = state.views.map((v) => crop(pixels, v.rect));
    crops.forEach((c, i) => assert.ok(foregroundFraction(c) > 0.03, `view ${i} is nearly empty at ${n} triangles`));
    const diff = meanAbsDiff(finest, crops[0]);
    rows.push(`${state.continuousTriangles}: ${diff.toFixed(3)}`);
    // Monotonic up to noise: fewer triangles never look much closer to the full mesh.
    assert.ok(diff >= 0.8 * previous, `the picture at ${n} triangles is closer to the full mesh (${rows})`);
    previous = diff;
  }
  console.log(`continuous LOD, mean |ΔRGB| per pixel from the full mesh: ${rows.join(', ')}`);
  assert.ok(previous > 0, 'the coarsest continuous mesh changes the picture');
  // With a duration, a new count morphs: popping shows it at once, the geomorph view goes from
  // the old state to the new one, its picture in between.
  const coarse = crop(await readPixels(page), start.views[0].rect);
  await frame(page, now += 16, { duration: 1, methods: ['popping', 'alpha', 'geomorph'] });
  let mid = await frame(page, now += 16, { continuousTriangles: 20000 });
  for (let i = 0; i < 5; i++) mid = await frame(page, now += 100);
  const shown = mid.views.map((v) => `${v.level}→${v.to} at ${v.t}`);
  assert.ok(shown.every((x) => x === shown[0]) && mid.views[0].level !== mid.views[0].to, `every view shows one change: ${shown}`);
  assert.ok(mid.views.every((v) => v.t > 0.4 && v.t < 0.6), `t: ${mid.views.map((v) => v.t)}`);
  assert.equal(mid.views[0].triangles, mid.continuousTriangles, 'popping switched at once');
  // The slider's states are levels.length and one more: the labels name the slider instead.
  const labels = await page.$$eval('.label', (ls) => ls.map((l) => l.textContent));
  const named = (l) => / · (continuous, t = |cont\. \()0\.[0-9]{2}\)? · [0-9,]+ (triangles|tris)$/.test(l) && !/level|L[0-9]/.test(l);
  assert.ok(labels.every(named), `labels (in full, or short in a narrow view): ${labels}`);
  const pixels = await readPixels(page);
  const [popped, , morphing] = mid.views.map((v) => crop(pixels, v.rect));
  const toCoarse = meanAbsDiff(morphing, coarse);
  const toFine = meanAbsDiff(morphing, popped);
  assert.ok(toCoarse > 0 && toFine > 0, `the half-way geomorph is neither end (${toCoarse}, ${toFine})`);
  assert.deepEqual(mid.errors, []);
  const off = await frame(page, now += 16, { continuousTriangles: null });
  assert.equal(off.continuousTriangles, null);
  assert.equal(off.views[0].triangles, off.levels[0].triangles);
});

test('overlays change every view: wireframe lines, level colours and the skeleton', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const now = 1000;
  const state = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1 });
  const rows = [];
  for (const overlay of ['wireframe', 'levels', 'skeleton']) {
    const { diffs, pixels } = await viewChanges(page, now, { overlay }, { overlay: 'none' });
    await savePng(`/tmp/clod-overlay-${overlay}.png`, pixels);
    rows.push(`${overlay}: ${diffs.map((d) => d.toFixed(2)).join(', ')}`);
    // A tenth of a level per pixel on average: lines or tints on the character, not rounding.
    diffs.forEach((d, i) => assert.ok(d > 0.1, `${overlay} leaves view ${i} (${state.views[i].method}) unchanged: ${d}`));
  }
  console.log(`overlay changes, mean |ΔRGB| per pixel in each view: ${rows.join('; ')}`);
  assert.equal((await frame(page, now)).overlay, 'none');
});

test('camera controls: pitch (clamped to ±85°), pan and resetCamera, reported in state()', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const now = 1000;
  // The default camera (resetCamera's): yaw 30°, pitch 8.6°, no pan, distance 1.
  const start = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1 });
  const home = await readPixels(page);
  const moved = await frame(page, now, { yaw: 75, pitch: 200, pan: [0.25, -0.1], distance: 2 });
  assert.deepEqual([moved.yaw, moved.pitch, moved.distance], [75, 85, 2]);
  assert.deepEqual(moved.pan.map((x) => Math.round(x * 100) / 100), [0.25, -0.1]);
  const view = moved.views[0].rect;
  const away = meanAbsDiff(crop(home, view), crop(await readPixels(page), view));
  assert.ok(away > 1, `the camera moved but the picture did not: ${away}`);
  assert.equal((await frame(page, now, { pitch: -90 })).pitch, -85);
  const reset = await frame(page, now, { resetCamera: true });
  for (const key of ['yaw', 'pitch', 'pan', 'distance']) assert.deepEqual(reset[key], start[key], key);
  assert.equal(meanAbsDiff(crop(home, view), crop(await readPixels(page), view)), 0, 'reset shows the first picture again');
  // Panning right moves the character left in the view.
  await frame(page, now, { pan: [0.3, 0] });
  const panned = await readPixels(page);
  const centroid = (pixels) => {
    const rgb = crop(pixels, view);
    const [r, g, b] = [rgb[0], rgb[1], rgb[2]];
    let sum = 0; let n = 0;
    for (let i = 0; i < rgb.length; i += 3) {
      if (Math.abs(rgb[i] - r) + Math.abs(rgb[i + 1] - g) + Math.abs(rgb[i + 2] - b) > 24) { sum += (i / 3) % view[2]; n++; }
    }
    return sum / n;
  };
  assert.ok(centroid(panned) < centroid(home) - 10, `pan right: centroid ${centroid(home)} → ${centroid(panned)}`);
  await assert.rejects(page.evaluate(() => window.__clod.setState({ pan: [1] })), /pan must be/);
});

test('the magnifier enlarges every view about its centre and keeps the level chosen for the real size', async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const now = 1000;
  const plain = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 3 });
  const before = crop(await readPixels(page), plain.views[2].rect);
  const zoomed = await frame(page, now, { magnify: 4 });
  const after = crop(await readPixels(page), zoomed.views[2].rect);
  assert.equal(zoomed.magnify, 4);
  assert.equal(zoomed.selected, plain.selected, 'the level is the real size\'s');
  assert.deepEqual(zoomed.views.map((v) => v.triangles), plain.views.map((v) => v.triangles));
  assert.ok(foregroundFraction(after) > 3 * foregroundFraction(before),
    `×4 covers more of the view: ${foregroundFraction(before)} → ${foregroundFraction(after)}`);
  assert.match(await page.locator('.clod-label').first().textContent(), /×4/);
  await frame(page, now, { magnify: 1 });
});

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: the difference overlay tints where a view differs from full detail, and nothing at full detail`, async () => {
    const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
    const now = 1000;
    const views = async () => { const p = await readPixels(page); return (await frame(page, now, {})).views.map((v) => crop(p, v.rect)); };
    const fine = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE, duration: 0, overlay: 'none' });
    assert.ok(fine.views.every((v) => v.level === 0));
    const plain = await views();
    await frame(page, now, { overlay: 'difference' });
    const same = await views();
    plain.forEach((p, i) => assert.equal(meanAbsDiff(p, same[i]), 0, `view ${i} at full detail is untouched`));
    const coarse = await frame(page, now, { tolerance: 500, overlay: 'none' });
    assert.ok(coarse.views.every((v) => v.level === coarse.levels.length - 1), 'the coarsest level');
    const coarsePlain = await views();
    await frame(page, now, { overlay: 'difference' });
    const heat = await views();
    heat.forEach((h, i) => {
      let magenta = 0;
      for (let k = 0; k < h.length; k += 3) if (h[k] > 150 && h[k + 2] > 120 && h[k + 1] < 0.6 * h[k]) magenta++;
      assert.ok(meanAbsDiff(h, coarsePlain[i]) > 0 && magenta > 20, `view ${i}: ${magenta} magenta pixels`);
    });
    await savePng(`/tmp/clod-difference-${backend}.png`, await readPixels(page));
    await frame(page, now, { overlay: 'none' });
  });
}
