// (1) The page starts, says which backend runs, and all three views show the character.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, readPixels, crop, foregroundFraction, savePng, baseUrl } from './helpers.mjs';

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
