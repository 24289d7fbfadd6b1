// The JavaScript API of issue 2, called from node exactly as a page would call it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { api, modelBytes } from './models.mjs';

const models = [
  { file: 'CesiumMan.glb', triangles: 4672, joints: 19, clips: ['Anim_0'] },
  { file: 'Fox.glb', triangles: 576, joints: 24, clips: ['Survey', 'Walk', 'Run'] },
  { file: 'RiggedSimple.glb', triangles: 892, joints: 4, clips: null },
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
    if (model.clips) assert.deepEqual(character.clipNames, model.clips);
    assert.ok(character.clipNames.length >= 1);

    const indices = character.indices();
    assert.ok(indices instanceof Uint32Array);
    assert.equal(indices.length, 3 * character.triangleCount);
    assert.ok(indices.every((i) => i < character.vertexCount));

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
    // All three models are textured.
    const uvs = character.uvs();
    assert.ok(uvs instanceof Float32Array);
    assert.equal(uvs.length, 2 * character.vertexCount);
    assert.ok(uvs.every(Number.isFinite));
    assert.ok(uvs.some((x) => x !== 0), 'the texture coordinates are not all zero');

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

  // Without texture coordinates, uvs() is undefined; the normals are the same.
  for (const mesh of json.meshes) for (const primitive of mesh.primitives) delete primitive.attributes.TEXCOORD_0;
  const untextured = api.Character.fromGltf(new TextEncoder().encode(JSON.stringify(json)), () => bin);
  assert.equal(untextured.uvs(), undefined);
  assert.deepEqual(untextured.normals(), character.normals());
  untextured.free();
  character.free();
});
