// Which models the benchmarks measure (bench/models.mjs): a user's own files and folders, .glb or
// .gltf with its buffer beside it, and the default list when none is named.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, mkdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { measure, SHORT } from '../../bench/animated-vs-meshoptimizer.mjs';
import { glbJson, loadModel, modelPaths } from '../../bench/models.mjs';
import { modelBytes } from './models.mjs';

/** `glb` split into a .gltf whose buffer is `data/<bin>` beside it, in a new folder: the folder. */
function asGltfFolder(glb, bin) {
  const folder = mkdtempSync(join(tmpdir(), 'bench-models-'));
  const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
  const jsonLength = view.getUint32(12, true);
  const binAt = 20 + jsonLength;
  const binLength = view.getUint32(binAt, true);
  const json = glbJson(glb);
  json.buffers[0].uri = `data/${encodeURIComponent(bin)}`;
  mkdirSync(join(folder, 'data'));
  writeFileSync(join(folder, 'data', bin), glb.subarray(binAt + 8, binAt + 8 + binLength));
  writeFileSync(join(folder, 'man.gltf'), JSON.stringify(json));
  writeFileSync(join(folder, 'man.glb'), glb);
  writeFileSync(join(folder, 'notes.txt'), 'not a model');
  return folder;
}

test('named files and folders replace the default list; a .gltf reads its buffer from its folder', (t) => {
  const glb = modelBytes('CesiumMan.glb');
  if (!glb) return t.skip('model missing');
  const folder = asGltfFolder(glb, 'Cesium Man.bin');
  try {
    const paths = modelPaths([folder], ['character.glb']);
    assert.deepEqual(paths.map((p) => basename(p)), ['man.glb', 'man.gltf'], 'the folder\'s models, sorted; no asset added');
    const [fromGlb, fromGltf] = paths.map(loadModel);
    try {
      assert.equal(fromGltf.character.triangleCount, fromGlb.character.triangleCount);
      assert.deepEqual([...fromGltf.character.bindPositions()], [...fromGlb.character.bindPositions()]);
      assert.deepEqual(fromGltf.json.meshes, fromGlb.json.meshes);
    } finally {
      fromGlb.character.free();
      fromGltf.character.free();
    }
    assert.throws(() => modelPaths([join(folder, 'notes.txt')], []), /notes\.txt: not a \.glb or \.gltf/);
    assert.throws(() => modelPaths([join(folder, 'absent.glb')], []), /absent\.glb: not a \.glb or \.gltf/);
    rmSync(join(folder, 'data'), { recursive: true });
    assert.throws(() => loadModel(join(folder, 'man.gltf')), /man\.gltf: .*Cesium Man\.bin/);
  } finally {
    rmSync(folder, { recursive: true });
  }
});

test('by default: the three shared models first, then the named assets', (t) => {
  if (!modelBytes('CesiumMan.glb')) return t.skip('models missing');
  const names = modelPaths([], ['character.glb']).map((p) => basename(p));
  assert.deepEqual(names.slice(0, 3), ['CesiumMan.glb', 'Fox.glb', 'RiggedSimple.glb']);
  assert.equal(names.at(-1), 'character.glb');
});

test('a file that does not import is skipped with the importer\'s message, and the others still run', async () => {
  const folder = mkdtempSync(join(tmpdir(), 'bench-models-'));
  try {
    writeFileSync(join(folder, 'broken.glb'), 'not a glb');
    assert.throws(() => loadModel(join(folder, 'broken.glb')), /broken\.glb: broken GLB file/);
    const [broken] = await measure(SHORT, [join(folder, 'broken.glb')]);
    assert.equal(broken.name, 'broken.glb');
    assert.match(broken.skipped, /broken GLB file/);
  } finally {
    rmSync(folder, { recursive: true });
  }
});
