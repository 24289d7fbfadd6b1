// Prints the gzip size of what the page downloads — HTML, CSS, main.js, the <clod-viewer> element
// and its worker, and one wasm build with its JS glue (the worker reuses the page's, from the HTTP
// cache) — for the WebGPU build and the WebGL2 fallback, against wasm-pack.toml's budgets, and the
// Draco decoder's module, which only a Draco-compressed file fetches. Exits 1 when a page is over
// its budget. `node scripts/page-size.mjs [--json]`.
import { existsSync, readFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { readManifest } from './manifest.mjs';

const repo = fileURLToPath(new URL('..', import.meta.url));
const manifest = readManifest();
const gz = (path) => gzipSync(readFileSync(join(repo, path)), { level: 9 }).length;
const shell = ['www/index.html', 'www/style.css', 'www/main.js', 'www/clod-viewer.js', 'www/clod-replay.js', 'www/clod-loading.js', 'www/clod-worker.js'].reduce((n, p) => n + gz(p), 0);
const module = (section) => {
  const dir = manifest[`${section}.out-dir`];
  const name = manifest[`${section}.out-name`];
  return { wasm: gz(`${dir}/${name}_bg.wasm`), js: gz(`${dir}/${name}.js`) };
};
const build = (section) => {
  const { wasm, js } = module(section);
  return { wasm, js, total: wasm + js + shell };
};
const draco = existsSync(join(repo, manifest['draco.out-dir'])) ? module('draco') : null;
const sizes = { shell, webgpu: build('web'), webgl2: build('webgl'), draco };
const budgets = { webgpu: manifest['budget.page-gzip-bytes'], webgl2: manifest['budget.webgl-page-gzip-bytes'] };
if (process.argv.includes('--json')) {
  console.log(JSON.stringify({ ...sizes, budgets }));
} else {
  const kib = (n) => `${(n / 1024).toFixed(1)} KiB`;
  for (const which of ['webgpu', 'webgl2']) {
    const s = sizes[which];
    console.log(`page (${which}): ${kib(s.total)} gzip = wasm ${kib(s.wasm)} + glue ${kib(s.js)} + html/css/js ${kib(shell)}; budget ${kib(budgets[which])}`);
  }
  if (draco) console.log(`Draco module (only for Draco-compressed files): ${kib(draco.wasm + draco.js)} gzip = wasm ${kib(draco.wasm)} + glue ${kib(draco.js)}`);
}
let over = false;
for (const which of ['webgpu', 'webgl2']) {
  if (sizes[which].total > budgets[which]) {
    console.error(`the ${which} page is over budget: ${sizes[which].total} > ${budgets[which]} gzip bytes`);
    over = true;
  }
}
if (over) process.exit(1);
