// The README's picture (docs/page.png) comes from here, so it shows the page as it is: the default
// page, untouched, on WebGPU in a 1240 × 760 window, photographed while its views are in the middle
// of a transition (after the first one, so the meter's strip chart and the replay have something to
// show). The test fails if the page does not draw: every view must show the character (at least 2 %
// of its pixels away from the background) in the screenshot itself, decoded by the browser.
//
// The suite writes the picture to target/screenshot/page.png; `bash scripts/screenshot.sh` runs this
// file alone with SCREENSHOT_OUT=docs/page.png to refresh the committed one.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import { dirname, resolve } from 'node:path';
import { launch, baseUrl, crop, decodePixels, foregroundFraction } from './helpers.mjs';

const OUT = resolve(process.env.SCREENSHOT_OUT ?? 'target/screenshot/page.png');
const VIEWPORT = { width: 1240, height: 760 };

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

test('the default page draws its three views mid-transition, photographed for the README', async () => {
  const page = await browser.newPage({ viewport: VIEWPORT, deviceScaleFactor: 1 });
  const problems = [];
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  await page.addInitScript(() => {
    document.addEventListener('error', (e) => { window.__viewerErrors = [...(window.__viewerErrors ?? []), e.detail?.code]; }, true);
  });
  await page.goto(`${baseUrl}?backend=webgpu`);
  // After the first transition has been measured, the next one, caught near its middle (the
  // alpha-blend and the geomorph differ most from popping there).
  const views = await page.evaluate(() => new Promise((resolve, reject) => {
    const viewer = document.getElementById('viewer');
    const deadline = performance.now() + 120_000;
    let seenFirst = false;
    const timer = setInterval(() => {
      if (performance.now() > deadline) { clearInterval(timer); reject(new Error(`no second transition: ${document.getElementById('status').textContent}`)); return; }
      let s;
      try { s = viewer.state(); } catch { return; }
      if (!s.views?.length) return;
      seenFirst ||= s.meter.transitions >= 1;
      const running = s.views.every((v) => v.to !== v.level && v.t > 0.3 && v.t < 0.7);
      if (seenFirst && running) { clearInterval(timer); resolve(s.views.map((v) => ({ method: v.method, rect: v.rect, t: v.t }))); }
    }, 20);
  }));
  const png = await page.screenshot({ type: 'png' });
  const canvas = await page.locator('clod-viewer canvas').first().boundingBox();
  const errors = await page.evaluate(() => window.__viewerErrors ?? []);

  // The browser decodes the picture it took (no PNG decoder in node).
  const pixels = decodePixels(await page.evaluate(async (base64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${base64}`;
    await img.decode();
    const c = new OffscreenCanvas(img.width, img.height);
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    return window.__encodePixels(ctx.getImageData(0, 0, img.width, img.height));
  }, png.toString('base64')));
  await page.close();

  mkdirSync(dirname(OUT), { recursive: true });
  writeFileSync(OUT, png);
  const covered = views.map((v) => {
    const [x, y, w, h] = v.rect;
    return foregroundFraction(crop(pixels, [Math.round(canvas.x) + x, Math.round(canvas.y) + y, w, h]));
  });
  console.log(`screenshot ${OUT} (${(png.length / 1024).toFixed(0)} KiB): ${views.map((v, i) => `${v.method} t=${v.t.toFixed(2)} covers ${(100 * covered[i]).toFixed(1)} %`).join(', ')}`);
  assert.deepEqual(problems, []);
  assert.deepEqual(errors, []);
  assert.equal(views.length, 3);
  for (const [i, c] of covered.entries()) assert.ok(c >= 0.02, `${views[i].method} view: ${(100 * c).toFixed(2)} % of its pixels drawn`);
});
