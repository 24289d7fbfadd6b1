// Events that mean what they say (issue 48): changing the model, through the file input or the
// `src` attribute, while frames run, fires `load` and `lod` and never `error`, on both backends;
// each real failure fires exactly one `error` whose `code` names its kind (every code of
// `ERROR_CODES` in www/clod-viewer.js is produced here).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, existsSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { launch, baseUrl } from './helpers.mjs';

const models = new URL('../../../shared/models/', import.meta.url);
const robot = new URL('../../assets/robot.glb', import.meta.url);

/** `[name, bytes, url]` of the shared models (absent ones skipped, or failing under CI=true) and the robot. */
function sources() {
  const list = [];
  for (const name of ['RiggedSimple.glb', 'Fox.glb', 'CesiumMan.glb']) {
    const url = new URL(name, models);
    if (!existsSync(url)) {
      if (process.env.CI === 'true') throw new Error(`${url.pathname} is missing, and CI needs the shared models`);
      console.log(`skipping: ${url.pathname} is missing`);
      continue;
    }
    list.push([name, readFileSync(url), `/models/${name}`]);
  }
  list.push(['robot.glb', readFileSync(robot), '/assets/robot.glb']);
  return list;
}

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// Opens the page with its frame loop running (not test mode: the swap must hold while frames are
// drawn) and records the viewer's events and the page's uncaught errors from the start.
async function open(t, query = {}, instrument = async () => {}, target = browser) {
  const page = await target.newPage({ viewport: { width: 700, height: 500 }, deviceScaleFactor: 1 });
  t.after(() => page.close());
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.pageErrors = pageErrors;
  await instrument(page);
  await page.addInitScript(() => {
    window.__events = [];
    for (const type of ['load', 'lod', 'error']) {
      document.addEventListener(type, (e) => {
        if (e.target.localName !== 'clod-viewer') return;
        window.__events.push(type === 'error' ? { type, ...e.detail } : { type, triangles: e.detail.triangles });
      }, true);
    }
  });
  await page.goto(`${baseUrl}?${new URLSearchParams(query)}`);
  return page;
}

const events = (page) => page.evaluate(() => window.__events);

// Waits until the page has seen `count` events of `type` (or an error it did not expect).
async function waitFor(page, type, count) {
  await page.waitForFunction(([type, count]) => window.__events.filter((e) => e.type === type).length >= count ||
    (type !== 'error' && window.__events.some((e) => e.type === 'error')), [type, count], { timeout: 180_000 });
  const errors = (await events(page)).filter((e) => e.type === 'error');
  if (type !== 'error') assert.deepEqual(errors, [], 'no error events');
}

// Lets the frame loop draw a few frames of the model shown.
async function someFrames(page) {
  await page.evaluate(() => new Promise((resolve) => {
    let n = 0;
    const step = () => (++n >= 5 ? resolve() : requestAnimationFrame(step));
    requestAnimationFrame(step);
  }));
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: changing the model, by file and by src, fires load and lod and no error, and keeps the reader's settings`, async (t) => {
    const page = await open(t, { backend });
    await waitFor(page, 'lod', 1);
    // The reader scrolls down to the controls and turns FLIP off (the meter stays on): every
    // model after keeps it off, and the frames between loads cost a third of a measured frame with
    // FLIP on SwiftShader. The first model opened out of sight still loads; the reader then
    // scrolls back, and the others swap while frames are drawn.
    await page.uncheck('#flip-on');
    assert.ok(await page.evaluate(() => document.getElementById('viewer').getBoundingClientRect().bottom < 0), 'the viewer scrolled out of sight');
    const kept = async (name) => assert.deepEqual(await page.evaluate(() => {
      const { meter } = document.getElementById('viewer').state();
      return [meter.on, meter.flipOn, document.getElementById('flip-on').checked];
    }), [true, false, false], `${name}: the meter on, FLIP off as the reader left them`);
    let loads = 1;
    for (const [name, bytes] of sources()) {
      await page.setInputFiles('#file', { name, mimeType: 'model/gltf-binary', buffer: bytes });
      loads++;
      await waitFor(page, 'lod', loads);
      if (loads === 2) await page.evaluate(() => window.scrollTo(0, 0));
      await someFrames(page);
      await kept(name);
      const shown = await page.evaluate(() => document.getElementById('viewer').state().triangles);
      assert.equal(shown, (await events(page)).filter((e) => e.type === 'load').at(-1).triangles, name);
    }
    for (const [name, , url] of sources()) {
      await page.evaluate((url) => document.getElementById('viewer').setAttribute('src', url), url);
      loads++;
      await waitFor(page, 'lod', loads);
      await someFrames(page);
      await kept(name);
      assert.ok((await page.evaluate(() => document.getElementById('viewer').state().levels.length)) > 1, `${name}: levels`);
    }
    const all = await events(page);
    assert.equal(all.filter((e) => e.type === 'load').length, loads);
    assert.deepEqual(all.filter((e) => e.type === 'error'), []);
    assert.deepEqual(page.pageErrors, []);
  });

  test(`${backend}: each real failure fires one error with its code, and the model shown keeps playing`, async (t) => {
    const page = await open(t, { backend });
    await waitFor(page, 'lod', 1);
    const outcomes = [];
    const expect = async (code, action) => {
      const before = (await events(page)).filter((e) => e.type === 'error').length;
      await action();
      await waitFor(page, 'error', before + 1);
      await someFrames(page);
      const errors = (await events(page)).filter((e) => e.type === 'error').slice(before);
      outcomes.push(...errors);
      assert.equal(errors.length, 1, JSON.stringify(errors));
      assert.equal(errors[0].code, code, errors[0].message);
    };
    const glb = readFileSync(new URL('../../assets/character.glb', import.meta.url));
    await expect('model', () => page.setInputFiles('#file', { name: 'cut.glb', mimeType: 'model/gltf-binary', buffer: Buffer.from(glb.subarray(0, 4000)) }));
    await expect('fetch', () => page.evaluate(() => document.getElementById('viewer').setAttribute('src', '/models/no-such-file.glb')));
    await expect('attribute', () => page.evaluate(() => document.getElementById('viewer').setAttribute('modes', 'pop fade')));
    for (const e of outcomes) assert.doesNotMatch(e.message, /wgpu|Validation|undefined|null/);
    // The character shown before the failures still draws.
    const state = await page.evaluate(() => document.getElementById('viewer').state());
    assert.equal(state.triangles, 50_972);
    assert.deepEqual(page.pageErrors, []);
  });
}

test('the viewer\'s own files missing: `wasm`, and the levels\' worker missing: `levels` with the full mesh shown', async (t) => {
  const noWasm = await open(t, {}, (page) => page.route(/\/pkg(-webgl)?\/clod_viewer\.js$/, (route) => route.fulfill({ status: 404, body: '' })));
  await waitFor(noWasm, 'error', 1);
  assert.deepEqual((await events(noWasm)).map((e) => [e.type, e.code]), [['error', 'wasm']]);
  const noWorker = await open(t, {}, (page) => page.route(/clod-worker\.js$/, (route) => route.fulfill({ status: 404, body: '' })));
  await waitFor(noWorker, 'error', 1);
  const seen = await events(noWorker);
  assert.deepEqual(seen.map((e) => [e.type, e.code]), [['load', undefined], ['error', 'levels']]);
  assert.equal(seen[0].triangles, 50_972);
});

test('a browser without WebGPU or WebGL2: one error, `no-gpu`, in words a reader can act on', async (t) => {
  const bare = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    args: ['--no-sandbox', '--headless', '--disable-gpu', '--disable-webgl', '--disable-3d-apis', '--disable-background-networking'],
  });
  t.after(() => bare.close());
  const page = await open(t, {}, async () => {}, bare);
  await waitFor(page, 'error', 1);
  const seen = await events(page);
  assert.deepEqual(seen.map((e) => [e.type, e.code]), [['error', 'no-gpu']]);
  assert.match(seen[0].message, /hardware acceleration/);
});

test('webgl2: a lost GPU context is one `render` error, and the viewer stops drawing', async (t) => {
  const page = await open(t, { backend: 'webgl2' });
  await waitFor(page, 'lod', 1);
  await page.evaluate(() => document.querySelector('clod-viewer > canvas').getContext('webgl2').getExtension('WEBGL_lose_context').loseContext());
  await waitFor(page, 'error', 1);
  const frames = () => page.evaluate(() => document.getElementById('viewer').state().frames);
  const stopped = await frames();
  for (let i = 0; i < 3; i++) await someFrames(page);
  assert.equal(await frames(), stopped, 'no frame is drawn into a lost context');
  const errors = (await events(page)).filter((e) => e.type === 'error');
  assert.deepEqual(errors.map((e) => e.code), ['render'], JSON.stringify(errors));
  assert.doesNotMatch(errors[0].message, /wgpu|Validation/);
});
