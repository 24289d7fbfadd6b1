// (2) Fairness: the three views differ only in the method. Forced to the same method — mid-
// transition, so every draw path runs — all three views are the same picture, pixel for pixel.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, openPage, readPixels, crop, clock, midTransition } from './helpers.mjs';

let browser;
let page;
before(async () => { browser = await launch(); page = await openPage(browser); });
after(async () => { await browser?.close(); });

const cases = [
  ['popping', 'opaque-first'],
  ['geomorph', 'opaque-first'],
  ['alpha', 'opaque-first'],
  ['alpha', 'naive'],
  ['alpha', 'dither'],
];

for (const [method, variant] of cases) {
  test(`three views forced to ${method}${method === 'alpha' ? ` (${variant})` : ''} are identical`, async () => {
    const state = await midTransition(page, clock(), { k: 4, t: 0.3, methods: [method, method, method], variant });
    assert.ok(state.views.every((v) => v.method === method));
    if (method !== 'popping') assert.ok(state.views[0].t > 0.2 && state.views[0].t < 0.4, `t = ${state.views[0].t}`);
    const pixels = await readPixels(page);
    const [a, b, c] = state.views.map((v) => crop(pixels, v.rect));
    let differing = 0;
    for (let i = 0; i < a.length; i++) if (a[i] !== b[i] || a[i] !== c[i]) differing++;
    assert.equal(differing, 0, `${differing} channel values differ between the views`);
  });
}
