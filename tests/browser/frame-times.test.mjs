// Frame times per method in SwiftShader, with and without a transition running: all three views
// forced to one method, so a third of a frame is one view's cost. Reported, not judged (SwiftShader
// is a CPU rasterizer); the test checks only that timing works and the numbers are finite.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, clock, midTransition, FINEST_TOLERANCE } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const FRAMES = 8;

// Median milliseconds per frame (CPU + GPU: each frame waits for the GPU to finish).
async function timeFrames(page, c) {
  const times = [];
  for (let i = 0; i < FRAMES; i++) {
    const start = c.tick(1000 / 60);
    times.push(await page.evaluate(async (now) => {
      const t0 = performance.now();
      window.__clod.renderFrame(now);
      await window.__clod.finish();
      return performance.now() - t0;
    }, start));
  }
  times.sort((a, b) => a - b);
  return times[Math.floor(FRAMES / 2)];
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`frame times per view on ${backend}`, async () => {
    const page = await openPage(browser, { backend });
    const rows = [];
    for (const [method, variant] of [['popping', 'opaque-first'], ['alpha', 'opaque-first'], ['alpha', 'dither'], ['geomorph', 'opaque-first']]) {
      const methods = [method, method, method];
      const c = clock();
      // Idle: the finest level (50k triangles), no transition.
      await frame(page, c.now, { paused: true, time: 0.4, methods, variant, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE, duration: 0 });
      const idle = await timeFrames(page, c);
      // Mid-transition between levels 0 and 1, held there by a long duration.
      const state = await midTransition(page, c, { k: 1, t: 0.5, methods, variant });
      await frame(page, c.tick(16), { duration: 60 });
      const busy = await timeFrames(page, c);
      assert.ok(Number.isFinite(idle) && Number.isFinite(busy));
      rows.push(`${method}${method === 'alpha' ? ` (${variant})` : ''}: ${(idle / 3).toFixed(1)} ms idle, ${(busy / 3).toFixed(1)} ms in transition (levels ${state.views[0].level}→${state.views[0].level + 1})`);
    }
    console.log(`${backend}, per view (a third of a frame of three equal views, ${await page.evaluate(() => window.__clod.state().width)} px wide):\n  ${rows.join('\n  ')}`);
  });
}
