// Benchmark (issue 14 item 3, judged as issue 47 asks): our LOD levels against meshoptimizer 1.3 under
// animation, at the same triangle counts.
//
//   source scripts/tools.sh; build_wasm node && npm ci
//   node bench/animated-vs-meshoptimizer.mjs [--short] [--json FILE] [--baseline FILE] [MODEL.glb|.gltf|FOLDER...]
//
// For every model it has (the shared models CesiumMan, Fox, RiggedSimple, any other model in
// ../shared/models, the project's assets/character.glb, robot.glb, parts.glb, critter.glb, and the generated
// hardsurface.glb, lowpoly-robot.glb and fingers.glb, made into target/generated/ on the spot; or the files named on the
// command line, see bench/models.mjs), the counts are our default build's levels from level 1 on (`buildClod()`:
// multi-pose simplification). At each count meshoptimizer simplifies the bind-pose mesh, from the full mesh, in
// eight variants: `simplify` and `simplifyWithAttributes` (normals and uv priced with weight 1 each, see
// `meshoptAttributeInput`), each with and without `Regularize` (its advice for skinned, deforming meshes since
// v0.25), on the file's vertices with their seams (what a gltf-transform user gets), and each of those four with
// `Permissive` at a count it cannot reach within 2 % without it (a flat-shaded file: every edge a normal seam). A
// variant competes at a count when it reaches it within 2 %. Where none does, the comparison moves to the count
// the variant that went furthest reached (ours rebuilt with those counts as its levels). `simplify` on the mesh
// welded by position, which merges across uv and normal seams (its textures tear), is shown beside in the full
// form, outside the judgement. meshoptimizer keeps a subset of the input vertices, so its indices skinned with the full mesh's
// `skinnedPositions(clip, t)` are its animated levels; ours are `levelSkinnedPositions(i, clip, t)`.
//
// Error: symmetric sampled surface distance (seeded, same samples for all) against the full mesh skinned at the
// same frame, in % of the bind-pose bounding-box diagonal; mean averaged over frames, Hausdorff the worst frame.
// Frames: 4 of each of the first 2 clips ((f + 0.5) / 4 of the duration); --short: 2 frames of the first clip,
// 4,000 samples (the regression test, tests/js/animated.test.mjs, runs that form).
//
// Judgement (`judge`), so that neither side wins by cutting parts away: a level is lost where a competing
// variant has a lower mean with a Hausdorff distance at most 1.1 x ours, or a Hausdorff distance more than 1.1 x
// lower with a mean no higher. Its ratio is ours / the lowest mean among the variants whose Hausdorff distance is
// within 1.1 x ours; where every variant's is above that (each cuts more away), meshoptimizer draws at best there:
// the ratio is ours / the lowest mean of all, at most 1 (a lower mean bought by cutting parts away does not count
// against ours; a higher one, even so, loses to ours). Issue 47's own example reads it so: Fox at 72 triangles "1.00
// (the one variant with a lower mean cuts 2.4x deeper)". Won: not lost and a ratio under 1. Beside it, not
// judged: the plain ratio, ours / the lowest mean of any competing variant (`plain`; the regression baseline holds
// it too, since a ratio capped at 1 hides a change). The full form also measures how far meshoptimizer goes past our coarsest level
// within its animated Hausdorff distance (`reach`).
import { existsSync, statSync, writeFileSync } from 'node:fs';
import { basename } from 'node:path';
import { pathToFileURL } from 'node:url';
import { MeshoptSimplifier } from 'meshoptimizer';
import { api } from '../tests/js/models.mjs';
import { GENERATED_NAMES } from './generated.mjs';
import { meshoptAttributeInput, uncompact, weldByPosition } from './meshopt-input.mjs';
import { loadModel, modelPaths } from './models.mjs';

const SEED = 12345;
// Issue 47's targets: ours at most 0.8x the best competing variant averaged over levels, and no level lost.
export const TARGET_MEAN_RATIO = 0.8;
// Errors under 0.001 % of the diagonal count as 0.001 % in the ratios and the judgement: that is 0.01 pixel
// on a character 1,000 pixels tall, invisible, and where float32 skinning noise lives, so a ratio of two such
// errors (parts.glb's first levels: lossless removal of flat-plate vertices by both) would be noise.
export const RATIO_FLOOR_PCT = 0.001;
// A variant's Hausdorff distance within this factor of ours is "the same distance" (issue 47).
export const HAUSDORFF_FACTOR = 1.1;
// A variant reaches a count when it keeps at most this factor of it.
export const REACH_FACTOR = 1.02;
// `reach`: the full form's extras, not judged: how far meshoptimizer goes past our coarsest level
// (`reachPast`), and the position-welded `simplify` beside every level.
export const FULL = { samples: 10000, frames: 4, clips: 2, reach: true };
export const SHORT = { samples: 4000, frames: 2, clips: 1 };

/** The project's committed test characters this benchmark measures by default, after the shared models. */
export const ASSET_NAMES = ['character.glb', 'robot.glb', 'parts.glb', 'critter.glb'];

/** The four variants; each also runs with `Permissive` where it cannot reach a count without it. */
export const VARIANTS = [
  { name: 'simplify', attributes: false, flags: [] },
  { name: 'simplify+Regularize', attributes: false, flags: ['Regularize'] },
  { name: 'withAttributes', attributes: true, flags: [] },
  { name: 'withAttributes+Regularize', attributes: true, flags: ['Regularize'] },
];

/**
 * The judgement of one level: `ours` and each competing variant are `{ mean, hausdorff }` (% of the
 * diagonal), both floored at RATIO_FLOOR_PCT. Returns `{ verdict, ratio, best, lostTo, drawAtBest, plain }`: `best` the index of the lowest mean among the variants within HAUSDORFF_FACTOR x our Hausdorff
 * distance (or, when there is none, among all: `drawAtBest`), `lostTo` the indices of the variants that beat
 * ours (where `drawAtBest`, the ratio is at most 1: meshoptimizer draws there at best), `plain` ours / the
 * lowest mean of all.
 */
export function judge(ours, variants) {
  const floor = (x) => Math.max(x, RATIO_FLOOR_PCT);
  const o = { mean: floor(ours.mean), hausdorff: floor(ours.hausdorff) };
  const v = variants.map((x) => ({ mean: floor(x.mean), hausdorff: floor(x.hausdorff) }));
  const lostTo = v.flatMap((x, i) => ((x.mean < o.mean && x.hausdorff <= HAUSDORFF_FACTOR * o.hausdorff) ||
    (x.hausdorff * HAUSDORFF_FACTOR < o.hausdorff && x.mean <= o.mean) ? [i] : []));
  const within = v.flatMap((x, i) => (x.hausdorff <= HAUSDORFF_FACTOR * o.hausdorff ? [i] : []));
  const drawAtBest = within.length === 0;
  const pool = drawAtBest ? v.map((_, i) => i) : within;
  const best = pool.reduce((b, i) => (v[i].mean < v[b].mean ? i : b), pool[0]);
  const plain = o.mean / Math.min(...v.map((x) => x.mean));
  const ratio = drawAtBest ? Math.min(1, plain) : o.mean / v[best].mean;
  const verdict = lostTo.length ? 'lost' : ratio < 1 ? 'won' : 'drawn';
  return { verdict, ratio, best, lostTo, drawAtBest, plain };
}

/** One model file: per level every variant's errors and the judgement, or `{ skipped }`. */
function measureModel(path, settings) {
  const { samples, frames, clips } = settings;
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
    // Each returns indices of the full mesh's vertices, so the full mesh's skinning poses them.
    const run = (variant, n, permissive) => {
      const flags = permissive ? [...variant.flags, 'Permissive'] : variant.flags;
      const [out] = variant.attributes
        ? MeshoptSimplifier.simplifyWithAttributes(input.indices, input.positions, 3, input.attributes, input.stride,
          input.weights, null, n * 3, 1.0, flags)
        : MeshoptSimplifier.simplify(input.indices, input.positions, 3, n * 3, 1.0, flags);
      return uncompact(out, input.vertices);
    };
    const simplifyWelded = (n) => uncompact(
      MeshoptSimplifier.simplify(welded.indices, welded.positions, 3, n * 3, 1.0, [])[0], welded.vertices);
    const reaches = (out, n) => out.length / 3 <= REACH_FACTOR * n;
    // The variants at count n: each of the four, with Permissive where it does not reach n without it; one
    // that reaches neither way is kept (its furthest count shown) but does not compete.
    const variantsAt = (n) => VARIANTS.map((variant) => {
      const plain = run(variant, n, false);
      if (reaches(plain, n)) return { name: variant.name, indices: plain, competes: true };
      const permissive = run(variant, n, true);
      if (reaches(permissive, n)) return { name: `${variant.name}+Permissive`, indices: permissive, competes: true };
      const further = permissive.length < plain.length ? permissive : plain;
      return { name: variant.name, indices: further, competes: false };
    });

    const defaults = character.buildClod();
    const counts = Array.from({ length: defaults.levelCount - 1 }, (_, i) => defaults.level(i + 1).triangleCount);
    const rows = counts.map((n) => {
      let variants = variantsAt(n);
      let common = n;
      if (!variants.some((v) => v.competes)) {
        common = Math.min(...variants.map((v) => v.indices.length / 3));
        variants = variantsAt(common);
      }
      return { target: n, common, variants };
    }).filter((r) => r.common < character.triangleCount && r.variants.some((v) => v.competes));
    if (rows.length === 0) {
      defaults.free();
      return { name, skipped: `meshoptimizer keeps all ${character.triangleCount} triangles at every count, even with Permissive: nothing to compare` };
    }
    // A level under a count meshoptimizer could not go under is compared once, at that count.
    const kept = rows.filter((r, k) => rows.slice(0, k).every((q) => r.common < q.common));
    const merged = rows.length - kept.length;
    let clod = defaults;
    let levelOf = (row) => counts.indexOf(row.target) + 1;
    if (kept.some((r) => r.common !== r.target)) {
      clod = character.buildClod({ levels: kept.map((r) => r.common) });
      // Its level 0 is the full mesh; each common count gets the first level at or under it.
      const got = Array.from({ length: clod.levelCount }, (_, i) => clod.level(i).triangleCount);
      levelOf = (row) => got.findIndex((t) => t <= row.common);
      defaults.free();
    }
    // Shown beside in the full form only: it is not judged.
    if (settings.reach) for (const row of kept) row.welded = simplifyWelded(row.common);

    const poses = [];
    for (const clip of clipNames) {
      for (let f = 0; f < frames; f++) poses.push({ clip, t: character.clipDuration(clip) * (f + 0.5) / frames });
    }
    // The mean over the frames of the sampled mean and its two halves (the input's samples from the level: what
    // the level misses; the level's from the input: where it strays), and the worst frame's Hausdorff distance.
    const animated = (levelPositions, levelIndices) => {
      const acc = [0, 0, 0, 0];
      for (const { clip, t } of poses) {
        const full = character.skinnedPositions(clip, t);
        const d = api.surfaceDistance(full, indices, levelPositions(clip, t) ?? full, levelIndices, samples, SEED);
        acc[0] += d.mean; acc[1] = Math.max(acc[1], d.hausdorff); acc[2] += d.meanFromA; acc[3] += d.meanFromB;
      }
      const pct = (x) => 100 * x / diag;
      return { mean: pct(acc[0] / poses.length), hausdorff: pct(acc[1]), missed: pct(acc[2] / poses.length), strayed: pct(acc[3] / poses.length) };
    };
    const levels = kept.map((row) => {
      const i = levelOf(row);
      const ours = animated((clip, t) => clod.levelSkinnedPositions(i, clip, t), clod.level(i).indices);
      const variants = row.variants.map((v) => ({
        name: v.name, triangles: v.indices.length / 3, competes: v.competes,
        ...(v.competes ? animated(() => null, v.indices) : {}),
      }));
      const competing = variants.filter((v) => v.competes);
      const j = judge(ours, competing);
      return {
        triangles: clod.level(i).triangleCount, target: row.target, common: row.common, ours, variants,
        welded: row.welded ? { triangles: row.welded.length / 3, ...animated(() => null, row.welded) } : null,
        verdict: j.verdict, ratio: j.ratio, plain: j.plain, best: competing[j.best], drawAtBest: j.drawAtBest,
        lostTo: j.lostTo.map((k) => competing[k].name),
      };
    });
    const reach = settings.reach ? reachPast(levels.at(-1), variantsAt, animated, character.triangleCount) : null;
    clod.free();
    const mean = (key) => levels.reduce((s, l) => s + l[key], 0) / levels.length;
    const meanRatio = mean('ratio');
    // The highest judged ratio; among equal ones (draws at 1), the highest plain ratio.
    const worst = levels.reduce((w, l) => (l.ratio > w.ratio || (l.ratio === w.ratio && l.plain > w.plain) ? l : w));
    return {
      name, triangles: character.triangleCount, clips: clipNames, targets: counts, attributes: input.what, merged,
      levels: [character.triangleCount, ...counts], levelResults: levels, meanRatio, plainMeanRatio: mean('plain'),
      worst: { ratio: worst.ratio, triangles: worst.triangles, ours: worst.ours, best: worst.best },
      lost: levels.filter((l) => l.verdict === 'lost').length,
      won: levels.filter((l) => l.verdict === 'won').length,
      drawn: levels.filter((l) => l.verdict === 'drawn').length,
      reach,
    };
  } finally {
    character.free();
  }
}

/**
 * How far meshoptimizer goes past our coarsest level within its animated Hausdorff distance: at half, a
 * quarter, ... of its triangle count (down to 12 triangles, at most 5 counts), the competing variants'
 * errors there; `furthest` is the lowest count at which one of them stays within our coarsest level's
 * Hausdorff distance (null: none does, at any count measured).
 */
function reachPast(coarsest, variantsAt, animated, full) {
  const steps = [];
  for (let n = Math.floor(coarsest.common / 2); n >= 12 && steps.length < 5; n = Math.floor(n / 2)) {
    const variants = variantsAt(n).filter((v) => v.competes).map((v) => ({ name: v.name, triangles: v.indices.length / 3, ...animated(() => null, v.indices) }));
    if (variants.length === 0) break;
    const within = variants.filter((v) => v.hausdorff <= coarsest.ours.hausdorff);
    const best = (within.length ? within : variants).reduce((b, v) => (v.mean < b.mean ? v : b));
    steps.push({ target: n, best, within: within.length > 0 });
  }
  const furthest = steps.filter((s) => s.within).at(-1) ?? null;
  return {
    ours: { triangles: coarsest.triangles, fraction: coarsest.triangles / full, mean: coarsest.ours.mean, hausdorff: coarsest.ours.hausdorff },
    steps,
    furthest: furthest && { triangles: furthest.best.triangles, fraction: furthest.best.triangles / full, variant: furthest.best.name, mean: furthest.best.mean, hausdorff: furthest.best.hausdorff },
  };
}

/** The models at `paths` (by default every model present, see bench/models.mjs), measured with `settings` (FULL or SHORT). */
export async function measure(settings = FULL, paths = modelPaths([], ASSET_NAMES, GENERATED_NAMES)) {
  await MeshoptSimplifier.ready;
  return paths.map((path) => measureModel(path, settings));
}

const f3 = (x) => (x < 0.001 && x > 0 ? x.toExponential(1) : x.toFixed(3));
const pct = (x) => `${(100 * x).toFixed(1)} %`;

/** The per-model markdown tables, and their summary lines. */
export function format(model) {
  if (model.skipped) return `## ${model.name}: skipped (${model.skipped})`;
  const lines = [
    `## ${model.name}: ${model.triangles} triangles, clips ${model.clips.join(', ')}; our levels ${model.levels.join('/')} ` +
      `(${model.levels.length} levels, the coarsest ${pct(model.levels.at(-1) / model.triangles)}); withAttributes prices ${model.attributes}`,
    '',
    '| level | triangles | ours mean % | ours Hausdorff % | best competing variant | its triangles | its mean % | its Hausdorff % | ours / best | judgement |',
    '|---|---|---|---|---|---|---|---|---|---|',
  ];
  model.levelResults.forEach((l, i) => {
    const judgement = l.verdict + (l.lostTo.length ? ` (to ${l.lostTo.join(', ')})` : '') + (l.drawAtBest ? ' (every variant cuts more away)' : '');
    lines.push(`| ${i + 1} | ${l.triangles}${l.common !== l.target ? ` (asked ${l.target})` : ''} | ${f3(l.ours.mean)} | ${f3(l.ours.hausdorff)} | ` +
      `${l.best.name} | ${l.best.triangles} | ${f3(l.best.mean)} | ${f3(l.best.hausdorff)} | ${l.ratio.toFixed(2)} | ${judgement} |`);
  });
  lines.push('', 'every variant, mean / Hausdorff % (P: with Permissive; stops: cannot reach the count within 2 %, not competing):', '',
    `| level | ${VARIANTS.map((v) => v.name).join(' | ')} | welded simplify (not judged) |`, `|---|${VARIANTS.map(() => '---|').join('')}---|`);
  model.levelResults.forEach((l, i) => {
    const cells = l.variants.map((v) => (v.competes
      ? `${v.name.endsWith('+Permissive') ? 'P ' : ''}${f3(v.mean)} / ${f3(v.hausdorff)}${v.triangles !== l.triangles ? ` (${v.triangles})` : ''}`
      : `stops at ${v.triangles}`));
    lines.push(`| ${i + 1} | ${cells.join(' | ')} | ${l.welded ? `${f3(l.welded.mean)} / ${f3(l.welded.hausdorff)}` : 'not measured (--short)'} |`);
  });
  lines.push('');
  if (model.merged) lines.push(`(${model.merged} of our levels below a count meshoptimizer could not go under: compared once, at that count)`);
  const w = model.worst;
  lines.push(`mean of ratios over levels: ${model.meanRatio.toFixed(2)} (target <= ${TARGET_MEAN_RATIO}); worst level ${w.ratio.toFixed(2)} ` +
    `at ${w.triangles} triangles (${f3(w.ours.mean)} vs ${w.best.name} ${f3(w.best.mean)} %; the input's mean distance from the level ` +
    `${f3(w.ours.missed)} vs ${f3(w.best.missed)} %, the level's from the input ${f3(w.ours.strayed)} vs ${f3(w.best.strayed)} %)`);
  lines.push(`levels won ${model.won}, drawn ${model.drawn}, lost ${model.lost} (target: none lost)`);
  lines.push(`not judged: ours / the lowest mean of any competing variant, Hausdorff distance aside: ${model.plainMeanRatio.toFixed(2)}`);
  if (model.reach) lines.push(reachText(model.reach));
  return lines.join('\n');
}

/** Our coarsest level against how far meshoptimizer goes within its animated Hausdorff distance, in words. */
export function reachText(reach) {
  const o = reach.ours;
  const steps = reach.steps.map((s) => `${s.best.triangles}: ${s.best.name} ${f3(s.best.mean)} / ${f3(s.best.hausdorff)} %${s.within ? '' : ' (over)'}`);
  return `past our coarsest level (${o.triangles} triangles, ${pct(o.fraction)}, ${f3(o.mean)} / ${f3(o.hausdorff)} %): ` +
    (reach.furthest
      ? `meshoptimizer stays within its Hausdorff distance down to ${reach.furthest.triangles} triangles (${pct(reach.furthest.fraction)}, ${reach.furthest.variant})`
      : 'meshoptimizer does not stay within its Hausdorff distance at any count measured') +
    (steps.length ? `; best variant per count, mean / Hausdorff: ${steps.join('; ')}` : '');
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const argv = process.argv.slice(2);
  if (argv.includes('--help')) {
    console.log('node bench/animated-vs-meshoptimizer.mjs [--short] [--json FILE] [--baseline FILE] [MODEL.glb|.gltf|FOLDER...]\n' +
      '  models: those named, or the shared models, any other model in ../shared/models, assets/ ' + ASSET_NAMES.join(', ') +
      ' and the generated ' + GENERATED_NAMES.join(', ') + ' (made into target/generated/)\n' +
      '  --short: 2 frames of 1 clip, 4,000 samples; --json: every number; --baseline: per model the mean and\n' +
      '  worst-level ratio, the number of levels lost and the plain mean ratio, as tests/js/animated.test.mjs reads them\n' +
      '  (bench/animated-baseline.json, from --short)');
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
  const paths = modelPaths(argv.filter((a, i) => !a.startsWith('--') && !valued.has(i)), ASSET_NAMES, GENERATED_NAMES);
  const results = await measure(settings, paths);
  console.log(`settings: ${settings.frames} frames of ${settings.clips} clip(s), ${settings.samples} samples each way\n`);
  for (const model of results) console.log(`${format(model)}\n`);
  console.log('| model | levels (coarsest) | mean of level ratios (judged) | worst level | won / drawn / lost | ' +
    'plain (not judged) |\n|---|---|---|---|---|---|');
  for (const m of results) {
    if (!m.skipped) {
      console.log(`| ${m.name} | ${m.levels.length} (${pct(m.levels.at(-1) / m.triangles)}) | ${m.meanRatio.toFixed(2)} | ` +
        `${m.worst.ratio.toFixed(2)} (${m.worst.triangles} tris) | ${m.won} / ${m.drawn} / ${m.lost} | ` +
        `${m.plainMeanRatio.toFixed(2)} |`);
    }
  }
  console.log(`\n${((performance.now() - started) / 1000).toFixed(1)} s`);
  if (baselineAt >= 0) {
    const models = Object.fromEntries(results.filter((m) => !m.skipped)
      .map((m) => [m.name, {
        meanRatio: +m.meanRatio.toFixed(4), worstRatio: +m.worst.ratio.toFixed(4), lost: m.lost, plainMeanRatio: +m.plainMeanRatio.toFixed(4),
      }]));
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
