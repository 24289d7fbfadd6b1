// (13) The live transition meter: while the character walks, every view is compared with the
// full-detail reference drawn at the same pose and camera, and a transition's pop is the largest
// frame-to-frame change of that difference. On the built-in character, a slow transition to the
// coarsest level: geomorphing's and the opaque-first blend's silhouette pops stay within 20 % of
// popping's. Also reports what the meter costs per frame. WebGPU and WebGL2.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, FINEST_TOLERANCE, tuneTolerance } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const FRAME_MS = 1000 / 60;
// One transition over 40 drawn frames: a software rasterizer draws few frames a second, so the
// viewer's clock is slowed, not the test.
const DURATION = 40 * FRAME_MS / 1000;

// Draws one frame at `now` and waits for the GPU, so the meter's readback is back by the next.
const step = (page, now, state = {}) => page.evaluate(async ([s, t]) => {
  window.__clod.setState(s);
  const state = window.__clod.renderFrame(t);
  await window.__clod.finish();
  return state;
}, [state, now]);

// With the camera still at the framing distance, settles at level k − 1 just before its switch,
// then moves the switch (the tolerance, not the camera: nothing else changes) so level k is
// selected, and draws frames until that transition has ended. Returns the meter, the frames the
// transition took and the last state.
async function transition(page, now, { paused }) {
  const distance = 1;
  let state = await frame(page, now, { paused, time: 0.4, speed: 1, transition: 'time', duration: 0, hysteresis: 0.1, distanceMode: 'manual', distance, tolerance: FINEST_TOLERANCE, variant: 'opaque-first' });
  const k = state.levels.length - 1;
  // Coarsening waits for the distance to pass the switch × 1.1 (the hysteresis).
  const [before, after] = [1.05, 0.95].map((f) => tuneTolerance(state, k, (distance / 1.1) * f));
  state = await step(page, now += FRAME_MS, { tolerance: before });
  assert.equal(state.selected, k - 1);
  for (let i = 0; i < 4; i++) state = await step(page, now += FRAME_MS);
  state = await step(page, now += FRAME_MS, { duration: DURATION, tolerance: after });
  assert.deepEqual([state.views[0].level, state.views[0].to], [k - 1, k]);
  let frames = 0;
  while (state.views[0].level !== state.views[0].to) {
    state = await step(page, now += FRAME_MS);
    frames++;
    assert.ok(frames < 200, 'the transition ends');
  }
  for (let i = 0; i < 3; i++) state = await step(page, now += FRAME_MS);
  const meter = await page.evaluate(() => document.getElementById('viewer').meter());
  return { meter, frames, state, k, now };
}

const describe = (m) => ['popping', 'alpha', 'geomorph'].map((x) => `${x} silhouette ${m[x].silhouette.toFixed(3)} % shading ${m[x].shading.toFixed(3)}`).join('; ');

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: the live meter measures each method's pop: geomorph and opaque-first blend ≤ 20 % of popping's`, async () => {
    const page = await openPage(browser, { backend }, { width: 960, height: 420 });
    // Paused: the only change from frame to frame is the transition's.
    const still = await transition(page, 1000, { paused: true });
    const { popping, alpha, geomorph } = still.meter;
    console.log(`${backend} meter, paused, level ${still.k - 1} → ${still.k} over ${still.frames} frames (${still.state.meter.size.join('×')} px, ${still.state.meter.gaps} gaps): ${describe(still.meter)}`);
    const history = await page.evaluate(() => document.getElementById('viewer').meterHistory());
    const series = (i) => history.samples.slice(-still.frames - 6).map((s) => s[2 + 2 * i].toFixed(4)).join(' ');
    console.log(`silhouette per frame, popping: ${series(0)}\n  geomorph: ${series(2)}`);
    assert.ok(still.frames >= 30, `the transition spans ${still.frames} drawn frames`);
    assert.ok(popping && alpha && geomorph, JSON.stringify(still.meter));
    assert.ok(popping.silhouette > 0.02, `popping changes the silhouette: ${popping.silhouette} %`);
    assert.ok(geomorph.silhouette <= 0.2 * popping.silhouette, `geomorph ${geomorph.silhouette} vs popping ${popping.silhouette}`);
    assert.ok(alpha.silhouette <= 0.2 * popping.silhouette, `opaque-first blend ${alpha.silhouette} vs popping ${popping.silhouette}`);
    assert.deepEqual(history.methods, ['popping', 'alpha', 'geomorph']);
    assert.ok(history.samples.length >= still.frames, `${history.samples.length} samples`);

    // Walking: the reference moves too, but the outline's rasterization changes every frame; the
    // pops then include that motion (reported, not asserted).
    const walking = await transition(page, still.now + 1000, { paused: false });
    console.log(`${backend} meter, walking: ${describe(walking.meter)} (transitions measured: ${walking.state.meter.transitions})`);
    assert.ok(walking.meter.popping && walking.meter.geomorph);

    // What the meter costs: the same frames with and without it (ratio in one run).
    const time = async (on) => page.evaluate(async ([on, start]) => {
      window.__clod.setState({ meter: on });
      let t = start;
      const begin = performance.now();
      for (let i = 0; i < 20; i++) { window.__clod.renderFrame(t += 16.7); await window.__clod.finish(); }
      return (performance.now() - begin) / 20;
    }, [on, walking.now + 1000]);
    const off1 = await time(false);
    const on1 = await time(true);
    const off2 = await time(false);
    const on2 = await time(true);
    console.log(`${backend} frame time with the meter: ${((on1 + on2) / 2).toFixed(1)} ms, without: ${((off1 + off2) / 2).toFixed(1)} ms (×${((on1 + on2) / (off1 + off2)).toFixed(2)})`);
  });
}
