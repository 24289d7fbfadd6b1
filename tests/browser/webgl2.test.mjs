// (4) The WebGL2 fallback draws the same picture as WebGPU, within a small tolerance (both on
// SwiftShader here; rasterization rules match, so only rounding differs).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, readPixels, crop, meanAbsDiff, foregroundFraction, clock, midTransition, savePng, SMALL_VIEWPORT, frame, viewChanges } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

async function picture(backend, methods) {
  const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
  const state = await midTransition(page, clock(), { k: 4, t: 0.5, methods, variant: 'dither', switchAt: 1.2 });
  assert.equal(state.backend, backend);
  assert.equal(state.errors.length, 0, state.errors.join('\n'));
  const pixels = await readPixels(page);
  await page.close();
  return { state, pixels };
}

test('WebGL2 draws what WebGPU draws', async () => {
  const methods = ['popping', 'alpha', 'geomorph'];
  const gpu = await picture('webgpu', methods);
  const gl = await picture('webgl2', methods);
  await savePng('/tmp/clod-webgpu.png', gpu.pixels);
  await savePng('/tmp/clod-webgl2.png', gl.pixels);
  assert.deepEqual([gl.pixels.width, gl.pixels.height], [gpu.pixels.width, gpu.pixels.height]);
  gpu.state.views.forEach((view, i) => {
    const a = crop(gpu.pixels, view.rect);
    const b = crop(gl.pixels, gl.state.views[i].rect);
    const diff = meanAbsDiff(a, b);
    console.log(`view ${i} (${view.method}): mean |ΔRGB| WebGPU vs WebGL2 = ${diff.toFixed(3)} per pixel`);
    assert.ok(foregroundFraction(b) > 0.01, `WebGL2 view ${i} is empty`);
    // 1.5 of 765 per pixel on average: edge pixels may differ by rounding, shapes may not.
    assert.ok(diff < 1.5, `view ${i} differs by ${diff}`);
  });
});

test('WebGL2 draws the overlays too (wireframe lines, level colours, skeleton) in every view', async () => {
  const page = await openPage(browser, { backend: 'webgl2' }, SMALL_VIEWPORT);
  const now = 1000;
  const state = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1 });
  assert.equal(state.backend, 'webgl2');
  for (const overlay of ['wireframe', 'levels', 'skeleton']) {
    const { diffs } = await viewChanges(page, now, { overlay }, { overlay: 'none' });
    console.log(`WebGL2 ${overlay}: mean |ΔRGB| per pixel ${diffs.map((d) => d.toFixed(2)).join(', ')}`);
    diffs.forEach((d, i) => assert.ok(d > 0.1, `${overlay} leaves WebGL2 view ${i} unchanged: ${d}`));
  }
  await page.close();
});
