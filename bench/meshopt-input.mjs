// What meshoptimizer is given in the benchmarks: the merged mesh welded by position (for
// `simplify`), and the normal and uv attributes (for `simplifyWithAttributes`/`WithUpdate`).

/** Welds vertices by position only: meshoptimizer sees one vertex per position, so it may collapse across seams. */
export function weldByPosition(indices, positions) {
  const first = new Map();
  const remap = new Uint32Array(positions.length / 3);
  for (let v = 0; v < remap.length; v++) {
    const key = `${positions[3 * v]},${positions[3 * v + 1]},${positions[3 * v + 2]}`;
    if (!first.has(key)) first.set(key, v);
    remap[v] = first.get(key);
  }
  return indices.map((i) => remap[i]);
}

/** Normals and uv interleaved, five floats per vertex (uv 0 when the model has none). */
export function normalsAndUvs(character) {
  const normals = character.normals();
  const uvs = character.uvs();
  const out = new Float32Array(5 * character.vertexCount);
  for (let v = 0; v < character.vertexCount; v++) {
    out.set(normals.subarray(3 * v, 3 * v + 3), 5 * v);
    if (uvs) out.set(uvs.subarray(2 * v, 2 * v + 2), 5 * v + 3);
  }
  return out;
}
