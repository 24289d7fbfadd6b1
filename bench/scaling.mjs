// How the LOD build scales with the input: build time per input triangle and the wasm memory the
// build needed, from about 6k to 820k triangles of the same character (make-character --detail F,
// generated into target/scaling/ once; not committed). Each size builds in a fresh node process
// with a fresh wasm instance, exactly as the page's worker does (Character.buildClodBytes: the
// whole build plus encoding), best of --runs builds (default 3; 1 above 300k triangles).
//
//   npm ci && wasm-pack build --release --target nodejs --out-dir target/pkg-node -- --features js
//   node bench/scaling.mjs [--details 0.125,0.25,1,2,4,16] [--runs N]
//
// Prints one row per size and the time per triangle relative to the built-in character's
// (detail 1), measured in the same run; and the same for meshoptimizer's `simplify` and
// `simplifyWithUpdate` chains of each file (bench/meshopt-chains.mjs), timed in the same process.

import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../', import.meta.url));
const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};

if (args[0] === '--one') {
  // Child: one build of one file, and meshoptimizer's chains of it, printed as JSON.
  const { api } = await import('../tests/js/models.mjs');
  const { loadModel } = await import('./models.mjs');
  const { FRACTIONS, meshoptAttributeChain, meshoptLevels } = await import('./meshopt-chains.mjs');
  const { meshoptAttributeInput, weldByPosition } = await import('./meshopt-input.mjs');
  const bytes = new Uint8Array(readFileSync(args[1]));
  const runs = Number(args[2]);
  const { character, json } = loadModel(args[1]);
  const best = (fn) => {
    let ms = Infinity;
    for (let r = 0; r < runs; r++) {
      const started = performance.now();
      fn();
      ms = Math.min(ms, performance.now() - started);
    }
    return ms;
  };
  let chainBytes = 0;
  let reports = 0;
  const ms = best(() => { chainBytes = character.buildClodBytes({}, () => { reports += 1; }).length; });
  const memoryBytes = api.wasmMemoryBytes();
  // The peer, in the same process: its chains to the benchmark's counts (bench/meshopt-chains.mjs).
  const counts = FRACTIONS.map((f) => Math.max(1, Math.round(character.triangleCount * f)));
  const welded = weldByPosition(character.indices(), character.bindPositions());
  const input = meshoptAttributeInput(character, json);
  const simplifyMs = best(() => meshoptLevels(welded.indices, welded.positions, counts, true));
  const updateMs = best(() => meshoptAttributeChain(input, counts, true));
  console.log(JSON.stringify({
    triangles: character.triangleCount,
    ms,
    simplifyMs,
    updateMs,
    glbBytes: bytes.length,
    chainBytes,
    progressReports: reports / runs,
    memoryBytes,
  }));
  process.exit(0);
}

const details = option('--details', '0.125,0.25,1,2,4,16').split(',').map(Number);
const dir = `${root}target/scaling`;
mkdirSync(dir, { recursive: true });
const rows = [];
for (const detail of details) {
  const file = `${dir}/character-x${detail}.glb`;
  if (!existsSync(file)) {
    execFileSync('cargo', ['run', '--release', '--quiet', '-p', 'make-character', '--', '--detail', String(detail), file], { stdio: 'ignore' });
  }
  const triangles = 50_972 * detail;
  const runs = option('--runs', triangles > 300_000 ? '1' : '3');
  const out = execFileSync(process.execPath, [fileURLToPath(import.meta.url), '--one', file, runs], { encoding: 'utf8', maxBuffer: 1 << 20 });
  rows.push({ detail, ...JSON.parse(out.trim().split('\n').pop()) });
}
const reference = rows.find((r) => r.detail === 1) ?? rows[0];
// Time per input triangle of `key`'s build, × the reference size's.
const growth = (r, key) => ((r[key] / r.triangles) / (reference[key] / reference.triangles)).toFixed(2);
console.log('| triangles | build (ms) | µs / triangle | × the 51k character\'s | meshoptimizer per triangle, × its 51k: `simplify` chain, `simplifyWithUpdate` chain | chain / .glb | wasm memory (MB) | progress reports |');
console.log('|---|---|---|---|---|---|---|---|');
for (const r of rows) {
  console.log(`| ${r.triangles.toLocaleString('en')} | ${r.ms.toFixed(0)} | ${((1000 * r.ms) / r.triangles).toFixed(2)} | ` +
    `${growth(r, 'ms')} | ${growth(r, 'simplifyMs')}, ${growth(r, 'updateMs')} | ${(r.chainBytes / r.glbBytes).toFixed(2)} | ` +
    `${(r.memoryBytes / 2 ** 20).toFixed(0)} | ${r.progressReports} |`);
}
