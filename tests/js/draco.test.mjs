// Draco-compressed files (KHR_draco_mesh_compression), as a user gets them from `gltf-transform
// draco` with Google's own encoder (draco3dgltf, the library Blender's exporter and gltf-pipeline also
// use), in memory: the shared models and the generated robot (28 primitives, morph targets on
// the face), with the EdgeBreaker and the sequential connectivity codecs. Each must import with
// its clips, skins and morph targets, skin to the uncompressed file's surface within the
// encoder's quantization (14-bit positions: under 1e-3 of the diagonal) at every measured
// frame, and build its levels. Draco reorders and welds vertices, so surfaces are compared,
// not arrays. Primitives sharing one stream cannot make a small file decode to gigabytes: all
// streams together decode to at most 64 times the file.
//
// The node tests bind the WebGPU page's wasm, which links no Draco decoder (wasm-pack.toml:
// default-features = false): as the page does, they load crates/clod-draco's own module
// (www/pkg-draco/, `build_wasm draco`) and hand its `decode` to `Character.fromBytes`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import { draco } from '@gltf-transform/functions';
import draco3d from 'draco3dgltf';
import { api, modelBytes } from './models.mjs';

const io = new NodeIO().registerExtensions(ALL_EXTENSIONS).registerDependencies({
  'draco3d.encoder': await draco3d.createEncoderModule(),
  'draco3d.decoder': await draco3d.createDecoderModule(),
});

/** `bytes` through `gltf-transform draco --method METHOD` (which welds, then compresses every primitive). */
async function dracoCompress(bytes, method) {
  const document = await io.readBinary(bytes);
  await document.transform(draco({ method }));
  return io.writeBinary(document);
}

/** The JSON chunk of a GLB. */
function glbJson(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + view.getUint32(12, true))));
}

/** The separate Draco module's `decode`, or null (failing under CI) when it is not built. */
const glue = fileURLToPath(new URL('../../www/pkg-draco/clod_draco.js', import.meta.url));
const dracoModule = existsSync(glue) ? await import(glue) : null;
if (dracoModule) await dracoModule.default({ module_or_path: readFileSync(glue.replace(/\.js$/, '_bg.wasm')) });
else if (process.env.CI === 'true') throw new Error(`${glue} is missing: build_wasm draco first`);
else console.log('skipping: www/pkg-draco is not built (build_wasm draco)');

/** A Draco-compressed file through the JS API, with the separate module's decoder. */
const fromDraco = (bytes, decode = dracoModule.decode) => api.Character.fromBytes(bytes, () => null, decode);

const robot = () => new Uint8Array(readFileSync(fileURLToPath(new URL('../../assets/robot.glb', import.meta.url))));
const cases = [
  ['CesiumMan.glb', () => modelBytes('CesiumMan.glb'), 'edgebreaker'],
  ['Fox.glb', () => modelBytes('Fox.glb'), 'edgebreaker'],
  ['RiggedSimple.glb', () => modelBytes('RiggedSimple.glb'), 'sequential'],
  ['robot.glb', robot, 'edgebreaker'],
  ['robot.glb', robot, 'sequential'],
];

for (const [name, load, method] of cases) {
  test(`${name} compressed with Draco (${method}) imports, skins as the original and builds its levels`, async (t) => {
    const bytes = load();
    if (!bytes) return t.skip('model missing');
    if (!dracoModule) return t.skip('www/pkg-draco is not built');
    const packed = await dracoCompress(bytes, method);
    const json = glbJson(packed);
    assert.ok(json.extensionsRequired.includes('KHR_draco_mesh_compression'));
    const compressed = json.meshes.flatMap((m) => m.primitives).filter((p) => p.extensions?.KHR_draco_mesh_compression);
    assert.ok(compressed.length > 0, 'the encoder compressed primitives');
    const original = api.Character.fromGlb(bytes);
    const c = fromDraco(packed);
    try {
      assert.deepEqual(c.warnings, original.warnings);
      assert.equal(c.triangleCount, original.triangleCount);
      assert.equal(c.jointCount, original.jointCount);
      assert.equal(c.morphTargetCount, original.morphTargetCount);
      assert.deepEqual(c.clipNames, original.clipNames);
      const diag = api.boundsDiagonal(original.bindPositions());
      for (const clip of original.clipNames) {
        for (const f of [0.1, 0.45, 0.8]) {
          const time = original.clipDuration(clip) * f;
          const d = api.surfaceDistance(original.skinnedPositions(clip, time), original.indices(),
            c.skinnedPositions(clip, time), c.indices(), 4000, 1);
          assert.ok(d.hausdorff / diag < 1e-3, `${clip} at ${time.toFixed(2)} s: ${d.hausdorff / diag} of the diagonal`);
        }
      }
      const clod = c.buildClod();
      assert.ok(clod.levelCount > 2, `${clod.levelCount} levels`);
      clod.free();
    } finally {
      c.free();
      original.free();
    }
  });
}

/** `bytes` with its JSON chunk replaced by `json`. */
function withJson(bytes, json) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const rest = bytes.subarray(20 + view.getUint32(12, true));
  const text = new TextEncoder().encode(JSON.stringify(json));
  const chunk = new Uint8Array(Math.ceil(text.length / 4) * 4).fill(0x20);
  chunk.set(text);
  const out = new Uint8Array(20 + chunk.length + rest.length);
  const header = new DataView(out.buffer);
  header.setUint32(0, 0x46546c67, true);
  header.setUint32(4, 2, true);
  header.setUint32(8, out.length, true);
  header.setUint32(12, chunk.length, true);
  header.setUint32(16, 0x4e4f534a, true);
  out.set(chunk, 20);
  out.set(rest, 20 + chunk.length);
  return out;
}

test('Draco streams shared by many primitives cannot decode to far more than the file', async (t) => {
  const bytes = modelBytes('CesiumMan.glb');
  if (!bytes) return t.skip('model missing');
  if (!dracoModule) return t.skip('www/pkg-draco is not built');
  const packed = await dracoCompress(bytes, 'edgebreaker');
  const json = glbJson(packed);
  // One primitive decodes to about 1.5 times this file; a hundred sharing its stream, to 150.
  const primitive = json.meshes[0].primitives[0];
  json.meshes[0].primitives = Array.from({ length: 100 }, () => primitive);
  assert.throws(() => fromDraco(withJson(packed, json)), /more than 64 times its size/);
  json.meshes[0].primitives = [primitive, primitive];
  const once = fromDraco(packed);
  const twice = fromDraco(withJson(packed, json));
  assert.equal(twice.triangleCount, 2 * once.triangleCount);
  twice.free();
  once.free();
});

// `usesDraco` is what the page asks before loading the module; without a decoder the import says
// what is missing; a decoder that answers nonsense is a message naming the primitive.
test('usesDraco finds the files that need the Draco module, and the import needs a decoder for them', async (t) => {
  if (!dracoModule) return t.skip('www/pkg-draco is not built');
  const original = robot();
  const packed = await dracoCompress(original, 'sequential');
  assert.equal(api.usesDraco(packed), true);
  assert.equal(api.usesDraco(original), false);
  assert.equal(api.usesDraco(new TextEncoder().encode('{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"]}')), true);
  assert.equal(api.usesDraco(new Uint8Array([1, 2, 3])), false);
  assert.throws(() => api.Character.fromBytes(packed, () => null), /KHR_draco_mesh_compression \(Draco-compressed geometry\).*separate Draco module/);
  let calls = 0;
  const counted = fromDraco(packed, (stream, request) => { calls++; return dracoModule.decode(stream, request); });
  assert.equal(calls, glbJson(packed).meshes.flatMap((m) => m.primitives).filter((p) => p.extensions?.KHR_draco_mesh_compression).length);
  counted.free();
  assert.throws(() => fromDraco(packed, () => new Uint8Array([9, 9])), /meshes\[\d+\]\.primitives\[\d+\]: its Draco stream does not decode \(the Draco decoder's answer is malformed\)/);
  assert.throws(() => fromDraco(packed, () => 'no'), /its Draco stream does not decode \(the Draco module did not answer\)/);
});
