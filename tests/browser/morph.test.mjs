// (10) Morph targets on the GPU: the robot's face (assets/robot.glb, three face targets driven by
// its "Talk" clip) changes the picture when the clip's weights apply and not otherwise, in every
// view, mid-geomorph included (both ends are morphed); views forced to geomorphing stay
// identical with morphs on. Then the same in crowd mode, where each instance reads its weights
// from its own pose palette row. On WebGPU and WebGL2.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, frame, readPixels, crop, clock, midTransition, savePng, SMALL_VIEWPORT } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// Pixels that differ between two RGB crops (`crop`'s three bytes per pixel).
function differing(a, b) {
  let n = 0;
  for (let i = 0; i < a.length; i += 3) {
    if (a[i] !== b[i] || a[i + 1] !== b[i + 1] || a[i + 2] !== b[i + 2]) n++;
  }
  return n;
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: the robot's face follows the clip's morph weights in every view, mid-geomorph too`, async () => {
    const page = await openPage(browser, { model: '/assets/robot.glb', ...(backend === 'webgl2' ? { backend } : {}) }, SMALL_VIEWPORT);
    const c = clock();
    let state = await frame(page, c.now, { clip: 'Talk', meter: false });
    assert.ok(state.morphTargets >= 3, `morph targets: ${state.morphTargets}`);
    assert.equal(state.morphs, true);
    assert.ok(!state.warnings.some((w) => /morph/.test(w)), state.warnings.join('\n'));
    // 1 s into "Talk": the blink is closed, the mouth half open, the smile at 0.5. The camera
    // close to the head: the face fills much of each view.
    const look = { pan: [0, 0.33], yaw: 0, pitch: 0 };
    for (const methods of [['geomorph', 'geomorph', 'geomorph'], ['popping', 'alpha', 'geomorph']]) {
      await frame(page, c.now, look);
      state = await midTransition(page, c, { k: 2, t: 0.5, methods, variant: 'dither', time: 1.0, switchAt: 0.6 });
      assert.equal(state.backend, backend);
      const on = await readPixels(page);
      state = await frame(page, c.now, { morphs: false });
      assert.equal(state.morphs, false);
      const off = await readPixels(page);
      await frame(page, c.now, { morphs: true });
      await savePng(`/tmp/clod-morph-${backend}-${methods.join('-')}.png`, on);
      const views = state.views.map((v) => [crop(on, v.rect), crop(off, v.rect)]);
      views.forEach(([a, b], i) => {
        const n = differing(a, b);
        assert.ok(n >= 30, `${methods[i]} view: ${n} pixels change when the morph weights apply (t = ${state.views[i].t})`);
      });
      if (methods[0] === methods[1]) {
        assert.ok(state.views[0].t > 0.2 && state.views[0].t < 0.8, `mid-geomorph: t = ${state.views[0].t}`);
        if (backend === 'webgpu') {
          const [a, b, d] = views.map(([x]) => x);
          assert.equal(differing(a, b) + differing(a, d), 0, 'views forced to geomorphing are identical with morphs on');
        }
      }
    }
    await page.close();
  });
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: crowd instances move their faces with their own clip time's morph weights`, async () => {
    const page = await openPage(browser, { model: '/assets/robot.glb', ...(backend === 'webgl2' ? { backend } : {}) }, SMALL_VIEWPORT);
    const c = clock();
    let state = await frame(page, c.now, { clip: 'Talk', meter: false });
    // The crowd starts when the levels arrive.
    for (let i = 0; i < 10 && state.levels.length < 2; i++) state = await frame(page, c.tick(200));
    // Every instance at full detail (the front row's faces are a few pixels each), paused.
    const crowd = { mode: 'crowd', count: 60, crowdLod: false, paused: true, time: 1.0, overlay: 'none', distanceMode: 'manual' };
    state = await frame(page, c.now, crowd);
    for (let i = 0; i < 2; i++) state = await frame(page, c.tick(300));
    assert.equal(state.mode, 'crowd');
    assert.equal(state.backend, backend);
    assert.equal(state.errors.length, 0, state.errors.join('\n'));
    const on = await readPixels(page);
    state = await frame(page, c.now, { morphs: false });
    const off = await readPixels(page);
    await savePng(`/tmp/clod-morph-crowd-${backend}.png`, on);
    for (const view of state.views) {
      const n = differing(crop(on, view.rect), crop(off, view.rect));
      assert.ok(n >= 30, `${view.method} view: ${n} pixels change when the crowd's morph weights apply`);
    }
    // Morphs back on: the same picture as before (the weights come back with the palette).
    await frame(page, c.now, { morphs: true });
    const again = await readPixels(page);
    for (const view of state.views) assert.equal(differing(crop(on, view.rect), crop(again, view.rect)), 0, view.method);
    await page.close();
  });
}
