// The README's picture (docs/page.png) is taken by the browser suite, so it shows the page as it
// is: first-impression.test.mjs photographs the default page, untouched, on WebGPU in a 1240 × 900
// window, in the middle of its second transition (the first one's pops in the table). The photograph
// fails if the page does not draw: in the screenshot itself, decoded by the browser, at least 6 % of
// every view's pixels must differ from its background (its most common colour; the character covers
// 13 to 22 % of a view as the camera dollies, the view's label under 3 %).
//
// The suite writes the picture to target/screenshot/page.png; `bash scripts/screenshot.sh` runs
// first-impression.test.mjs with SCREENSHOT_OUT=docs/page.png to refresh the committed one.
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import { dirname, resolve } from 'node:path';
import { crop, decodePixels } from './helpers.mjs';

export const SCREENSHOT_VIEWPORT = { width: 1240, height: 900 };

/**
 * Waits until every view of the `<clod-viewer id="viewer">` on `page` is between 0.3 and 0.7 of one
 * transition (alpha-blending and geomorphing differ most from popping there), photographs the page
 * into SCREENSHOT_OUT (default target/screenshot/page.png) and checks that every view drew.
 */
export async function photographMidTransition(page) {
  const out = resolve(process.env.SCREENSHOT_OUT ?? 'target/screenshot/page.png');
  const views = await page.evaluate(() => new Promise((resolve, reject) => {
    const viewer = document.getElementById('viewer');
    const deadline = performance.now() + 60_000;
    const timer = setInterval(() => {
      if (performance.now() > deadline) { clearInterval(timer); reject(new Error('no view mid-transition within 60 s')); return; }
      const s = viewer.state();
      if (s.views.length && s.views.every((v) => v.to !== v.level && v.t > 0.3 && v.t < 0.7)) {
        clearInterval(timer);
        resolve(s.views.map((v) => ({ method: v.method, rect: v.rect, t: v.t })));
      }
    }, 20);
  }));
  const png = await page.screenshot({ type: 'png' });
  const canvas = await page.locator('clod-viewer canvas').first().boundingBox();
  // The browser decodes the picture it took (no PNG decoder in node).
  const pixels = decodePixels(await page.evaluate(async (base64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${base64}`;
    await img.decode();
    const ctx = new OffscreenCanvas(img.width, img.height).getContext('2d');
    ctx.drawImage(img, 0, 0);
    return window.__encodePixels(ctx.getImageData(0, 0, img.width, img.height));
  }, png.toString('base64')));
  mkdirSync(dirname(out), { recursive: true });
  writeFileSync(out, png);
  const drawn = views.map(({ rect: [x, y, w, h] }) =>
    awayFromBackground(crop(pixels, [Math.round(canvas.x) + x, Math.round(canvas.y) + y, w, h])));
  console.log(`screenshot ${out} (${(png.length / 1024).toFixed(0)} KiB): ${views.map((v, i) => `${v.method} t=${v.t.toFixed(2)} drawn ${(100 * drawn[i]).toFixed(1)} %`).join(', ')}`);
  assert.equal(views.length, 3);
  for (const [i, d] of drawn.entries()) assert.ok(d >= 0.06, `${views[i].method} view: ${(100 * d).toFixed(2)} % of its pixels drawn`);
}

// The fraction of an RGB crop's pixels that differ from its most common colour (the background)
// by more than 24 in some channel.
function awayFromBackground(rgb) {
  const counts = new Map();
  for (let i = 0; i < rgb.length; i += 3) {
    const key = (rgb[i] << 16) | (rgb[i + 1] << 8) | rgb[i + 2];
    counts.set(key, (counts.get(key) ?? 0) + 1);
  }
  const background = [...counts].reduce((a, b) => (b[1] > a[1] ? b : a))[0];
  const [r, g, b] = [background >> 16, (background >> 8) & 255, background & 255];
  let away = 0;
  for (let i = 0; i < rgb.length; i += 3) {
    if (Math.abs(rgb[i] - r) > 24 || Math.abs(rgb[i + 1] - g) > 24 || Math.abs(rgb[i + 2] - b) > 24) away++;
  }
  return away / (rgb.length / 3);
}
