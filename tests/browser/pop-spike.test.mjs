// (3) The pop spike: animation paused, the camera moves slowly through one LOD switch over a fixed
// number of frames. Popping changes the picture at once; geomorphing spreads the change over the
// transition, so its largest frame-to-frame change must be at most 10 % of popping's.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, readPixels, crop, meanAbsDiff, clock, tuneTolerance, FINEST_TOLERANCE } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// 72 frames at 60 Hz; the transition takes 0.8 s (48 frames) and ends inside the sweep.
const FRAMES = 72;
const SWITCH_AT = 1.5;

for (const variant of ['opaque-first', 'dither', 'naive']) {
  test(`geomorph's largest frame change is ≤ 10 % of popping's (alpha-blend ${variant} reported)`, async () => {
    const page = await openPage(browser);
    const c = clock();
    // The last switch (to the coarsest level): the biggest change of shape, so the clearest pop.
    const k = 6;
    let state = await frame(page, c.now, { paused: true, time: 0.4, variant, transition: 'time', duration: 0, hysteresis: 0.1, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE });
    const tolerance = tuneTolerance(state, k, SWITCH_AT);
    // The switch to level k happens at SWITCH_AT × (1 + hysteresis); sweep ±0.4 % around it, so
    // the camera's own motion changes the picture far less than the pop.
    const at = (i) => SWITCH_AT * 1.1 * (0.996 + 0.008 * i / (FRAMES - 1));
    state = await frame(page, c.tick(100), { tolerance, distance: at(0) });
    state = await frame(page, c.tick(100), { duration: 0.8 });
    assert.equal(state.selected, k - 1);
    const largest = [0, 0, 0];
    const series = [[], [], []];
    let previous = null;
    const selected = [];
    for (let i = 0; i < FRAMES; i++) {
      state = await frame(page, c.tick(1000 / 60), { distance: at(i) });
      selected.push(state.selected);
      const pixels = await readPixels(page);
      const crops = state.views.map((v) => crop(pixels, v.rect));
      if (previous) {
        crops.forEach((cur, v) => {
          const d = meanAbsDiff(previous[v], cur);
          series[v].push(d.toFixed(3));
          largest[v] = Math.max(largest[v], d);
        });
      }
      previous = crops;
    }
    assert.equal(selected[0], k - 1);
    assert.equal(selected.at(-1), k, 'the sweep crosses the switch');
    assert.equal(state.views[2].t, 0, 'the transition has finished within the sweep');
    const [pop, alpha, geo] = largest;
    console.log(`pop spike (${variant}): popping ${pop.toFixed(3)}, alpha-blend ${alpha.toFixed(3)} (${(100 * alpha / pop).toFixed(1)} %), geomorph ${geo.toFixed(3)} (${(100 * geo / pop).toFixed(1)} %) mean |ΔRGB| per pixel`);
    assert.ok(pop > 0, 'popping changes the picture');
    assert.ok(geo <= 0.1 * pop, `geomorph ${geo} > 10 % of popping ${pop}; frame changes: popping ${series[0]} geomorph ${series[2]}`);
  });
}
