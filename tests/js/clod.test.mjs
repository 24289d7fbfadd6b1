// The articulated progressive mesh through the JavaScript API (issue 4), from node.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { api, modelBytes } from './models.mjs';

test('buildClod on CesiumMan: levels, ancestors, continuous LOD and skinning', (t) => {
  const bytes = modelBytes('CesiumMan.glb');
  if (!bytes) return t.skip('model missing');
  const character = api.Character.fromGlb(bytes);
  const progress = [];
  const clod = character.buildClod({ onProgress: (f) => progress.push(f) });
  assert.ok(clod.buildMs > 0);
  assert.ok(progress.length >= 2 && progress.at(-1) === 1 && progress.every((f, i) => i === 0 || f >= progress[i - 1]));
  assert.ok(clod.levelCount >= 2);
  assert.ok(clod.ancestorTableBytes > 0);

  let previous = null;
  for (let i = 0; i < clod.levelCount; i++) {
    const level = clod.level(i);
    assert.equal(level.indices.length, 3 * level.triangleCount);
    assert.equal(level.positions.length, 3 * level.vertexCount);
    assert.ok(level.indices.every((v) => v < level.vertexCount));
    if (previous) {
      assert.ok(level.triangleCount < previous.triangleCount, 'levels get coarser');
      assert.ok(level.error >= previous.error, 'error never decreases');
      const ancestors = clod.ancestors(i - 1);
      assert.equal(ancestors.length, previous.vertexCount);
      assert.ok(ancestors.every((a) => a < level.vertexCount), 'every ancestor exists in the coarser level');
    }
    const skinned = clod.levelSkinnedPositions(i, 'Anim_0', 0.7);
    assert.equal(skinned.length, level.positions.length);
    assert.ok(skinned.every(Number.isFinite));
    previous = level;
  }
  assert.equal(clod.level(0).triangleCount, character.triangleCount, 'level 0 is the input mesh');
  assert.throws(() => clod.ancestors(clod.levelCount - 1), /coarser/);
  assert.throws(() => clod.level(clod.levelCount), /does not exist/);

  for (const want of [4000, 2000, 1000]) {
    const mesh = clod.meshAt(want);
    assert.ok(mesh.indices.length / 3 <= want);
    assert.equal(mesh.positions.length, mesh.bindPositions.length);
    assert.ok(mesh.indices.every((v) => v < mesh.positions.length / 3));
  }
  clod.free();
  character.free();
});

test('buildClod options: poses, explicit levels, half-edge mode, and clear errors', (t) => {
  const bytes = modelBytes('Fox.glb');
  if (!bytes) return t.skip('model missing');
  const fox = api.Character.fromGlb(bytes);
  for (const pose of ['bind', 'multi', 'mid-clip', { clip: 'Walk', time: 0.3 }]) {
    const clod = fox.buildClod({ pose, levels: [400, 200, 100], mode: 'halfedge' });
    assert.equal(clod.levelCount, 3);
    assert.deepEqual([0, 1, 2].map((i) => clod.level(i).triangleCount <= [400, 200, 100][i]), [true, true, true]);
    clod.free();
  }
  assert.throws(() => fox.buildClod({ levels: [100, 200] }), /decreasing/);
  assert.throws(() => fox.buildClod({ levels: [1.5] }), /whole/);
  assert.throws(() => fox.buildClod({ pose: 'sideways' }), /pose must be/);
  assert.throws(() => fox.buildClod({ pose: { clip: 'Dance', time: 1 } }), /Dance/);
  assert.throws(() => fox.buildClod({ mode: 'quarter' }), /mode must be/);
  assert.throws(() => fox.buildClod({ onProgress: 3 }), /onProgress/);
  assert.throws(() => fox.buildClod({ maxError: 0 }), /maxError/);
  assert.throws(() => fox.buildClod({ maxError: 'low' }), /maxError/);
  assert.throws(() => fox.buildClod({ schedule: 'fast' }), /schedule must be/);
  // An unknown or ill-typed key names the key and what it takes.
  assert.throws(() => fox.buildClod({ level: [100] }), /^Error: buildClod: unknown field `level`, expected one of `pose`, `levels`, /);
  assert.throws(() => fox.buildClod({ levels: [400, 'many'] }), /^Error: buildClod: levels\[1\] must be a whole number of triangles ≥ 1, got "many"$/);
  assert.throws(() => fox.buildClod({ pose: { clip: 'Walk' } }), /^Error: buildClod: pose must be \{ clip, time \}/);
  assert.throws(() => fox.buildClod('bind'), /^Error: buildClod takes an object/);
  // The strict order is the default; batched passes give a valid chain of the same levels.
  const strict = fox.buildClod({ levels: [400, 200, 100], schedule: 'strict' });
  const passes = fox.buildClod({ levels: [400, 200, 100], schedule: 'passes' });
  const plain = fox.buildClod({ levels: [400, 200, 100] });
  const plainStop = plain.stoppedShort;
  for (let i = 0; i < 3; i++) {
    assert.deepEqual(plain.level(i), strict.level(i));
    assert.ok(passes.level(i).triangleCount <= [400, 200, 100][i]);
    assert.ok(i === 0 || passes.level(i).error >= passes.level(i - 1).error);
  }
  for (const c of [strict, passes, plain]) c.free();
  // The default floor (5 % of the diagonal) keeps Fox's legs; without it the simplifier goes on.
  const floored = fox.buildClod({ levels: [400, 20] });
  const unbounded = fox.buildClod({ levels: [400, 20], maxError: Infinity });
  assert.ok(floored.level(1).triangleCount > unbounded.level(1).triangleCount);
  // ... and says so: where the levels stop, and why.
  assert.match(floored.stoppedShort, new RegExp(`^the levels stop at ${floored.level(1).triangleCount} of 576 triangles .*error limit`));
  assert.equal(plainStop, undefined, 'a build that reaches its last count did not stop short');
  floored.free();
  unbounded.free();
  fox.free();
});

test('buildClodBytes: progress in order ending at 1, bytes that start with "CLOD"', (t) => {
  const bytes = modelBytes('RiggedSimple.glb');
  if (!bytes) return t.skip('model missing');
  const character = api.Character.fromGlb(bytes);
  const progress = [];
  const started = performance.now();
  const encoded = character.buildClodBytes({ levels: [892, 400, 100] }, (f) => progress.push(f));
  const bytesMs = performance.now() - started;
  assert.ok(encoded instanceof Uint8Array);
  assert.equal(new TextDecoder().decode(encoded.subarray(0, 4)), 'CLOD');
  assert.equal(new DataView(encoded.buffer, encoded.byteOffset).getUint32(4, true), 2, 'format version 2');
  assert.equal(progress[0], 0);
  assert.equal(progress.at(-1), 1);
  assert.equal(progress.filter((f) => f === 1).length, 1, '1 only once, when the bytes are ready');
  assert.ok(progress.every((f, i) => f >= 0 && f <= 1 && (i === 0 || f >= progress[i - 1])), `${progress}`);

  // The same chain built twice encodes to the same bytes; options.onProgress works too.
  const again = [];
  const second = character.buildClodBytes({ levels: [892, 400, 100], onProgress: (f) => again.push(f) });
  assert.deepEqual(second, encoded);
  assert.deepEqual(again, progress);
  const clod = character.buildClod({ levels: [892, 400, 100] });
  console.log(`RiggedSimple: ${encoded.length} bytes in ${bytesMs.toFixed(0)} ms (buildClod ${clod.buildMs.toFixed(0)} ms)`);
  clod.free();

  assert.throws(() => character.buildClodBytes({ levels: [100, 200] }), /decreasing/);
  assert.throws(() => character.buildClodBytes({}, 3), /onProgress/);
  character.free();
});
