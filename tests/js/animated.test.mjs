// Issue 14 item 3 as a regression test: the short form of bench/animated-vs-meshoptimizer.mjs (our levels
// vs meshoptimizer's, skinned, at the same triangle counts) must not get worse than the committed baseline.
//
// Re-baseline after a deliberate change (say why in the commit):
//   node bench/animated-vs-meshoptimizer.mjs --short --baseline bench/animated-baseline.json
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import { ASSET_NAMES, measure, SHORT } from '../../bench/animated-vs-meshoptimizer.mjs';
import { modelPaths } from '../../bench/models.mjs';

// The measurement is deterministic (seeded samples; our build, meshoptimizer and the distances are wasm;
// two runs gave byte-identical --json output), so the margin is not for noise: it lets a change move a
// ratio by 0.02, about 2 % of a level's error, without a re-baseline, and fails anything larger.
const MARGIN = 0.02;

test('animated error vs meshoptimizer (short form) stays within the baseline on every model', async () => {
  const baseline = JSON.parse(readFileSync(new URL('../../bench/animated-baseline.json', import.meta.url), 'utf8'));
  assert.deepEqual(baseline.settings, SHORT, 'the baseline was measured with the short form');
  // The baseline's models only: another model in ../shared/models has no baseline to hold.
  const paths = modelPaths([], ASSET_NAMES).filter((path) => basename(path) in baseline.models);
  const results = await measure(SHORT, paths);
  const byName = Object.fromEntries(results.map((m) => [m.name, m]));
  const failures = [];
  for (const [name, limit] of Object.entries(baseline.models)) {
    const m = byName[name];
    if (!m) continue; // a shared model that is absent here (models.mjs printed why; CI=true fails there)
    if (m.skipped) {
      failures.push(`${name}: was compared, now skipped (${m.skipped})`);
      continue;
    }
    if (m.meanRatio > limit.meanRatio + MARGIN) {
      failures.push(`${name}: mean ratio ${m.meanRatio.toFixed(3)} > baseline ${limit.meanRatio} + ${MARGIN}`);
    }
    if (m.worst.ratio > limit.worstRatio + MARGIN) {
      failures.push(`${name}: worst level ${m.worst.ratio.toFixed(3)} at ${m.worst.triangles} triangles > baseline ${limit.worstRatio} + ${MARGIN}`);
    }
    if (m.hausdorffHigher.length > (limit.hausdorffHigher ?? Infinity)) {
      const levels = m.hausdorffHigher.map((h) => h.triangles).join(', ');
      failures.push(`${name}: ${m.hausdorffHigher.length} levels (${levels}) with a higher Hausdorff distance than meshoptimizer's > baseline ${limit.hausdorffHigher}`);
    }
    for (const level of m.levels) {
      assert.ok(Number.isFinite(level.ratio) && level.ratio > 0, `${name}: ratio ${level.ratio} at ${level.triangles.ours}`);
    }
  }
  assert.deepEqual(failures, []);
});
