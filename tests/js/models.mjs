// Shared helpers for the node tests of the JavaScript API: load the nodejs build and the shared models.
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { readManifest } from '../../scripts/manifest.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const manifest = readManifest();

/** The wasm-bindgen module built by `wasm-pack build --target nodejs` (scripts/test.sh builds it). */
export const api = createRequire(import.meta.url)(`${root}${manifest['node.out-dir']}/${manifest['node.out-name']}.js`);

/** Bytes of ../shared/models/NAME, or null (with a message) when absent; absent models fail under CI=true. */
export function modelBytes(name) {
  const path = `${root}../shared/models/${name}`;
  if (!existsSync(path)) {
    if (process.env.CI === 'true') throw new Error(`${path} is missing, and CI needs the shared models`);
    console.log(`skipping: ${path} is missing`);
    return null;
  }
  return new Uint8Array(readFileSync(path));
}
