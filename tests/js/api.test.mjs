// The JavaScript API of issue 2, called from node exactly as a page would call it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { api, modelBytes } from './models.mjs';

const models = [
  { file: 'CesiumMan.glb', triangles: 4672, joints: 19, clips: ['Anim_0'], textured: true },
  { file: 'Fox.glb', triangles: 576, joints: 24, clips: ['Survey', 'Walk', 'Run'], textured: true },
  // RiggedSimple has TEXCOORD_0 but no material: no texture samples it, so it is not imported.
  { file: 'RiggedSimple.glb', triangles: 892, joints: 4, clips: null, textured: false },
];

/** Distinct joint nodes over every skin of a GLB, read straight from its JSON chunk. */
function skinJointsInFile(bytes) {
  const jsonLength = new DataView(bytes.buffer, bytes.byteOffset).getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  return new Set((json.skins ?? []).flatMap((s) => s.joints)).size;
}

for (const model of models) {
  test(`${model.file}: counts, clips and skinning through the JS API`, (t) => {
    const bytes = modelBytes(model.file);
    if (!bytes) return t.skip('model missing');
    const character = api.Character.fromGlb(bytes);
    assert.equal(character.triangleCount, model.triangles);
    assert.equal(character.jointCount, model.joints);
    assert.equal(character.jointCount, skinJointsInFile(bytes));
    assert.ok(character.primitiveCount >= 1);
    assert.equal(character.morphTargetCount, 0);
    if (model.clips) assert.deepEqual(character.clipNames, model.clips);
    assert.ok(character.clipNames.length >= 1);

    const indices = character.indices();
    assert.ok(indices instanceof Uint32Array);
    assert.equal(indices.length, 3 * character.triangleCount);
    assert.ok(indices.every((i) => i < character.vertexCount));

    const materials = character.triangleMaterials();
    assert.ok(materials instanceof Uint32Array);
    assert.equal(materials.length, character.triangleCount);
    // CesiumMan and Fox have one material; RiggedSimple none (glTF's default material).
    assert.ok(materials.every((m) => m === (model.textured ? 0 : 0xFFFFFFFF)));

    const bind = character.bindPositions();
    assert.ok(bind instanceof Float32Array);
    assert.equal(bind.length, 3 * character.vertexCount);

    const normals = character.normals();
    assert.ok(normals instanceof Float32Array);
    assert.equal(normals.length, bind.length);
    for (let v = 0; v < character.vertexCount; v++) {
      const length = Math.hypot(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
      assert.ok(Math.abs(length - 1) < 1e-3, `normal ${v} has length ${length}`);
    }
    const uvs = character.uvs();
    if (model.textured) {
      assert.ok(uvs instanceof Float32Array);
      assert.equal(uvs.length, 2 * character.vertexCount);
      assert.ok(uvs.every(Number.isFinite));
      assert.ok(uvs.some((x) => x !== 0), 'the texture coordinates are not all zero');
    } else {
      assert.equal(uvs, undefined);
    }

    for (const clip of character.clipNames) {
      const duration = character.clipDuration(clip);
      assert.ok(duration > 0, `${clip} has a duration`);
      const posed = character.skinnedPositions(clip, duration / 2);
      assert.equal(posed.length, bind.length);
      assert.ok(posed.every(Number.isFinite));
      const moved = posed.some((v, i) => Math.abs(v - bind[i]) > 1e-4);
      assert.ok(moved, `${clip} moves the mesh at mid-clip`);
    }
    character.free();
  });
}

test('bad bytes throw an Error that names the problem', () => {
  assert.throws(() => api.Character.fromGlb(new Uint8Array([1, 2, 3, 4, 5])), (e) => e instanceof Error && e.message.length > 10);
  const bytes = modelBytes('RiggedSimple.glb');
  if (!bytes) return;
  assert.throws(() => api.Character.fromGlb(bytes.subarray(0, bytes.length / 2)), Error);
});

test('unknown clips and bad times throw, listing what exists', (t) => {
  const bytes = modelBytes('Fox.glb');
  if (!bytes) return t.skip('model missing');
  const fox = api.Character.fromGlb(bytes);
  assert.throws(() => fox.clipDuration('Dance'), /Survey/);
  assert.throws(() => fox.skinnedPositions('Walk', Number.NaN), /finite/);
  fox.free();
});

test('a .gltf with an external buffer loads through the resolver', (t) => {
  const bytes = modelBytes('RiggedSimple.glb');
  if (!bytes) return t.skip('model missing');
  // Split the GLB into its JSON and BIN chunks, and point the buffer at an external URI.
  const view = new DataView(bytes.buffer, bytes.byteOffset);
  const jsonLength = view.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  const binStart = 20 + jsonLength + 8;
  const bin = bytes.subarray(binStart, binStart + view.getUint32(20 + jsonLength, true));
  json.buffers[0].uri = 'external%20data.bin';
  const text = new TextEncoder().encode(JSON.stringify(json));
  const asked = [];
  const character = api.Character.fromGltf(text, (uri) => (asked.push(uri), uri === 'external data.bin' ? bin : null));
  assert.deepEqual(asked, ['external data.bin']);
  assert.equal(character.triangleCount, api.Character.fromGlb(bytes).triangleCount);
  assert.throws(() => api.Character.fromGltf(text, () => null), /external data\.bin/);
  // fromBytes tells the two forms apart by the GLB magic.
  for (const [input, resolve] of [[text, (uri) => (uri === 'external data.bin' ? bin : null)], [bytes, () => null]]) {
    const either = api.Character.fromBytes(input, resolve);
    assert.deepEqual([...either.bindPositions()], [...character.bindPositions()]);
    either.free();
  }
  assert.throws(() => api.Character.fromBytes(text, () => undefined), /external data\.bin/);
  // A URI with a folder: the resolver is asked for its path, then for the file's name (the files
  // of a .gltf dropped together have names, no folders).
  json.buffers[0].uri = 'buffers/external%20data.bin';
  const nested = new TextEncoder().encode(JSON.stringify(json));
  asked.length = 0;
  const byName = api.Character.fromGltf(nested, (uri) => (asked.push(uri), uri === 'external data.bin' ? bin : null));
  assert.deepEqual(asked, ['buffers/external data.bin', 'external data.bin']);
  assert.deepEqual([...byName.bindPositions()], [...character.bindPositions()]);
  byName.free();
  assert.throws(() => api.Character.fromGltf(nested, () => null), /buffers\/external data\.bin/);
  json.buffers[0].uri = 'external%20data.bin';

  // Without texture coordinates, uvs() is undefined, as it is for texture coordinates no texture
  // samples (RiggedSimple's); the normals are the same.
  for (const mesh of json.meshes) for (const primitive of mesh.primitives) delete primitive.attributes.TEXCOORD_0;
  const untextured = api.Character.fromGltf(new TextEncoder().encode(JSON.stringify(json)), () => bin);
  assert.equal(untextured.uvs(), undefined);
  assert.deepEqual(untextured.normals(), character.normals());
  untextured.free();
  character.free();
});

/** A triangle whose corner (0, 1, 0) one morph target lifts by 1 in z, and a clip `lift` whose
 * weight goes linearly from 0 to 1 over a second: a .gltf with its buffer as a data URI. */
function morphingTriangle() {
  const f32 = new Float32Array([
    0, 0, 0, 1, 0, 0, 0, 1, 0, // positions: 0..36
    0, 0, 0, 0, 0, 0, 0, 0, 1, // target deltas: 36..72
    0, 1, // key times: 72..80
    0, 1, // weights: 80..88
  ]);
  const uri = `data:application/octet-stream;base64,${Buffer.from(f32.buffer).toString('base64')}`;
  const json = {
    asset: { version: '2.0' },
    scenes: [{ nodes: [0] }],
    nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, targets: [{ POSITION: 1 }] }] }],
    animations: [{ name: 'lift', channels: [{ sampler: 0, target: { node: 0, path: 'weights' } }], samplers: [{ input: 2, output: 3 }] }],
    buffers: [{ byteLength: 88, uri }],
    bufferViews: [
      { buffer: 0, byteOffset: 0, byteLength: 36 }, { buffer: 0, byteOffset: 36, byteLength: 36 },
      { buffer: 0, byteOffset: 72, byteLength: 8 }, { buffer: 0, byteOffset: 80, byteLength: 8 },
    ],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 3, type: 'VEC3', min: [0, 0, 0], max: [1, 1, 0] },
      { bufferView: 1, componentType: 5126, count: 3, type: 'VEC3' },
      { bufferView: 2, componentType: 5126, count: 2, type: 'SCALAR', min: [0], max: [1] },
      { bufferView: 3, componentType: 5126, count: 2, type: 'SCALAR' },
    ],
  };
  return new TextEncoder().encode(JSON.stringify(json));
}

test('morph targets and their clip weights reach skinnedPositions and levelSkinnedPositions', () => {
  const character = api.Character.fromGltf(morphingTriangle(), () => null);
  assert.equal(character.morphTargetCount, 1);
  assert.deepEqual(character.warnings, []);
  assert.deepEqual([...character.morphWeights('lift', 0.5)], [0.5]);
  const posed = character.skinnedPositions('lift', 0.5);
  assert.deepEqual([...posed], [0, 0, 0, 1, 0, 0, 0, 1, 0.5]);
  const clod = character.buildClod({ pose: 'bind' });
  const level = clod.levelSkinnedPositions(0, 'lift', 0.25);
  // Level vertices are in first-use order: find the lifted corner by its position.
  const lifted = [0, 1, 2].filter((v) => level[3 * v + 1] === 1);
  assert.equal(lifted.length, 1);
  assert.equal(level[3 * lifted[0] + 2], 0.25);
  clod.free();
  character.free();
});
