// Crowd mode's cost: frame time of the crowd with LOD against the same crowd forced to full
// detail, at several instance counts, per method; triangles drawn; and the CPU time of a frame
// (the viewer's `frame`: instance selection, records, encoding and submit, plus the state read).
// Headless Chromium on SwiftShader (WebGPU by default), one page, one camera path: every
// configuration draws the same frames of the same clock.
//
//   (source scripts/tools.sh; build_wasm web && build_wasm webgl)
//   MODELS_DIR=../shared/models PORT=0 node scripts/serve.mjs &     # prints its URL
//   CLOD_URL=http://127.0.0.1:PORT/ node bench/crowd.mjs [--counts 100,400,1600] [--frames 4] [--backend webgl2] [--model /models/CesiumMan.glb]
//
// Full detail is the same crowd with `crowdLod: false`: every instance at level 0, no
// transitions (so one row per count serves every method). One view per configuration, so a
// row's numbers are one method's. Frame time = `renderFrame` + `finish()` (the GPU done), the
// mean of `--frames` frames 100 ms of clock apart, after one warm-up frame.

import { launch, openPage, frame } from '../tests/browser/helpers.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const counts = option('--counts', '100,400,1600').split(',').map(Number);
const frames = Number(option('--frames', '4'));
const backend = option('--backend', 'webgpu');
// A model URL on the test server (`/models/CesiumMan.glb` serves ../shared/models); default the
// built-in character. SwiftShader needs tens of seconds for a frame of 20 M triangles, more than
// the viewer waits for the GPU: full-detail crowds of the 51k-triangle character stop at 100.
const model = option('--model', null);
// A 4:3 view of 480 × 360 framebuffer pixels.
const viewport = { width: 484, height: 364 };

const browser = await launch();
const page = await openPage(browser, { ...(backend === 'webgpu' ? {} : { backend }), ...(model ? { model } : {}) }, viewport);

// Draws `frames` frames of one configuration; returns mean frame and CPU milliseconds and the
// crowd's numbers of the last frame.
async function measure(state) {
  let now = 1000;
  await frame(page, now, { dollyPeriod: 16, distanceMode: 'dolly', meter: false, paused: false, time: 0, ...state });
  await page.evaluate(() => window.__clod.finish());
  let frameMs = 0;
  let cpuMs = 0;
  let last;
  for (let i = 0; i < frames; i++) {
    now += 100;
    const r = await page.evaluate(async (t) => {
      const start = performance.now();
      const s = window.__clod.renderFrame(t);
      const cpu = performance.now() - start;
      await window.__clod.finish();
      return { cpu, total: performance.now() - start, crowd: s.crowd };
    }, now);
    frameMs += r.total;
    cpuMs += r.cpu;
    last = r.crowd;
  }
  return { frameMs: frameMs / frames, cpuMs: cpuMs / frames, crowd: last };
}

const methods = [['popping', 'opaque-first'], ['alpha', 'opaque-first'], ['geomorph', 'opaque-first']];
console.log(`crowd frame times, ${model ?? 'built-in character'}, ${backend} on ${(await frame(page, 1000, {})).adapter}, ${viewport.width - 4} × ${viewport.height - 4} px, mean of ${frames} frames`);
console.log('| instances | method | drawn | triangles (LOD) | triangles (full) | ratio | frame ms LOD | frame ms full | full ÷ LOD | CPU ms / frame (LOD) |');
console.log('|---|---|---|---|---|---|---|---|---|---|');
for (const count of counts) {
  const base = { mode: 'crowd', count, methods: ['popping'], crowdLod: false };
  const full = await measure(base);
  for (const [method, variant] of methods) {
    const lod = await measure({ ...base, methods: [method], variant, crowdLod: true });
    const c = lod.crowd;
    console.log(`| ${count} | ${method} | ${c.drawn} | ${c.trianglesDrawn.toLocaleString('en')} | ${full.crowd.trianglesDrawn.toLocaleString('en')} | ` +
      `${(full.crowd.trianglesDrawn / c.trianglesDrawn).toFixed(1)}× | ${lod.frameMs.toFixed(0)} | ${full.frameMs.toFixed(0)} | ` +
      `${(full.frameMs / lod.frameMs).toFixed(1)}× | ${lod.cpuMs.toFixed(2)} |`);
  }
}
// CPU alone at the largest counts: the frame without waiting for the GPU, LOD on.
for (const count of [2000, 4096]) {
  const r = await measure({ mode: 'crowd', count, methods: ['geomorph'], crowdLod: true });
  console.log(`CPU per frame at ${count} instances (geomorph, ${r.crowd.drawn} drawn): ${r.cpuMs.toFixed(2)} ms`);
}
await browser.close();
