// The LOD build's speed in two or more node builds of the JS API, in one process: each build is a
// folder holding wasm-pack's `--target nodejs` output (clod_viewer.js and clod_viewer_bg.wasm),
// e.g. the same build before and after `wasm-opt -Oz`, or built with another Cargo opt-level.
// Runs `Character.buildClodBytes` on each model, the builds alternating, and prints the median
// time of each build and its ratio to the first.
//   node bench/build-ab.mjs [--runs N] DIR_A DIR_B [DIR_C …] [-- MODEL.glb …]
// Models default to the built-in character and ../shared/models/CesiumMan.glb.
import { createRequire } from 'node:module';
import { existsSync, readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const args = process.argv.slice(2);
const split = args.indexOf('--');
const runsAt = args.indexOf('--runs');
const runs = runsAt >= 0 ? Number(args[runsAt + 1]) : 7;
const dirs = (split >= 0 ? args.slice(0, split) : args).filter((a, i, all) => a !== '--runs' && all[i - 1] !== '--runs');
const repo = fileURLToPath(new URL('..', import.meta.url));
const models = split >= 0 ? args.slice(split + 1)
  : [`${repo}assets/character.glb`, `${repo}../shared/models/CesiumMan.glb`].filter((p) => existsSync(p));
if (dirs.length < 2) {
  console.error('usage: node bench/build-ab.mjs [--runs N] DIR_A DIR_B [DIR_C …] [-- MODEL.glb …]');
  process.exit(2);
}
const require = createRequire(import.meta.url);
const builds = dirs.map((d) => ({ dir: d, api: require(resolve(d, 'clod_viewer.js')) }));

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
for (const model of models) {
  const bytes = new Uint8Array(readFileSync(model));
  const characters = builds.map((b) => b.api.Character.fromBytes(bytes, () => null));
  const times = builds.map(() => []);
  // One warm-up build each, then `runs` rounds, each build once per round.
  for (let round = -1; round < runs; round++) {
    builds.forEach((_, i) => {
      const started = performance.now();
      characters[i].buildClodBytes({});
      if (round >= 0) times[i].push(performance.now() - started);
    });
  }
  characters.forEach((c) => c.free());
  const base = median(times[0]);
  console.log(`${model.split('/').pop()} (median of ${runs}):`);
  builds.forEach((b, i) => {
    const m = median(times[i]);
    console.log(`  ${b.dir}: ${m.toFixed(0)} ms (${(m / base).toFixed(3)}×; range ${Math.min(...times[i]).toFixed(0)}–${Math.max(...times[i]).toFixed(0)})`);
  });
}
