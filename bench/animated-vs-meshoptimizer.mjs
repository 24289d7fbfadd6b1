// Benchmark (issue 14, item 3): our LOD levels against meshoptimizer 1.3 under animation, at the same
// triangle counts.
//
//   source scripts/tools.sh; build_wasm node && npm ci
//   node bench/animated-vs-meshoptimizer.mjs [--short] [--json FILE] [--baseline FILE] [MODEL.glb|.gltf|FOLDER...]
//
// For every model it has (the shared models CesiumMan, Fox, RiggedSimple, any other model in
// ../shared/models and the project's assets/character.glb, robot.glb, parts.glb; or the files named on
// the command line, see bench/models.mjs), the counts are our default build's levels from level 1 on
// (`buildClod()`: multi-pose simplification). At each count it simplifies the bind-pose mesh with
// meshoptimizer `simplify` and `simplifyWithAttributes` (normals and uv priced with weight 1 each) on the
// file's vertices with their seams, as issue 14 asks (what a gltf-transform user gets; uv only for a file
// without normals, see `meshoptAttributeInput`), each from the full mesh; and, shown beside but not a
// target, `simplify` on the mesh welded by position, which merges across uv and normal seams (its
// textures tear). Both keep a subset of the input vertices, so their
// indices skinned with the full mesh's `skinnedPositions(clip, t)` are their animated levels; ours are
// `levelSkinnedPositions(i, clip, t)`. Where a side stops short of a count, the comparison moves to the count
// ours and the meshoptimizer variant that went further both reached (ours rebuilt with those counts as its
// levels, meshoptimizer re-run); a variant still short of it is shown but not taken as the better one, and a
// model meshoptimizer cannot take to our coarsest level with its default flags is compared with `Permissive`
// where that goes further (robot.glb: every edge a normal seam), and one it cannot simplify even so is skipped
// with a line saying so.
//
// Error: symmetric sampled surface distance (seeded, same samples for all) against the full mesh skinned at
// the same frame, in % of the bind-pose bounding-box diagonal; mean averaged over frames, Hausdorff the
// worst frame. Frames: 4 of each of the first 2 clips ((f + 0.5) / 4 of the duration); --short: 2 frames of
// the first clip, 4,000 samples (the regression test, tests/js/animated.test.mjs, runs that form). For the
// worst level it prints the mean's two halves as well: the input's distance from the level (what the level
// misses) and the level's from the input (where it strays off the input's surface).
import { readFileSync, existsSync, statSync, writeFileSync } from 'node:fs';
import { basename } from 'node:path';
import { pathToFileURL } from 'node:url';
import { MeshoptSimplifier } from 'meshoptimizer';
import { api } from '../tests/js/models.mjs';
import { meshoptAttributeInput, uncompact, weldByPosition } from './meshopt-input.mjs';
import { loadModel, modelPaths } from './models.mjs';

const SEED = 12345;
// The targets: ours at most 0.8x the better meshoptimizer averaged over levels, 1.0x at every level.
export const TARGET_MEAN_RATIO = 0.8;
export const TARGET_WORST_RATIO = 1.0;
// Errors under 0.001 % of the diagonal count as 0.001 % in the ratios: that is 0.01 pixel on a character
// 1,000 pixels tall, invisible, and where float32 skinning noise lives, so a ratio of two such errors
// (parts.glb's first levels: lossless removal of flat-plate vertices by both) would be noise.
export const RATIO_FLOOR_PCT = 0.001;
export const FULL = { samples: 10000, frames: 4, clips: 2 };
export const SHORT = { samples: 4000, frames: 2, clips: 1 };

/** The project's test characters this benchmark measures by default, after the shared models. */
export const ASSET_NAMES = ['character.glb', 'robot.glb', 'parts.glb'];

/** One model file: per level the three errors, or `{ skipped }` when it has nothing to animate. */
function measureModel(path, { samples, frames, clips }) {
  let model;
  try {
    model = loadModel(path);
  } catch (error) {
    return { name: basename(path), skipped: error.message }; // the other models still run
  }
  const { name, json, character } = model;
  try {
    const clipNames = character.clipNames.slice(0, clips);
    if (character.jointCount === 0 || clipNames.length === 0) {
      return { name, skipped: `no ${character.jointCount === 0 ? 'skin' : 'animation clip'} to pose it with` };
    }
    const indices = character.indices();
    const positions = character.bindPositions();
    const diag = api.boundsDiagonal(positions);
    const input = meshoptAttributeInput(character, json);
    const welded = weldByPosition(indices, positions);
    let flags = [];
    // Each returns indices of the full mesh's vertices, so the full mesh's skinning poses them.
    const simplify = (n) => uncompact(
      MeshoptSimplifier.simplify(input.indices, input.positions, 3, n * 3, 1.0, flags)[0], input.vertices);
    const withAttributes = (n) => uncompact(MeshoptSimplifier.simplifyWithAttributes(
      input.indices, input.positions, 3, input.attributes, input.stride, input.weights, null, n * 3, 1.0, flags)[0],
    input.vertices);
    const simplifyWelded = (n) => uncompact(
      MeshoptSimplifier.simplify(welded.indices, welded.positions, 3, n * 3, 1.0, flags)[0], welded.vertices);

    const defaults = character.buildClod();
    const counts = Array.from({ length: defaults.levelCount - 1 }, (_, i) => defaults.level(i + 1).triangleCount);
    // Compared at the count ours and the meshoptimizer variant that went further both reached; the other
    // variant is re-run there, and where it stops short of it, it is shown but not taken as the better one.
    // The position-welded `simplify` is run at that count and shown beside, outside the target.
    const compare = () => counts.map((n) => {
      let s = simplify(n), a = withAttributes(n);
      const common = Math.max(n, Math.min(s.length / 3, a.length / 3));
      if (s.length / 3 !== common) s = simplify(common);
      if (a.length / 3 !== common) a = withAttributes(common);
      return { target: n, common, simplify: s, attributes: a };
    }).filter((r) => r.common < character.triangleCount);
    let rows = compare();
    // Where meshoptimizer cannot reach our coarsest level with its default flags (a flat-shaded file:
    // every edge a normal seam it will not cross), its `Permissive` flag lets collapses cross seams and
    // such vertices, which is what a user of it would try next; it is taken when it goes further.
    const reach = (r) => (r.length ? r[r.length - 1].common : character.triangleCount);
    let withoutPermissive = null;
    if (rows.length === 0 || rows[rows.length - 1].common > rows[rows.length - 1].target) {
      flags = ['Permissive'];
      const permissive = compare();
      if (reach(permissive) < reach(rows)) {
        withoutPermissive = reach(rows);
        rows = permissive;
      } else {
        flags = [];
      }
    }
    if (rows.length === 0) {
      defaults.free();
      return { name, skipped: `meshoptimizer keeps all ${character.triangleCount} triangles at every count, even with Permissive: nothing to compare` };
    }
    for (const row of rows) row.welded = simplifyWelded(row.common);
    const kept = rows.filter((r, k) => rows.slice(0, k).every((q) => r.common < q.common));
    const merged = rows.length - kept.length;
    const commons = kept.map((r) => r.common);
    let clod = defaults;
    let levelOf = (row) => counts.indexOf(row.target) + 1;
    if (rows.some((r) => r.common !== r.target)) {
      clod = character.buildClod({ levels: commons });
      // Its level 0 is the full mesh; each common count gets the first level at or under it.
      const got = Array.from({ length: clod.levelCount }, (_, i) => clod.level(i).triangleCount);
      levelOf = (row) => got.findIndex((t) => t <= row.common);
      defaults.free();
    }
    const unique = kept;

    // Per variant: the sums of the mean and of its two halves (the input's samples from the level: what
    // the level misses; the level's from the input: where it strays), and the largest distance.
    const sums = unique.map(() => ({ ours: [0, 0, 0, 0], simplify: [0, 0, 0, 0], attributes: [0, 0, 0, 0], welded: [0, 0, 0, 0] }));
    let n = 0;
    for (const clip of clipNames) {
      for (let f = 0; f < frames; f++) {
        const t = character.clipDuration(clip) * (f + 0.5) / frames;
        const full = character.skinnedPositions(clip, t);
        const add = (acc, d) => {
          acc[0] += d.mean; acc[1] = Math.max(acc[1], d.hausdorff); acc[2] += d.meanFromA; acc[3] += d.meanFromB;
        };
        unique.forEach((row, k) => {
          const i = levelOf(row);
          const level = clod.level(i);
          add(sums[k].ours, api.surfaceDistance(full, indices, clod.levelSkinnedPositions(i, clip, t), level.indices, samples, SEED));
          add(sums[k].simplify, api.surfaceDistance(full, indices, full, row.simplify, samples, SEED));
          add(sums[k].attributes, api.surfaceDistance(full, indices, full, row.attributes, samples, SEED));
          add(sums[k].welded, api.surfaceDistance(full, indices, full, row.welded, samples, SEED));
        });
        n++;
      }
    }
    const pct = (acc) => ({
      mean: 100 * acc[0] / n / diag, hausdorff: 100 * acc[1] / diag, missed: 100 * acc[2] / n / diag, strayed: 100 * acc[3] / n / diag,
    });
    const levels = unique.map((row, k) => {
      const ours = pct(sums[k].ours), s = pct(sums[k].simplify), a = pct(sums[k].attributes), w = pct(sums[k].welded);
      const t = { simplify: row.simplify.length / 3, attributes: row.attributes.length / 3, welded: row.welded.length / 3 };
      const reached = ['simplify', 'attributes'].filter((v) => t[v] <= row.common);
      const better = reached.length === 2 ? (s.mean <= a.mean ? 'simplify' : 'attributes') : reached[0];
      const best = better === 'simplify' ? s : a;
      return {
        triangles: { ours: clod.level(levelOf(row)).triangleCount, ...t },
        ours, simplify: s, attributes: a, welded: w, better,
        ratio: Math.max(ours.mean, RATIO_FLOOR_PCT) / Math.max(best.mean, RATIO_FLOOR_PCT),
        weldedRatio: t.welded <= row.common ? Math.max(ours.mean, RATIO_FLOOR_PCT) / Math.max(w.mean, RATIO_FLOOR_PCT) : null,
      };
    });
    const weldedRatios = levels.map((l) => l.weldedRatio).filter((r) => r !== null);
    clod.free();
    const meanRatio = levels.reduce((s, l) => s + l.ratio, 0) / levels.length;
    // Levels where both sides are under the floor (lossless for both) count 1.00 in the mean; the
    // mean over the others is shown beside it, not as the target.
    const informative = levels.filter((l) => Math.max(l.ours.mean, l[l.better].mean) > RATIO_FLOOR_PCT);
    const informativeMean = informative.length
      ? { ratio: informative.reduce((s, l) => s + l.ratio, 0) / informative.length, levels: informative.length }
      : null;
    const worst = levels.reduce((w, l) => (l.ratio > w.ratio ? l : w));
    // The third target: our animated Hausdorff distance is never above the better meshoptimizer's.
    // Under the floor both are float32 noise and count as equal.
    const hausdorffHigher = levels
      .filter((l) => Math.max(l.ours.hausdorff, RATIO_FLOOR_PCT) > Math.max(l[l.better].hausdorff, RATIO_FLOOR_PCT))
      .map((l) => ({ triangles: l.triangles.ours, ours: l.ours.hausdorff, better: l[l.better].hausdorff }));
    return {
      name, triangles: character.triangleCount, clips: clipNames, targets: counts, flags, withoutPermissive, attributes: input.what, merged, levels, meanRatio,
      worst: { ratio: worst.ratio, triangles: worst.triangles.ours, ours: worst.ours, better: worst[worst.better] }, hausdorffHigher, informativeMean,
      welded: weldedRatios.length
        ? { meanRatio: weldedRatios.reduce((a, b) => a + b, 0) / weldedRatios.length, worstRatio: Math.max(...weldedRatios), levels: weldedRatios.length }
        : null,
    };
  } finally {
    character.free();
  }
}

/** The models at `paths` (by default every model present, see bench/models.mjs), measured with `settings` (FULL or SHORT). */
export async function measure(settings = FULL, paths = modelPaths([], ASSET_NAMES)) {
  await MeshoptSimplifier.ready;
  return paths.map((path) => measureModel(path, settings));
}

/** The levels whose animated Hausdorff distance is over the better meshoptimizer's, in words. */
export function hausdorffText(model) {
  const f = (x) => x.toFixed(3);
  return model.hausdorffHigher.length
    ? model.hausdorffHigher.map((h) => `${h.triangles} (${f(h.ours)} vs ${f(h.better)} %)`).join(', ')
    : 'none';
}

/** The per-model markdown table, and its summary lines. */
export function format(model) {
  if (model.skipped) return `## ${model.name}: skipped (${model.skipped})`;
  const f = (x) => (x < 0.001 && x > 0 ? x.toExponential(1) : x.toFixed(3));
  const lines = [
    `## ${model.name}: ${model.triangles} triangles, clips ${model.clips.join(', ')}; our levels ${model.targets.join('/')}; ` +
      `withAttributes prices ${model.attributes}` +
      (model.flags.length ? `; meshoptimizer with ${model.flags.join(', ')} (without, it stops at ${model.withoutPermissive} triangles)` : ''),
    '| level | triangles (ours / simplify / withAttributes / welded) | ours mean % | simplify mean % | withAttributes mean % | ours / better | ours Hausdorff % | better Hausdorff % | welded simplify mean % (seams ignored) |',
    '|---|---|---|---|---|---|---|---|---|',
  ];
  model.levels.forEach((l, i) => {
    const t = l.triangles;
    const tris = t.ours === t.simplify && t.ours === t.attributes && t.ours === t.welded
      ? `${t.ours}` : `${t.ours} / ${t.simplify} / ${t.attributes} / ${t.welded}`;
    lines.push(`| ${i + 1} | ${tris} | ${f(l.ours.mean)} | ${f(l.simplify.mean)} | ${f(l.attributes.mean)} | ` +
      `${l.ratio.toFixed(2)} | ${f(l.ours.hausdorff)} | ${f(l[l.better].hausdorff)} | ${f(l.welded.mean)} |`);
  });
  if (model.merged) lines.push(`(${model.merged} of our levels below a count meshoptimizer could not go under: compared once, at that count)`);
  const lossless = model.levels.length - (model.informativeMean?.levels ?? 0);
  lines.push(`mean of ratios over levels: ${model.meanRatio.toFixed(2)} (target <= ${TARGET_MEAN_RATIO})` +
    (lossless && model.informativeMean
      ? `; over the ${model.informativeMean.levels} levels not lossless for both: ${model.informativeMean.ratio.toFixed(2)} (not the target)`
      : ''));
  lines.push(`worst level: ${model.worst.ratio.toFixed(2)} at ${model.worst.triangles} triangles (target <= ${TARGET_WORST_RATIO}); ` +
    `its halves, ours vs the better meshoptimizer: the input's mean distance from the level ${f(model.worst.ours.missed)} vs ` +
    `${f(model.worst.better.missed)} %, the level's from the input ${f(model.worst.ours.strayed)} vs ${f(model.worst.better.strayed)} %`);
  lines.push(`levels with a higher animated Hausdorff distance than the better meshoptimizer (target: none): ${hausdorffText(model)}`);
  if (model.welded) {
    lines.push(`against the position-welded simplify (not a target: it merges across uv and normal seams, so its ` +
      `textures tear): mean ${model.welded.meanRatio.toFixed(2)}, worst ${model.welded.worstRatio.toFixed(2)} over ${model.welded.levels} levels`);
  }
  return lines.join('\n');
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const argv = process.argv.slice(2);
  if (argv.includes('--help')) {
    console.log('node bench/animated-vs-meshoptimizer.mjs [--short] [--json FILE] [--baseline FILE] [MODEL.glb|.gltf|FOLDER...]\n' +
      '  models: those named, or the shared models, any other model in ../shared/models and assets/ ' + ASSET_NAMES.join(', ') + '\n' +
      '  --short: 2 frames of 1 clip, 4,000 samples; --json: every number; --baseline: per model the mean and\n' +
      '  worst-level ratio and the number of levels with a higher Hausdorff distance, as tests/js/animated.test.mjs reads them (bench/animated-baseline.json, from --short)');
    process.exit(0);
  }
  const settings = argv.includes('--short') ? SHORT : FULL;
  const jsonAt = argv.indexOf('--json');
  const baselineAt = argv.indexOf('--baseline');
  for (const [flag, at] of [['--json', jsonAt], ['--baseline', baselineAt]]) {
    if (at >= 0) checkOutputPath(flag, argv[at + 1]);
  }
  const started = performance.now();
  const valued = new Set([jsonAt, baselineAt].filter((i) => i >= 0).map((i) => i + 1));
  const paths = modelPaths(argv.filter((a, i) => !a.startsWith('--') && !valued.has(i)), ASSET_NAMES);
  const results = await measure(settings, paths);
  console.log(`settings: ${settings.frames} frames of ${settings.clips} clip(s), ${settings.samples} samples each way\n`);
  for (const model of results) console.log(`${format(model)}\n`);
  console.log(`| model | ours / better meshopt, mean over levels | worst level | levels with a higher Hausdorff distance |\n|---|---|---|---|`);
  for (const m of results) {
    if (!m.skipped) {
      console.log(`| ${m.name} | ${m.meanRatio.toFixed(2)} | ${m.worst.ratio.toFixed(2)} (${m.worst.triangles} tris) | ${hausdorffText(m)} |`);
    }
  }
  console.log(`\nagainst the position-welded simplify (seams ignored, not a target):\n| model | mean over levels | worst level |\n|---|---|---|`);
  for (const m of results) {
    if (m.welded) console.log(`| ${m.name} | ${m.welded.meanRatio.toFixed(2)} | ${m.welded.worstRatio.toFixed(2)} |`);
  }
  console.log(`\n${((performance.now() - started) / 1000).toFixed(1)} s`);
  if (baselineAt >= 0) {
    const models = Object.fromEntries(results.filter((m) => !m.skipped)
      .map((m) => [m.name, { meanRatio: +m.meanRatio.toFixed(4), worstRatio: +m.worst.ratio.toFixed(4), hausdorffHigher: m.hausdorffHigher.length }]));
    writeFileSync(argv[baselineAt + 1], JSON.stringify({ settings, models }, null, 1) + '\n');
  }
  if (jsonAt >= 0) writeFileSync(argv[jsonAt + 1], JSON.stringify({ settings, models: results }, null, 1) + '\n');
}

// Exits unless `path`, given after `flag`, names a JSON file to write: `--json Fox.glb` would
// overwrite the model it was meant to measure.
function checkOutputPath(flag, path) {
  const isModel = /\.(glb|gltf|bin)$/i.test(path ?? '');
  if (path === undefined || path.startsWith('--') || isModel || (existsSync(path) && statSync(path).isDirectory())) {
    console.error(`${flag} takes the JSON file to write, e.g. ${flag} out.json; got ${path ?? 'nothing'}`);
    process.exit(2);
  }
}
