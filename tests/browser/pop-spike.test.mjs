// (3) The pop spike: animation paused, the camera moves slowly through one LOD switch over a fixed
// number of frames (the viewer's own `measurePopSpike`: offscreen frames read back and compared in
// Rust). Popping changes the picture at once; geomorphing spreads the change over the transition,
// so its largest frame-to-frame change must be at most 10 % of popping's. Alpha-blending's is
// reported for each variant.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, measurePopSpike, SMALL_VIEWPORT } from './helpers.mjs';

let browser;
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

test("geomorph's largest frame change is ≤ 10 % of popping's (alpha-blend variants reported)", async () => {
  const page = await openPage(browser, {}, SMALL_VIEWPORT);
  const now = 1000;
  const before = await frame(page, now, { paused: true, time: 0.4, distanceMode: 'manual', distance: 1.3 });
  const lines = [];
  for (const variant of ['opaque-first', 'dither', 'naive']) {
    await frame(page, now, { variant });
    const started = Date.now();
    const spike = await measurePopSpike(page, now);
    const { popping, alpha, geomorph, level, frames } = spike;
    const pct = (x) => `${(100 * x / popping).toFixed(1)} %`;
    lines.push(`${variant}: popping ${popping.toFixed(3)}, alpha-blend ${alpha.toFixed(3)} (${pct(alpha)}), ` +
      `geomorph ${geomorph.toFixed(3)} (${pct(geomorph)}) mean |ΔRGB| per pixel; switch to level ${level}, ` +
      `${frames} frames in ${((Date.now() - started) / 1000).toFixed(1)} s`);
    assert.equal(spike.variant, variant);
    assert.deepEqual(spike.views.map((v) => v.method), ['popping', 'alpha', 'geomorph']);
    assert.ok(spike.views.every((v) => v.series.length === frames - 1));
    // The switch must stand out of the camera's own motion, whatever the levels' accuracy: the
    // slow sweep changes about 0.01 per frame; the coarsest switch of the built-in character pops
    // 0.84 since collapses are ordered by area-weighted error (it was over 1 before).
    const drift = median(spike.views[0].series);
    assert.ok(popping > 20 * drift && popping > 0.25, `popping changes the picture: ${popping} (drift ${drift})`);
    assert.ok(geomorph <= 0.1 * popping,
      `geomorph ${geomorph} > 10 % of popping ${popping}; frame changes: popping ${spike.views[0].series} geomorph ${spike.views[2].series}`);
  }
  console.log(`pop spike (${SMALL_VIEWPORT.width}-px-wide page):\n  ${lines.join('\n  ')}`);
  // The viewer is as it was: same settings, clocks and level.
  const after = await frame(page, now, {});
  for (const key of ['distance', 'animTime', 'paused', 'selected', 'views', 'switch']) {
    assert.deepEqual(after[key], before[key], key);
  }
});
