// The npm package (bash scripts/package.sh → target/package/clod-viewer-VERSION.tgz), installed
// as an author would install it (tests/browser/package-site.mjs): a plain HTML page imports the
// element from node_modules/ by a bare specifier (an import map) and shows the built-in character
// from the package's own assets; the element draws in every view and reaches its levels, on
// WebGPU and on the WebGL2 fallback, and the package holds what package.json says and nothing
// the page does not need. (tests/browser/embed.test.mjs runs the embedding tests against the
// package too.)
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { launch, crop, foregroundFraction, decodePixels } from './helpers.mjs';
import { packageSite } from './package-site.mjs';

const page = (backend) => `<!doctype html>
<html lang="en">
<head>
  <meta charset="utf-8">
  <title>A page using the clod-viewer package</title>
  <script type="importmap">{ "imports": { "clod-viewer": "./node_modules/clod-viewer/clod-viewer.js" } }</script>
  <script type="module">
    import { ERROR_CODES } from 'clod-viewer';
    window.__codes = Object.keys(ERROR_CODES);
  </script>
</head>
<body>
  <clod-viewer id="viewer" modes="pop blend morph" clip="Walk" backend="${backend}" style="width: 900px; aspect-ratio: 3 / 1"></clod-viewer>
</body>
</html>
`;

let browser;
let site;
before(async () => {
  browser = await launch();
  site = await packageSite({ 'webgpu.html': page('webgpu'), 'webgl2.html': page('webgl2') });
});
after(async () => {
  await browser?.close();
  site?.close();
});

test('the package holds the element, its worker, both wasm builds, the Draco module, the character and the types', () => {
  const root = join(site.dir, 'node_modules/clod-viewer');
  const pkg = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));
  assert.equal(pkg.name, 'clod-viewer');
  assert.equal(pkg.types, './clod-viewer.d.ts');
  assert.equal(pkg.exports['.'].default, './clod-viewer.js');
  for (const file of pkg.files) assert.ok(existsSync(join(root, file)), `${file} is listed and installed`);
  for (const file of ['clod-viewer.js', 'clod-replay.js', 'clod-loading.js', 'clod-worker.js', 'clod-viewer.d.ts', 'assets/character.glb', 'pkg/clod_viewer_bg.wasm',
    'pkg-webgl/clod_viewer_bg.wasm', 'pkg-draco/clod_draco_bg.wasm', 'README.md']) {
    assert.ok(existsSync(join(root, file)), `${file} is in the package`);
  }
  // Nothing of the repository's page, tests or sources.
  const top = readdirSync(root).sort();
  assert.deepEqual(top, ['README.md', 'assets', 'clod-loading.js', 'clod-replay.js', 'clod-viewer.d.ts', 'clod-viewer.js', 'clod-worker.js', 'package.json', 'pkg', 'pkg-draco', 'pkg-webgl']);
  assert.deepEqual(readdirSync(join(root, 'assets')), ['character.glb']);
});

for (const backend of ['webgpu', 'webgl2']) {
  test(`${backend}: a page that imports the package from node_modules draws the built-in character and reaches its levels`, async (t) => {
    const tab = await browser.newPage({ viewport: { width: 1000, height: 500 }, deviceScaleFactor: 1 });
    t.after(() => tab.close());
    const logs = [];
    tab.on('console', (m) => logs.push(`${m.type()}: ${m.text()}`));
    tab.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
    const requests = [];
    tab.on('request', (r) => requests.push(new URL(r.url()).pathname));
    await tab.addInitScript(() => {
      window.__events = [];
      for (const type of ['load', 'lod', 'error']) {
        document.addEventListener(type, (e) => {
          if (e.target.localName === 'clod-viewer') window.__events.push({ type, detail: type === 'error' ? e.detail : { triangles: e.detail.triangles, levels: e.detail.levels.length, backend: e.detail.backend } });
        }, true);
      }
    });
    await tab.goto(new URL(`${backend}.html`, site.url).href);
    try {
      await tab.waitForFunction(() => window.__events.some((e) => e.type === 'lod' || e.type === 'error'), null, { timeout: 180_000 });
    } catch {
      throw new Error(`no lod event: ${logs.join('\n')}`);
    }
    const events = await tab.evaluate(() => window.__events);
    assert.deepEqual(events.map((e) => e.type), ['load', 'lod'], JSON.stringify(events));
    assert.equal(events[1].detail.triangles, 50_972);
    assert.equal(events[1].detail.backend, backend);
    assert.ok(events[1].detail.levels > 1, `${events[1].detail.levels} levels`);
    assert.deepEqual(await tab.evaluate(() => window.__codes), ['fetch', 'model', 'levels', 'no-gpu', 'wasm', 'attribute', 'render']);
    const { state, encoded } = await tab.evaluate(async () => {
      const el = document.getElementById('viewer');
      el.pause();
      el.setTime(0.4);
      el.setState({ distanceMode: 'manual', distance: 1 });
      await el.finish();
      const state = el.state();
      return { state, encoded: window.__encodePixels(await el.readPixels()) };
    });
    const pixels = decodePixels(encoded);
    assert.equal(state.views.length, 3);
    state.views.forEach((v, i) => {
      const f = foregroundFraction(crop(pixels, v.rect));
      assert.ok(f > 0.02, `view ${i} (${v.method}) is blank: ${f}`);
    });
    // Everything came from the package, and a file without Draco never fetched the decoder.
    const own = requests.filter((p) => p.startsWith('/node_modules/clod-viewer/'));
    assert.ok(own.includes('/node_modules/clod-viewer/assets/character.glb'), own.join(', '));
    assert.ok(own.includes(`/node_modules/clod-viewer/${backend === 'webgpu' ? 'pkg' : 'pkg-webgl'}/clod_viewer_bg.wasm`), own.join(', '));
    assert.ok(!own.some((p) => p.includes('pkg-draco')), own.join(', '));
    assert.deepEqual(logs.filter((l) => l.startsWith('pageerror')), []);
  });
}
