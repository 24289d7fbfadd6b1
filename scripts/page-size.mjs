// Prints the gzip size of what the page downloads — HTML, CSS, main.js, the <clod-viewer> element
// and its worker, and one wasm build with its JS glue (the worker reuses the page's, from the HTTP
// cache) — for the WebGPU build and the WebGL2 fallback, against wasm-pack.toml's budget.
// Exits 1 when the WebGPU page is over budget. `node scripts/page-size.mjs [--json]`.
import { readFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { readManifest } from './manifest.mjs';

const repo = fileURLToPath(new URL('..', import.meta.url));
const manifest = readManifest();
const gz = (path) => gzipSync(readFileSync(join(repo, path)), { level: 9 }).length;
const shell = ['www/index.html', 'www/style.css', 'www/main.js', 'www/clod-viewer.js', 'www/clod-replay.js', 'www/clod-worker.js'].reduce((n, p) => n + gz(p), 0);
const build = (section) => {
  const dir = manifest[`${section}.out-dir`];
  const name = manifest[`${section}.out-name`];
  const wasm = gz(`${dir}/${name}_bg.wasm`);
  const js = gz(`${dir}/${name}.js`);
  return { wasm, js, total: wasm + js + shell };
};
const sizes = { shell, webgpu: build('web'), webgl2: build('webgl') };
const budget = manifest['budget.page-gzip-bytes'];
if (process.argv.includes('--json')) {
  console.log(JSON.stringify({ ...sizes, budget }));
} else {
  const kib = (n) => `${(n / 1024).toFixed(1)} KiB`;
  for (const which of ['webgpu', 'webgl2']) {
    const s = sizes[which];
    console.log(`page (${which}): ${kib(s.total)} gzip = wasm ${kib(s.wasm)} + glue ${kib(s.js)} + html/css/js ${kib(shell)}`);
  }
  console.log(`budget: ${kib(budget)} for the WebGPU page`);
}
if (sizes.webgpu.total > budget) {
  console.error(`the WebGPU page is over budget: ${sizes.webgpu.total} > ${budget} gzip bytes`);
  process.exit(1);
}
