// Shared helpers of the browser tests: headless Debian Chromium driven by playwright-core (never a
// downloaded browser), SwiftShader for both WebGPU (Vulkan) and WebGL2 (ANGLE), the page in test
// mode (?test=1: frames only on request, window.__clod hook), and pixel arithmetic on readbacks.
// The page URL comes from CLOD_URL (scripts/browser-test.sh starts the server).
import { chromium } from 'playwright-core';

export const baseUrl = process.env.CLOD_URL ?? 'http://127.0.0.1:8080/';

const ARGS = [
  '--no-sandbox', '--headless', '--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking',
  '--disable-component-update', '--disable-sync',
];

// Every page of the browser gets `window.__encodePixels` (see `decodePixels`).
export async function launch() {
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', args: ARGS });
  const newPage = browser.newPage.bind(browser);
  browser.newPage = async (options) => {
    const page = await newPage(options);
    await page.addInitScript(installPixelEncoder);
    return page;
  };
  return browser;
}

// In the page: `window.__encodePixels({ width, height, data })` returns `{ width, height, base64 }`.
// Pixels leave the page as base64 because playwright sends a plain array as JSON, one number at a
// time: a 1240×700 readback took 17 s that way and takes 0.3 s this way.
function installPixelEncoder() {
  window.__encodePixels = ({ width, height, data }) => {
    let binary = '';
    for (let i = 0; i < data.length; i += 0x8000) binary += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
    return { width, height, base64: btoa(binary) };
  };
}

// The other end of `window.__encodePixels`: `{ width, height, data: Uint8Array }`.
export function decodePixels({ width, height, base64 }) {
  return { width, height, data: new Uint8Array(Buffer.from(base64, 'base64')) };
}

// Opens the page in test mode and waits until it is ready (or failed). `query` adds parameters.
export async function openPage(browser, query = {}, viewport = { width: 1240, height: 700 }) {
  const page = await browser.newPage({ viewport, deviceScaleFactor: 1 });
  const logs = [];
  page.on('console', (m) => logs.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  const params = new URLSearchParams({ test: '1', ...query });
  await page.goto(`${baseUrl}?${params}`);
  try {
    await page.waitForFunction(() => document.documentElement.dataset.state !== 'loading', null, { timeout: 120_000 });
  } catch (e) {
    throw new Error(`page never left loading: ${logs.join('\n')}`);
  }
  const state = await page.evaluate(() => document.documentElement.dataset.state);
  if (state !== 'ready') {
    const alert = await page.locator('[role=alert]').textContent();
    throw new Error(`page state ${state}: ${alert}\n${logs.join('\n')}`);
  }
  // The full mesh is drawn first; the tests compare levels, so they wait for them.
  await page.waitForFunction(() => document.documentElement.dataset.lod === 'ready', null, { timeout: 120_000 });
  return page;
}

// Sets the viewer state, draws one frame at `nowMs`, and returns the viewer's state.
export function frame(page, nowMs, state = {}) {
  return page.evaluate(([s, t]) => { window.__clod.setState(s); return window.__clod.renderFrame(t); }, [state, nowMs]);
}

// Like `frame`, and waits for the GPU, so the meter's readback of this frame is back by the next.
export function step(page, nowMs, state = {}) {
  return page.evaluate(async ([s, t]) => {
    window.__clod.setState(s);
    const state = window.__clod.renderFrame(t);
    await window.__clod.finish();
    return state;
  }, [state, nowMs]);
}

// The current frame read back: `{ width, height, data: Uint8Array }` (RGBA, top row first).
export async function readPixels(page) {
  return decodePixels(await page.evaluate(async () => window.__encodePixels(await window.__clod.readPixels())));
}

// The RGB pixels of one view rectangle `[x, y, w, h]`, as a flat array (alpha dropped).
export function crop(pixels, [x, y, w, h]) {
  const out = new Uint8Array(w * h * 3);
  for (let row = 0; row < h; row++) {
    for (let col = 0; col < w; col++) {
      const src = 4 * ((y + row) * pixels.width + x + col);
      const dst = 3 * (row * w + col);
      out[dst] = pixels.data[src];
      out[dst + 1] = pixels.data[src + 1];
      out[dst + 2] = pixels.data[src + 2];
    }
  }
  return out;
}

// Sum of absolute channel differences of two equal-size crops, divided by the pixel count:
// the mean change per pixel (0..765).
export function meanAbsDiff(a, b) {
  let sum = 0;
  for (let i = 0; i < a.length; i++) sum += Math.abs(a[i] - b[i]);
  return sum / (a.length / 3);
}

// Fraction of pixels of a crop that differ from its corner pixel (the background) by more than
// `threshold` in some channel.
export function foregroundFraction(rgb, threshold = 24) {
  const [r, g, b] = [rgb[0], rgb[1], rgb[2]];
  let n = 0;
  for (let i = 0; i < rgb.length; i += 3) {
    if (Math.abs(rgb[i] - r) > threshold || Math.abs(rgb[i + 1] - g) > threshold || Math.abs(rgb[i + 2] - b) > threshold) n++;
  }
  return n / (rgb.length / 3);
}

// Writes RGBA pixels as a PNG (no dependency: stored zlib blocks are valid deflate).
export async function savePng(path, { width, height, data }) {
  const { writeFileSync } = await import('node:fs');
  const { deflateSync, crc32 } = await import('node:zlib');
  const raw = Buffer.alloc((4 * width + 1) * height);
  for (let y = 0; y < height; y++) {
    raw[y * (4 * width + 1)] = 0;
    Buffer.from(data.buffer, data.byteOffset + 4 * width * y, 4 * width).copy(raw, y * (4 * width + 1) + 1);
  }
  const chunk = (type, body) => {
    const len = Buffer.alloc(4); len.writeUInt32BE(body.length);
    const tb = Buffer.concat([Buffer.from(type), body]);
    const crc = Buffer.alloc(4); crc.writeUInt32BE(crc32(tb) >>> 0);
    return Buffer.concat([len, tb, crc]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(width, 0); ihdr.writeUInt32BE(height, 4);
  ihdr[8] = 8; ihdr[9] = 6; ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = 0;
  writeFileSync(path, Buffer.concat([
    Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk('IHDR', ihdr), chunk('IDAT', deflateSync(raw)), chunk('IEND', Buffer.alloc(0)),
  ]));
}

// Frame clock for deterministic runs: every call to `tick` advances `dtMs`.
export function clock(startMs = 1000) {
  let now = startMs;
  return { tick: (dtMs) => (now += dtMs), get now() { return now; } };
}

// Puts the schedule mid-transition from level `k - 1` to level `k` with blend `t` (time-driven),
// the animation paused at `time`: pops to `k - 1` just before the switch distance, moves just
// past it (the switch frame, t = 0), then steps 0.1 s frames with `duration` = 1 s until `t`.
// Returns the last state. `switchScale` places the switch at that many framing distances.
export async function midTransition(page, c, { k, t, methods, variant = 'opaque-first', switchAt = 1.5, time = 0.4 }) {
  let state = await frame(page, c.now, { paused: true, time, methods, variant, transition: 'time', duration: 0, hysteresis: 0.1, distanceMode: 'manual', distance: 1, tolerance: FINEST_TOLERANCE });
  const tolerance = tuneTolerance(state, k, switchAt);
  state = await frame(page, c.tick(100), { tolerance, distance: switchAt * 1.1 * 0.97 });
  if (state.selected !== k - 1) throw new Error(`expected level ${k - 1} before the switch, got ${state.selected}`);
  state = await frame(page, c.tick(100), { duration: 1, distance: switchAt * 1.1 * 1.03 });
  for (let i = 0; i < Math.round(t * 10); i++) state = await frame(page, c.tick(100));
  return state;
}

// A tolerance so small that every view starts at the finest level (the schedule's hysteresis
// would otherwise keep whatever level an earlier frame chose).
export const FINEST_TOLERANCE = 0.01;

// The tolerance (pixels) that puts level `k`'s switch distance at `switchAt` framing distances,
// from a state drawn with FINEST_TOLERANCE: switch distances scale as 1 / tolerance.
export function tuneTolerance(state, k, switchAt) {
  const current = state.switch[k];
  if (!(current > 0)) throw new Error(`level ${k} has no switch distance: ${JSON.stringify(state.switch)}`);
  return FINEST_TOLERANCE * current / switchAt;
}

// `viewer.measurePopSpike(options)` on the page's viewer (see src/web/pop_spike.rs), through the
// test hook.
export function measurePopSpike(page, nowMs, options = {}) {
  return page.evaluate((o) => window.__clod.measurePopSpike(o), options);
}

// A viewport for tests that draw many frames: a 668 × 223 canvas (three views about 220 px
// square), a tenth of the default page's pixels, so SwiftShader draws it quickly.
export const SMALL_VIEWPORT = { width: 700, height: 600 };

// Mean |ΔRGB| per pixel of each view between the current picture with `state` applied and
// without (the state is applied, a frame drawn at the same time, read back), then `undo` applied.
// Returns `{ diffs: [3 numbers], pixels }` (the pixels with `state`).
export async function viewChanges(page, nowMs, state, undo) {
  const base = await frame(page, nowMs, undo);
  const before = await readPixels(page);
  const changed = await frame(page, nowMs, state);
  if (changed.errors.length) throw new Error(changed.errors.join('\n'));
  const pixels = await readPixels(page);
  await frame(page, nowMs, undo);
  const diffs = base.views.map((v) => meanAbsDiff(crop(before, v.rect), crop(pixels, v.rect)));
  return { diffs, pixels };
}
