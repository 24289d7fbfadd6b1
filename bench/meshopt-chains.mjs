// meshoptimizer's LOD chains as the benchmarks time them: each level simplified from the one
// before, to the same triangle counts as ours (FRACTIONS of the input), `target_error` 1 so that
// the count decides. bench/lod-vs-meshoptimizer.mjs and bench/scaling.mjs time them beside ours.

import { MeshoptSimplifier } from 'meshoptimizer';

await MeshoptSimplifier.ready;

/** The levels' triangle counts, as fractions of the input's. */
export const FRACTIONS = [0.5, 0.25, 0.1, 0.05, 0.01];

/**
 * `simplify` levels of the mesh welded by position (`weldByPosition`), to `counts` triangles:
 * each from the one before when `chained`, else each from the input.
 */
export function meshoptLevels(indices, positions, counts, chained) {
  const levels = [];
  let source = indices;
  for (const triangles of counts) {
    // target_error 1 (the whole model's extent) lets the target count decide, as ours does.
    const [out] = MeshoptSimplifier.simplify(chained ? source : indices, positions, 3, triangles * 3, 1.0, []);
    levels.push(out);
    if (chained) source = out;
  }
  return levels;
}

/**
 * meshoptimizer doing the job ours does: the file's vertices (so attribute seams are kept), normals and uv
 * priced (weight 1 each, the docs' advice for unit-range attributes; see `meshoptAttributeInput`), as a chain. `update` uses
 * `simplifyWithUpdate`, which moves vertices and their attributes to better places as our full collapses
 * do, and copies each level's vertex data out (the next level overwrites it); otherwise
 * `simplifyWithAttributes`, which keeps a subset of the input vertices as our half-edge mode does.
 */
export function meshoptAttributeChain({ indices, positions, attributes, stride, weights }, counts, update) {
  const levels = [];
  let source = indices;
  const moved = update ? positions.slice() : positions;
  const movedAttributes = update ? attributes.slice() : attributes;
  for (const triangles of counts) {
    if (update) {
      const working = source.slice();
      const [count] = MeshoptSimplifier.simplifyWithUpdate(working, moved, 3, movedAttributes, stride, weights, null, triangles * 3, 1.0);
      source = working.subarray(0, count);
      levels.push({ indices: source, positions: moved.slice(), attributes: movedAttributes.slice() });
    } else {
      [source] = MeshoptSimplifier.simplifyWithAttributes(source, positions, 3, attributes, stride, weights, null, triangles * 3, 1.0);
      levels.push(source);
    }
  }
  return levels;
}
