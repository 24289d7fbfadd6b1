// What meshoptimizer is given in the benchmarks: the merged mesh welded by position (for
// `simplify`), and the file's vertices with their normal and uv attributes (for
// `simplifyWithAttributes`/`WithUpdate`).

/**
 * The vertices `indices` uses, each once and in increasing order, and `indices` renumbered into that
 * list: `{ indices, vertices }`, with `pick(array, stride)` copying those vertices' rows of an array.
 *
 * meshoptimizer must get a vertex buffer without unused vertices: its simplifier finds seams among
 * vertices of one position over the whole buffer, and an unused copy of a vertex's position makes
 * that vertex a seam it cannot pair, so it locks it (Fox welded by position simplifies not one
 * triangle with its unused copies left in, and to every count without them). An exporter's file, and
 * gltf-transform's `weld`, have none.
 */
export function compact(indices) {
  const place = new Int32Array(indices.reduce((m, i) => Math.max(m, i + 1), 0)).fill(-1);
  for (const i of indices) place[i] = 0;
  const vertices = [];
  place.forEach((p, v) => { if (p === 0) { place[v] = vertices.length; vertices.push(v); } });
  return {
    indices: indices.map((i) => place[i]),
    vertices: Uint32Array.from(vertices),
    pick(array, stride) {
      const out = new Float32Array(vertices.length * stride);
      vertices.forEach((v, k) => out.set(array.subarray(stride * v, stride * v + stride), stride * k));
      return out;
    },
  };
}

/** Maps indices into a [`compact`] buffer back to the input's vertex ids. */
export function uncompact(indices, vertices) {
  return indices.map((i) => vertices[i]);
}

/**
 * The mesh welded by position only (meshoptimizer sees one vertex per position, so it may collapse
 * across seams), compacted: `{ indices, positions, vertices }`, `vertices[k]` being the input vertex
 * whose position is the buffer's `k`-th.
 */
export function weldByPosition(indices, positions) {
  const first = new Map();
  const remap = new Uint32Array(positions.length / 3);
  for (let v = 0; v < remap.length; v++) {
    const key = `${positions[3 * v]},${positions[3 * v + 1]},${positions[3 * v + 2]}`;
    if (!first.has(key)) first.set(key, v);
    remap[v] = first.get(key);
  }
  const c = compact(indices.map((i) => remap[i]));
  return { indices: c.indices, positions: c.pick(positions, 3), vertices: c.vertices };
}

/**
 * Whether every mesh primitive of a glTF file (its JSON, as `loadModel` in models.mjs gives it) has
 * its own `NORMAL` attribute. Without it glTF (§3.7.2.1) has viewers draw flat normals, which our
 * importer generates (a face normal per triangle corner); a meshoptimizer user (gltf-transform) sees
 * the file's vertices, which have none.
 */
export function fileHasNormals(json) {
  return (json.meshes ?? []).every((m) => m.primitives.every((p) => p.attributes.NORMAL !== undefined));
}

/**
 * What meshoptimizer's attribute-aware simplifiers are given for the job ours does: the file's
 * vertices with their seams, and their normals and uv (weight 1 each, the meshoptimizer docs' advice
 * for unit-range attributes; uv 0 when the model has none), compacted (see [`compact`]): `{ indices,
 * positions, attributes, vertices, stride, weights, what }`.
 *
 * Vertices of one material that are equal in all of that are one vertex, as gltf-transform's `weld`
 * makes them. That matters where the importer left out uvs no texture samples (gltf-transform's
 * `prune` drops those too): the built-in character's seam down its back is then two copies of equal
 * vertices, and ours welds them too.
 *
 * For a file without normals (Fox.glb) that is its vertices as stored, with uv only: the importer's
 * flat normals split every vertex into facet corners, which are not in the file and would make
 * every edge a normal seam only meshoptimizer's `Permissive` gets across, and `Permissive` crosses
 * the uv seams too. Welding the corners again by position and uv gives back the file's vertices.
 */
export function meshoptAttributeInput(character, json) {
  const indices = character.indices();
  const positions = character.bindPositions();
  const uvs = character.uvs();
  const normals = fileHasNormals(json) ? character.normals() : null;
  // A vertex's material: that of the triangles using it (a primitive's vertices are its own).
  const triangleMaterials = character.triangleMaterials();
  const material = new Uint32Array(character.vertexCount);
  indices.forEach((v, k) => { material[v] = triangleMaterials[Math.floor(k / 3)]; });
  const row = (array, stride, v) => (array ? array.subarray(stride * v, stride * v + stride) : '');
  const first = new Map();
  const remap = new Uint32Array(character.vertexCount);
  for (let v = 0; v < remap.length; v++) {
    const key = `${material[v]}|${row(positions, 3, v)}|${row(normals, 3, v)}|${row(uvs, 2, v)}`;
    if (!first.has(key)) first.set(key, v);
    remap[v] = first.get(key);
  }
  const welded = indices.map((i) => remap[i]);
  if (!normals) {
    // Without uv either, one attribute of zeros (it costs nothing): positions alone decide.
    return uvs
      ? compacted(welded, positions, uvs, 2, 'uv (the file has no normals)')
      : compacted(welded, positions, new Float32Array(remap.length), 1, 'nothing (the file has no normals or uv)');
  }
  const out = new Float32Array(5 * character.vertexCount);
  for (let v = 0; v < character.vertexCount; v++) {
    out.set(normals.subarray(3 * v, 3 * v + 3), 5 * v);
    if (uvs) out.set(uvs.subarray(2 * v, 2 * v + 2), 5 * v + 3);
  }
  return compacted(welded, positions, out, 5, uvs ? 'normals and uv' : 'normals (no texture samples uv)');
}

function compacted(indices, positions, attributes, stride, what) {
  const c = compact(indices);
  return {
    indices: c.indices, positions: c.pick(positions, 3), attributes: c.pick(attributes, stride), vertices: c.vertices,
    stride, weights: new Array(stride).fill(1), what,
  };
}
