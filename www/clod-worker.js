// Module worker of <clod-viewer>: builds a character's LOD chain off the main thread with the same
// wasm build the page loaded, and sends it back as bytes (src/clod/bytes.rs) that the page's
// `Viewer.create` decodes. Messages in: `{ id, moduleUrl, name, bytes, resources }`; out:
// `{ id, type: 'progress', fraction }` (rising, ending at 1), then `{ id, type: 'done', clod,
// buildMs }` or `{ id, type: 'error', message }`.

const builds = new Map();

function load(moduleUrl) {
  if (!builds.has(moduleUrl)) {
    builds.set(moduleUrl, import(moduleUrl).then(async (module) => { await module.default(); return module; }));
  }
  return builds.get(moduleUrl);
}

const GLB_MAGIC = [0x67, 0x6c, 0x54, 0x46]; // "glTF"

self.onmessage = async ({ data: { id, moduleUrl, name, bytes, resources } }) => {
  let character = null;
  try {
    const { Character } = await load(moduleUrl);
    const isGlb = GLB_MAGIC.every((b, i) => bytes[i] === b);
    const resolve = (uri) => resources?.get(uri) ?? resources?.get(decodeURIComponent(uri.split('/').pop())) ?? null;
    character = isGlb ? Character.fromGlb(bytes) : Character.fromGltf(bytes, resolve);
    const started = performance.now();
    const clod = character.buildClodBytes({}, (fraction) => self.postMessage({ id, type: 'progress', fraction }));
    const buildMs = performance.now() - started;
    self.postMessage({ id, type: 'done', clod, buildMs }, [clod.buffer]);
  } catch (e) {
    self.postMessage({ id, type: 'error', message: `Could not show ${name}: ${e.message ?? e}` });
  } finally {
    character?.free();
  }
};
