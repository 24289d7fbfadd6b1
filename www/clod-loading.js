// What the `<clod-viewer>` element (clod-viewer.js) loads, shared by every element of a page: its
// wasm builds (WebGPU from pkg/, the WebGL2 fallback from pkg-webgl/) and the Draco decoder
// (pkg-draco/), each loaded once; the LOD build in a Web Worker (clod-worker.js); and the cache of
// built LOD chains in IndexedDB, keyed by the file's SHA-256 and the code that built it.
//
// Every file is named relative to this module as a literal `import('./…')` or
// `new URL('./…', import.meta.url)`, so a browser finds it next to this file wherever a site
// hosts it and bundlers emit it with the bundle.

// --- wasm builds, shared by every element of the page ---------------------------------------

const builds = new Map();

/** Loads (once) the wasm build of `backend` (`webgpu` → pkg/, `webgl2` → pkg-webgl/). */
export function loadBuild(backend) {
  if (!builds.has(backend)) {
    const url = backend === 'webgpu' ? new URL('./pkg/clod_viewer.js', import.meta.url).href : new URL('./pkg-webgl/clod_viewer.js', import.meta.url).href;
    const module = backend === 'webgpu' ? import('./pkg/clod_viewer.js') : import('./pkg-webgl/clod_viewer.js');
    builds.set(backend, module.then(async (module) => { await module.default(); return { module, url }; }));
    builds.get(backend).catch(() => builds.delete(backend));
  }
  return builds.get(backend);
}

let draco = null;
/**
 * Loads (once) the Draco decoder (pkg-draco/, crates/clod-draco), a module of its own that only
 * files with Draco-compressed geometry need: resolves to `{ decode, url }`.
 */
export function loadDraco() {
  if (!draco) {
    draco = import('./pkg-draco/clod_draco.js').then(async (module) => { await module.default(); return { decode: module.decode }; });
    draco.catch(() => { draco = null; });
  }
  return draco;
}

let adapterCheck = null;
/** Whether this browser hands out a WebGPU adapter (asked once per page). */
export function webgpuWorks() {
  adapterCheck ??= (async () => {
    if (!('gpu' in navigator)) return false;
    try { return (await navigator.gpu.requestAdapter()) !== null; } catch { return false; }
  })();
  return adapterCheck;
}

// --- the LOD build in a worker ---------------------------------------------------------------

let worker = null;
let workerBroken = false;
const jobs = new Map();
let nextJob = 1;

export function buildWorker() {
  if (worker || workerBroken) return worker;
  try {
    worker = new Worker(new URL('./clod-worker.js', import.meta.url), { type: 'module' });
  } catch {
    workerBroken = true;
    return null;
  }
  worker.onmessage = ({ data }) => {
    const job = jobs.get(data.id);
    if (!job) return;
    if (data.type === 'progress') { job.onProgress(data.fraction); return; }
    jobs.delete(data.id);
    if (data.type === 'done') job.resolve(data);
    else job.reject(new Error(data.message));
  };
  worker.onerror = (e) => {
    // A worker that cannot start (no module workers): build on the main thread from now on.
    workerBroken = true;
    worker = null;
    for (const job of jobs.values()) job.reject(Object.assign(new Error(e.message || 'worker failed'), { workerFailed: true }));
    jobs.clear();
  };
  return worker;
}

/**
 * Builds the LOD chain of `source` off the main thread with the `backend` build (the one the page
 * loaded, from the HTTP cache), its Draco module when `draco`. Resolves to `{ clod: Uint8Array,
 * buildMs }`, or to null when no worker can run (the caller then builds inline).
 */
export function buildOffMainThread(backend, draco, source, onProgress) {
  const w = buildWorker();
  if (!w) return Promise.resolve(null);
  const id = nextJob++;
  return new Promise((resolve, reject) => {
    jobs.set(id, { resolve, reject, onProgress });
    w.postMessage({ id, backend, draco, name: source.name, bytes: source.bytes, resources: source.resources });
  }).catch((e) => { if (e.workerFailed) return null; throw e; });
}

// --- the LOD chain cache (IndexedDB) ------------------------------------------------------------

const CACHE_DB = 'clod-viewer';
const CACHE_STORE = 'chains';

/**
 * The cache key of a source's LOD chain: the tag of the code that builds it (`chainCacheTag`,
 * so an updated viewer never attaches levels its own simplifier did not make), SHA-256 of the
 * file (and a .gltf's resources, by name) and the build options; null where the browser has no
 * subtle crypto (plain http).
 */
export async function chainKey(source, codeTag) {
  if (!globalThis.crypto?.subtle || !globalThis.indexedDB) return null;
  const parts = [source.bytes, ...[...(source.resources ?? new Map())].sort(([a], [b]) => (a < b ? -1 : 1)).flatMap(([name, bytes]) => [new TextEncoder().encode(name), bytes])];
  const whole = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) { whole.set(p, at); at += p.length; }
  const digest = new Uint8Array(await crypto.subtle.digest('SHA-256', whole));
  const hex = [...digest].map((b) => b.toString(16).padStart(2, '0')).join('');
  return `${codeTag}:${hex}:default`;
}

function openCache() {
  return new Promise((resolve, reject) => {
    const request = indexedDB.open(CACHE_DB, 1);
    request.onupgradeneeded = () => request.result.createObjectStore(CACHE_STORE);
    request.onsuccess = () => resolve(request.result);
    request.onerror = () => reject(request.error);
  });
}

/** The cached `{ clod, buildMs }` of `key`, or null (missing, or the cache cannot be used). */
export async function cacheGet(key) {
  try {
    const db = await openCache();
    return await new Promise((resolve) => {
      const request = db.transaction(CACHE_STORE).objectStore(CACHE_STORE).get(key);
      // Connections are closed after use, so nothing holds the database open (a page may delete it).
      request.onsuccess = () => { db.close(); resolve(request.result ?? null); };
      request.onerror = () => { db.close(); resolve(null); };
    });
  } catch { return null; }
}

/**
 * Stores `{ clod, buildMs }` under `key`, and drops the entries of other code tags: no build of
 * the viewer reads another's, so each update would otherwise leave them behind for good. A cache
 * that cannot be written is skipped.
 */
export async function cachePut(key, value) {
  try {
    const db = await openCache();
    const transaction = db.transaction(CACHE_STORE, 'readwrite');
    const store = transaction.objectStore(CACHE_STORE);
    store.put(value, key);
    const tag = key.slice(0, key.indexOf(':') + 1);
    store.openKeyCursor().onsuccess = (event) => {
      const cursor = event.target.result;
      if (!cursor) return;
      if (typeof cursor.key !== 'string' || !cursor.key.startsWith(tag)) store.delete(cursor.key);
      cursor.continue();
    };
    transaction.oncomplete = transaction.onerror = transaction.onabort = () => db.close();
  } catch { /* private mode or quota: the next visit builds again */ }
}

/**
 * A `.gltf`'s resolver over the files dropped with it, by name. The wasm side asks for a URI's
 * path and then its last segment (`textures/skin.png`, then `skin.png`).
 */
export function resolverFor(resources) {
  return (name) => resources?.get(name) ?? null;
}
