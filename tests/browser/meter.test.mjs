// (13) The live transition meter, with its control: every measured frame also draws each view
// with its plan of the previous measured frame (its control), so a transition's pop is what the
// transition itself changed, not the animation's own motion.
// - A view whose level holds reports a step below 0.005 % of its pixels in every frame while the
//   character walks, although its difference from the reference moves by more (uncontrolled).
// - Walking, tolerance 6 px, 2 s transitions, the camera jumping across three switches (L4 → L5,
//   L5 → L6, L6 → L5), 10 frames per second: the median over the three transitions of alpha's and
//   geomorph's silhouette pops ≤ 20 % of popping's; on WebGPU the middle transition again at 100
//   frames per second (the clock slowed 10×) ranks the methods the same. The replay of the last
//   transition has frames for every view, a curve point for every frame, and exports a PNG. FLIP is
//   off throughout: the ranking reads the silhouette, which does not depend on it, and FLIP is 60 %
//   of a measured frame on SwiftShader (the first impression's test checks the meter's FLIP).
// WebGPU and WebGL2.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, step, FINEST_TOLERANCE, tuneTolerance, SMALL_VIEWPORT } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const METHODS = ['popping', 'alpha', 'geomorph'];

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: a view whose level holds reports no step while the character walks`, async () => {
    const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
    let now = 1000;
    let state = await frame(page, now, { paused: false, speed: 1, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE, duration: 0 });
    // The coarsest level at the framing distance, so each view differs from the reference.
    const k = state.levels.length - 1;
    state = await step(page, now += 100, { tolerance: tuneTolerance(state, k, 0.5) });
    for (let i = 0; i < 12; i++) state = await step(page, now += 100);
    assert.deepEqual(state.views.map((v) => [v.level, v.to]), [[k, k], [k, k], [k, k]]);
    const history = await page.evaluate(() => document.getElementById('viewer').meterHistory());
    const samples = history.samples.slice(-10);
    const steps = history.steps.slice(-10);
    const largestStep = Math.max(...steps.flatMap((s) => [s[0], s[2], s[4]]));
    // The same frames without the control: how far the difference from the reference moved.
    const moved = Math.max(...samples.slice(1).map((s, i) => Math.abs(s[2] - samples[i][2])));
    console.log(`${backend}: level ${k} held while walking, 10 frames: largest step ${largestStep} %, largest frame-to-frame change of the difference from the reference ${moved.toFixed(4)} %`);
    assert.ok(moved > 0.005, `the walk moves the difference from the reference: ${moved} %`);
    assert.ok(largestStep < 0.005, `steps ${JSON.stringify(steps)}`);
  });

  test(`${backend}: walking at 6 px with 2 s transitions, alpha's and geomorph's pops ≤ 20 % of popping's, ranked alike at 10× the frame rate`, async () => {
    const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
    let now = 1000;
    let state = await frame(page, now, { paused: false, speed: 1, time: 0.2, distanceMode: 'manual', distance: 1, tolerance: 6, hysteresis: 0.1, transition: 'time', duration: 2, variant: 'opaque-first', flip: false });
    const s = state.switch;
    const k = s.length - 1;
    // Distances that select k − 2, k − 1 and k (coarsening waits for the switch × 1.1).
    const at = { [k - 2]: (1.1 * s[k - 2] + s[k - 1]) / 2, [k - 1]: 1.1 * 1.05 * s[k - 1], [k]: 1.1 * 1.05 * s[k] };
    assert.ok(at[k - 1] < s[k], `levels ${k - 1} and ${k} are apart: ${JSON.stringify(s)}`);
    // Settles at `level`, then moves the camera to select `to` and draws `dtMs` frames until the
    // transition has ended and the meter has it: returns its pops and frames.
    const transition = async (level, to, dtMs) => {
      state = await step(page, now += dtMs, { duration: 0, distance: at[level] });
      for (let i = 0; i < 3; i++) state = await step(page, now += dtMs);
      assert.equal(state.views[0].level, level);
      const seen = state.meter.transitions;
      state = await step(page, now += dtMs, { duration: 2, distance: to < level ? 0.95 * s[level] : at[to] });
      assert.deepEqual([state.views[0].level, state.views[0].to], [level, to]);
      let frames = 1;
      while (state.meter.transitions === seen || state.views[0].to !== state.views[0].level) {
        state = await step(page, now += dtMs);
        assert.ok(++frames < 2600 / dtMs * 10, 'the transition ends');
      }
      return { frames, ...Object.fromEntries(METHODS.map((m) => [m, state.meter[m]])) };
    };
    const runs = [await transition(k - 2, k - 1, 100), await transition(k - 1, k, 100), await transition(k, k - 1, 100)];
    const median = (m, key) => runs.map((r) => key(r[m])).sort((a, b) => a - b)[1];
    const sil = (p) => p.silhouette;
    const raw = (p) => p.uncontrolled.silhouette;
    for (const r of runs) {
      console.log(`${backend} 10 fps, ${r.frames} frames: ${METHODS.map((m) => `${m} ${r[m].silhouette.toFixed(4)} % (uncontrolled ${r[m].uncontrolled.silhouette.toFixed(4)} %), shading ${r[m].shading.toFixed(3)}`).join('; ')}`);
    }
    const med = Object.fromEntries(METHODS.map((m) => [m, median(m, sil)]));
    const medRaw = Object.fromEntries(METHODS.map((m) => [m, median(m, raw)]));
    console.log(`${backend} median of 3 at 10 fps: ${METHODS.map((m) => `${m} ${med[m].toFixed(4)} % (${(100 * med[m] / med.popping).toFixed(0)} %; uncontrolled ${medRaw[m].toFixed(4)} %, ${(100 * medRaw[m] / medRaw.popping).toFixed(0)} %)`).join(', ')}`);
    assert.ok(med.popping > 0.01, `popping pops: ${med.popping} %`);
    assert.ok(med.alpha <= 0.2 * med.popping, `alpha ${med.alpha} vs popping ${med.popping}`);
    assert.ok(med.geomorph <= 0.2 * med.popping, `geomorph ${med.geomorph} vs popping ${med.popping}`);
    // The replay of the last transition (L6 → L5): frames for every view, curves for every frame,
    // and one PNG.
    const replay = await page.evaluate(async () => {
      const r = window.__clod.replay();
      const png = await window.__clod.replayPng();
      return r && {
        methods: r.methods, levels: r.levels, region: r.region, curve: r.curves.frame.length,
        frames: r.frames.map((f) => f.views.map((v) => v.length)), lengths: r.curves.silhouette.map((c) => c.length), png,
      };
    });
    console.log(`${backend} replay: levels ${replay.levels.join(' → ')}, ${replay.frames.length} frames of ${replay.region[2]} × ${replay.region[3]} px at [${replay.region.slice(0, 2)}], ${replay.curve} curve points, PNG ${replay.png.size} bytes`);
    assert.deepEqual(replay.methods, METHODS);
    assert.deepEqual(replay.levels, [k, k - 1]);
    assert.ok(replay.frames.length >= 6, `${replay.frames.length} frames`);
    const bytes = 4 * replay.region[2] * replay.region[3];
    assert.ok(replay.frames.every((views) => views.length === 3 && views.every((n) => n === bytes)), JSON.stringify(replay.frames));
    // 2 s at 10 frames a second, the frame before and the frame after.
    assert.ok(replay.curve >= 21, `${replay.curve} curve points`);
    assert.deepEqual(replay.lengths, [replay.curve, replay.curve, replay.curve]);
    assert.deepEqual(replay.png.head, [137, 80, 78, 71, 13, 10, 26, 10]);
    assert.equal(state.meter.flipOn, false);
    assert.equal(state.meter.flip, null, 'FLIP off: state().meter.flip is null');
    if (backend !== 'webgpu') return;
    // The middle transition (the last one ended at k − 1) again at 100 frames per second: the
    // same order of the three methods.
    const fast = await transition(k - 1, k, 10);
    const slow = runs[1];
    const order = (r) => [...METHODS].sort((a, b) => r[b].silhouette - r[a].silhouette).join(' > ');
    console.log(`${backend} 100 fps, ${fast.frames} frames: ${METHODS.map((m) => `${m} ${fast[m].silhouette.toFixed(4)} % (uncontrolled ${fast[m].uncontrolled.silhouette.toFixed(4)} %)`).join('; ')}; order ${order(fast)} (10 fps: ${order(slow)})`);
    assert.equal(order(fast), order(slow));
  });
}
