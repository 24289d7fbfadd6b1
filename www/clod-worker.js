// Module worker of <clod-viewer>: builds a character's LOD chain off the main thread with the same
// wasm build the page loaded, and sends it back as bytes (src/clod/bytes/) that the page's
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

self.onmessage = async ({ data: { id, moduleUrl, name, bytes, resources } }) => {
  let character = null;
  try {
    const { Character } = await load(moduleUrl);
    // A .gltf's files were dropped with it: by name (the wasm side asks for a URI's path, then
    // its last segment).
    const resolve = (name) => resources?.get(name) ?? null;
    character = Character.fromBytes(bytes, resolve);
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
