// Benchmark: our articulated progressive mesh against meshoptimizer's wasm simplifier, in one node process.
//
//   wasm-pack build --release --target nodejs --out-dir target/pkg-node -- --features js && npm ci
//   node bench/lod-vs-meshoptimizer.mjs [--samples N] [--frames N] [--build-only] [MODEL.glb|.gltf|FOLDER...]
//
// For each model in ../shared/models and the built-in character (or each named on the command line, see
// bench/models.mjs) it prints, as ratios measured in this run:
//  1. build time: ours (progressive mesh + LOD chain + correspondences) vs meshoptimizer simplifying the same
//     merged, position-welded mesh to 50/25/10/5/1 % independently and as a chain (each level from the last),
//     each the best of at least 5 runs and of as many as fit in 1.5 s; and, for context, meshoptimizer doing
//     our job: the file's vertices with their seams, normals and uv priced (`meshoptAttributeInput`),
//     keeping vertices (simplifyWithAttributes) or moving them (simplifyWithUpdate), as a chain. Every
//     meshoptimizer input is compacted (no unused vertices, see `compact` in meshopt-input.mjs);

//  2. geometric error in the bind pose at the same triangle counts (symmetric sampled distance, % of the bbox
//     diagonal, same seed and sample count for both); then the same against simplifyWithUpdate's chain;
//  3. animated error: every LOD and the full mesh skinned at frames of every clip, for bind-pose, multi-pose
//     and mid-clip (the default: the middle frame of the first clip) simplification;
//  4. the native build time of the same build (`cargo run --release --example clod_timing`, run from here).
import { execFileSync } from 'node:child_process';
import { MeshoptSimplifier } from 'meshoptimizer';
import { api } from '../tests/js/models.mjs';
import { FRACTIONS, meshoptAttributeChain, meshoptLevels } from './meshopt-chains.mjs';
import { meshoptAttributeInput, weldByPosition } from './meshopt-input.mjs';
import { loadModel, modelPaths } from './models.mjs';

// --build-only prints the build times (1 and 4) and skips the error measurements.
const BUILD_ONLY = process.argv.includes('--build-only');
// `--samples N` and `--frames N` take a value; every other argument that is not an option names a model.
const argv = process.argv.slice(2).filter((a) => a !== '--build-only');
const valued = new Set(argv.flatMap((a, i) => (a.startsWith('--') ? [i + 1] : [])));
const args = Object.fromEntries(argv.flatMap((a, i) => (a.startsWith('--') ? [[a.slice(2), argv[i + 1]]] : [])));
const modelArgs = argv.filter((a, i) => !a.startsWith('--') && !valued.has(i));
const SAMPLES = Number(args.samples ?? 20000);
const FRAMES = Number(args.frames ?? 6);
const SEED = 12345;

await MeshoptSimplifier.ready;

const now = () => performance.now();
const pct = (d, diag) => (100 * d / diag).toFixed(3);

/**
 * Best time of `fn`: at least `minRuns` runs and as many as fit in `budgetMs`. The machine is shared,
 * so one slow run says little; small models build in about a millisecond, so they get many runs.
 */
function timeIt(fn, minRuns = 5, budgetMs = 1500) {
  let best = Infinity, result;
  const started = now();
  for (let r = 0; r < minRuns || now() - started < budgetMs; r++) {
    const t0 = now();
    result = fn();
    best = Math.min(best, now() - t0);
  }
  return [result, best];
}

/** Native build times (ms) of the same builds, from examples/clod_timing.rs, keyed by file path. */
function nativeTimes(paths) {
  const out = execFileSync('cargo', ['run', '--release', '--quiet', '--example', 'clod_timing', '--', ...paths], { encoding: 'utf8' });
  return Object.fromEntries(out.trim().split('\n').map((line) => JSON.parse(line)).map((r) => [r.file, r.ms]));
}

// A file that does not import is skipped with the importer's message; the others still run.
const paths = modelPaths(modelArgs, ['character.glb']).filter((path) => {
  try {
    loadModel(path).character.free();
    return true;
  } catch (error) {
    console.log(`skipped: ${error.message}`);
    return false;
  }
});
const native = nativeTimes(paths);

for (const path of paths) {
  const { name, json, character } = loadModel(path);
  const indices = character.indices();
  const positions = character.bindPositions();
  const diag = api.boundsDiagonal(positions);
  const full = character.triangleCount;
  const counts = FRACTIONS.map((f) => Math.max(1, Math.round(full * f)));
  const welded = weldByPosition(indices, positions);

  const [, meshoptIndependentMs] = timeIt(() => meshoptLevels(welded.indices, welded.positions, counts, false));
  const [meshopt, meshoptChainMs] = timeIt(() => meshoptLevels(welded.indices, welded.positions, counts, true));
  const input = meshoptAttributeInput(character, json);
  const [, withAttributesMs] = timeIt(() => meshoptAttributeChain(input, counts, false));
  const [updated, withUpdateMs] = timeIt(() => meshoptAttributeChain(input, counts, true));
  // The default build (timed), and a bind-pose build for the static comparison: meshoptimizer
  // simplifies the bind-pose mesh, so ours is compared simplifying the same pose.
  const [, oursMs] = timeIt(() => character.buildClod({ levels: counts }).free());
  // The same build with batched collapse passes (`schedule: 'passes'`), for the ratio between the two.
  const [, passesMs] = timeIt(() => character.buildClod({ levels: counts, schedule: 'passes' }).free());
  // Simplifying one static pose, as meshoptimizer does: our build without the multi-pose frames.
  const [, oursBindMs] = timeIt(() => character.buildClod({ levels: counts, pose: 'bind' }).free());
  const attributeLine = `meshoptimizer chain with ${input.what}: simplifyWithAttributes ${withAttributesMs.toFixed(1)} ms, ` +
    `simplifyWithUpdate ${withUpdateMs.toFixed(1)} ms; ours in the bind pose ${oursBindMs.toFixed(1)} ms: ` +
    `ratio ours/update chain = ${(oursMs / withUpdateMs).toFixed(2)} (bind pose ${(oursBindMs / withUpdateMs).toFixed(2)})`;
  if (BUILD_ONLY) {
    console.log(`${name}: ours ${oursMs.toFixed(1)} ms, meshoptimizer chain ${meshoptChainMs.toFixed(1)} ms: ` +
      `ratio ${(oursMs / meshoptChainMs).toFixed(2)}; ours native ${native[path].toFixed(1)} ms`);
    console.log(`  ${attributeLine}`);
    console.log(`  ours with schedule 'passes' ${passesMs.toFixed(1)} ms: ratio passes/strict = ${(passesMs / oursMs).toFixed(2)}, ` +
      `passes/chain = ${(passesMs / meshoptChainMs).toFixed(2)}, passes/update chain = ${(passesMs / withUpdateMs).toFixed(2)}`);
    character.free();
    continue;
  }
  const clod = character.buildClod({ levels: counts, pose: 'bind' });

  console.log(`\n## ${name}: ${full} triangles, ${character.vertexCount} vertices, ${character.jointCount} joints`);
  console.log(`build: ours ${oursMs.toFixed(1)} ms, meshoptimizer chain ${meshoptChainMs.toFixed(1)} ms ` +
    `(independent ${meshoptIndependentMs.toFixed(1)} ms): ratio ours/chain = ${(oursMs / meshoptChainMs).toFixed(2)}; ` +
    `ours native ${native[path].toFixed(1)} ms (wasm/native ${(oursMs / native[path]).toFixed(2)})`);
  console.log(attributeLine);

  // Compare at the same triangle count: where one side stopped short of a target, the other is
  // taken to that side's count too (ours through the continuous LOD, meshoptimizer re-run).
  console.log('| target | triangles | mean ours % | mean meshopt % | ratio | hausdorff ours % | hausdorff meshopt % |');
  console.log('|---|---|---|---|---|---|---|');
  for (let i = 0; i < counts.length; i++) {
    const ourCount = clod.meshAt(counts[i]).indices.length / 3;
    const common = Math.max(ourCount, meshopt[i].length / 3);
    const ours = clod.meshAt(common);
    let theirs = meshopt[i];
    if (theirs.length / 3 > common) theirs = MeshoptSimplifier.simplify(welded.indices, welded.positions, 3, common * 3, 1.0, [])[0];
    const dOurs = api.surfaceDistance(positions, indices, ours.bindPositions, ours.indices, SAMPLES, SEED);
    const dTheirs = api.surfaceDistance(positions, indices, welded.positions, theirs, SAMPLES, SEED);
    const shown = ours.indices.length / 3 === theirs.length / 3 ? `${theirs.length / 3}` : `${ours.indices.length / 3} / ${theirs.length / 3}`;
    console.log(`| ${FRACTIONS[i] * 100}% | ${shown} | ${pct(dOurs.mean, diag)} | ${pct(dTheirs.mean, diag)} | ` +
      `${(dOurs.mean / dTheirs.mean).toFixed(2)} | ${pct(dOurs.hausdorff, diag)} | ${pct(dTheirs.hausdorff, diag)} |`);
  }

  // The same job: simplifyWithUpdate's levels, each at the count it reached, and ours at that count
  // (or at our floor, when it is above).
  console.log('| target | triangles (ours / update) | mean ours % | mean update % | hausdorff ours % | hausdorff update % |');
  console.log('|---|---|---|---|---|---|');
  for (let i = 0; i < counts.length; i++) {
    const level = updated[i];
    const theirCount = level.indices.length / 3;
    const ours = clod.meshAt(theirCount);
    const dOurs = api.surfaceDistance(positions, indices, ours.bindPositions, ours.indices, SAMPLES, SEED);
    const dTheirs = api.surfaceDistance(positions, indices, level.positions, level.indices, SAMPLES, SEED);
    const ourCount = ours.indices.length / 3;
    const shown = ourCount === theirCount ? `${theirCount}` : `${ourCount} / ${theirCount}`;
    console.log(`| ${FRACTIONS[i] * 100}% | ${shown} | ${pct(dOurs.mean, diag)} | ${pct(dTheirs.mean, diag)} | ` +
      `${pct(dOurs.hausdorff, diag)} | ${pct(dTheirs.hausdorff, diag)} |`);
  }
  clod.free();

  // Animated error: each pose choice, every level vs the full mesh skinned at the same frames.
  const poses = { bind: 'bind', multi: 'multi', 'mid-clip': 'mid-clip' };
  // Every pose at the same triangle counts: the largest any pose reached for each target.
  const reached = Object.values(poses).map((pose) => {
    const built = character.buildClod({ pose, levels: counts });
    const got = Array.from({ length: built.levelCount }, (_, i) => built.level(i).triangleCount);
    built.free();
    return counts.map((_, i) => got[Math.min(i, got.length - 1)]);
  });
  const commonCounts = [...new Set(counts.map((_, i) => Math.max(...reached.map((r) => r[i]))))].sort((x, y) => y - x);
  const animated = {};
  for (const [label, pose] of Object.entries(poses)) {
    const built = character.buildClod({ pose, levels: commonCounts });
    let sum = 0, n = 0, worst = 0;
    for (const clip of character.clipNames) {
      for (let f = 0; f < FRAMES; f++) {
        const t = character.clipDuration(clip) * (f + 0.5) / FRAMES;
        const fullPosed = character.skinnedPositions(clip, t);
        for (let i = 0; i < built.levelCount; i++) {
          const level = built.level(i);
          const d = api.surfaceDistance(fullPosed, indices, built.levelSkinnedPositions(i, clip, t), level.indices, SAMPLES / 4, SEED);
          sum += d.mean; worst = Math.max(worst, d.hausdorff); n++;
        }
      }
    }
    animated[label] = { mean: sum / n, hausdorff: worst };
    built.free();
  }
  console.log(`animated error at ${commonCounts.join('/')} triangles:`);
  console.log('  over all clips, frames and levels (mean / hausdorff, % of diagonal):');
  for (const [label, e] of Object.entries(animated)) {
    const vsBind = label === 'bind' ? '' : ` (${((1 - e.mean / animated.bind.mean) * 100).toFixed(1)} % lower than bind)`;
    console.log(`  ${label.padEnd(10)} ${pct(e.mean, diag)} / ${pct(e.hausdorff, diag)}${vsBind}`);
  }
  character.free();
}
