// Module worker of <clod-viewer>: builds a character's LOD chain off the main thread with the same
// wasm build the page loaded, and sends it back as bytes (src/clod/bytes/) that the page's
// `Viewer.create` decodes. Messages in: `{ id, backend, draco, name, bytes, resources }` (`backend`
// names the build: `webgpu` or `webgl2`; `draco`: the file needs the Draco module); out:
// `{ id, type: 'progress', fraction }` (rising, ending at 1), then `{ id, type: 'done', clod,
// buildMs }` or `{ id, type: 'error', message }`.

// The same literal paths as the element's (see clod-viewer.js): next to this file unbundled, and
// found by bundlers.
const builds = new Map();

function load(which) {
  if (!builds.has(which)) {
    const module = which === 'webgpu' ? import('./pkg/clod_viewer.js')
      : which === 'webgl2' ? import('./pkg-webgl/clod_viewer.js') : import('./pkg-draco/clod_draco.js');
    builds.set(which, module.then(async (m) => { await m.default(); return m; }));
  }
  return builds.get(which);
}

self.onmessage = async ({ data: { id, backend, draco, name, bytes, resources } }) => {
  let character = null;
  try {
    const { Character } = await load(backend);
    const decode = draco ? (await load('draco')).decode : undefined;
    // A .gltf's files were dropped with it: by name (the wasm side asks for a URI's path, then
    // its last segment).
    const resolve = (name) => resources?.get(name) ?? null;
    character = Character.fromBytes(bytes, resolve, decode);
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
