// (16) LDR-FLIP on the GPU (src/render/flip.wgsl, two fragment passes) against NVIDIA's reference
// implementation: the fixture pairs of tests/fixtures/flip/ uploaded through the test hook, the
// GPU's error map read back, its mean within 0.01 and its 99th percentile within 0.02 of
// `flip-evaluator` 1.7's (tests/fixtures/flip/reference.json, 67.02 pixels per degree); the
// native test (tests/flip.rs) checks the Rust version against the same numbers. WebGPU and WebGL2.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { inflateSync } from 'node:zlib';
import { launch, openPage, SMALL_VIEWPORT } from './helpers.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

const dir = new URL('../fixtures/flip/', import.meta.url);
const reference = JSON.parse(readFileSync(new URL('reference.json', dir), 'utf8'));

// An 8-bit RGB PNG without row filters (what make_pairs.py writes) as RGBA8, base64.
function readPng(name) {
  const bytes = readFileSync(new URL(name, dir));
  let at = 8;
  let width = 0;
  let height = 0;
  const idat = [];
  while (at < bytes.length) {
    const length = bytes.readUInt32BE(at);
    const kind = bytes.toString('latin1', at + 4, at + 8);
    const body = bytes.subarray(at + 8, at + 8 + length);
    if (kind === 'IHDR') { width = body.readUInt32BE(0); height = body.readUInt32BE(4); }
    if (kind === 'IDAT') idat.push(body);
    at += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const rgba = Buffer.alloc(4 * width * height);
  for (let y = 0; y < height; y++) {
    assert.equal(raw[y * (1 + 3 * width)], 0, 'rows without a filter');
    for (let x = 0; x < width; x++) {
      const src = y * (1 + 3 * width) + 1 + 3 * x;
      raw.copy(rgba, 4 * (y * width + x), src, src + 3);
      rgba[4 * (y * width + x) + 3] = 255;
    }
  }
  return { width, height, base64: rgba.toString('base64') };
}

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: flip.wgsl matches flip-evaluator 1.7 on the fixture pairs (mean ±0.01, p99 ±0.02)`, async () => {
    const page = await openPage(browser, { backend }, SMALL_VIEWPORT);
    for (const pair of reference.pairs) {
      const [r, t] = [readPng(pair.reference), readPng(pair.test)];
      const ours = await page.evaluate(async ([r, t, ppd]) => {
        const bytes = (b64) => Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
        return window.__clod.flipImages(bytes(r.base64), bytes(t.base64), r.width, r.height, ppd);
      }, [r, t, reference.ppd]);
      assert.ok(ours, `${backend} renders into float targets`);
      console.log(`${backend} ${pair.name}: mean ${ours.mean.toFixed(5)} (reference ${pair.mean.toFixed(5)}), p99 ${ours.p99.toFixed(5)} (reference ${pair.p99.toFixed(5)}), max ${ours.max.toFixed(4)} (${pair.max.toFixed(4)})`);
      assert.ok(Math.abs(ours.mean - pair.mean) <= 0.01, `${pair.name} mean ${ours.mean} vs ${pair.mean}`);
      assert.ok(Math.abs(ours.p99 - pair.p99) <= 0.02, `${pair.name} p99 ${ours.p99} vs ${pair.p99}`);
    }
    const state = await page.evaluate(() => window.__clod.state());
    assert.deepEqual(state.errors, []);
  });
}
