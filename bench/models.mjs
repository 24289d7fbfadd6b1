// The models a benchmark measures. With no paths on its command line: the three shared models
// (../shared/models: CesiumMan, Fox, RiggedSimple), then any other .glb or .gltf in that folder,
// then the project's test characters in assets/ that the benchmark names, then the generated ones
// it names (made into target/generated/ on the spot, bench/generated.mjs). Paths on the command
// line replace that list: each a .glb or .gltf file, or a folder standing for the ones in it. So
// a user measures their own character with `node bench/animated-vs-meshoptimizer.mjs my.glb`.
import { existsSync, readdirSync, readFileSync, statSync } from 'node:fs';
import { basename, dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { api } from '../tests/js/models.mjs';
import { generated } from './generated.mjs';

const root = fileURLToPath(new URL('../', import.meta.url));
const SHARED = join(root, '../shared/models');
const SHARED_NAMES = ['CesiumMan.glb', 'Fox.glb', 'RiggedSimple.glb'];
const isModel = (path) => /\.(glb|gltf)$/i.test(path);

/** The .glb and .gltf files of `folder`, sorted by name. */
function modelsIn(folder) {
  return readdirSync(folder).filter(isModel).sort().map((f) => join(folder, f));
}

/**
 * Paths of the models to measure: `args` (files and folders, see the top of this file) when it
 * names any, or the default list: the shared models, `assets/<name>` for each of `assetNames`
 * present, and `target/generated/<name>` for each of `generatedNames`, generated now.
 * An absent shared model is skipped with a line (and fails under CI=true, as in the tests).
 *
 * @throws {Error} naming a path on the command line that is neither a model nor a folder, or when
 * the generator fails.
 */
export function modelPaths(args, assetNames, generatedNames = []) {
  if (args.length) {
    return args.flatMap((arg) => {
      const path = resolve(arg);
      if (existsSync(path) && statSync(path).isDirectory()) return modelsIn(path);
      if (!existsSync(path) || !isModel(path)) throw new Error(`${arg}: not a .glb or .gltf file, or a folder of them`);
      return [path];
    });
  }
  const shared = SHARED_NAMES.map((name) => join(SHARED, name)).filter((path) => {
    if (existsSync(path)) return true;
    if (process.env.CI === 'true') throw new Error(`${path} is missing, and CI needs the shared models`);
    console.log(`skipping: ${path} is missing`);
    return false;
  });
  const others = existsSync(SHARED) ? modelsIn(SHARED).filter((p) => !SHARED_NAMES.includes(basename(p))) : [];
  const assets = assetNames.map((name) => join(root, 'assets', name)).filter((path) => {
    if (!existsSync(path)) console.log(`skipping ${basename(path)}: ${path} is missing`);
    return existsSync(path);
  });
  return [...shared, ...others, ...assets, ...generatedNames.map((name) => generated(name))];
}

/**
 * One model file: `{ name, path, json, character }`, `json` being its glTF JSON (for what the file
 * itself has, see `fileHasNormals`) and `character` the imported `Character` (free it when done).
 * A `.gltf` reads its external buffers and images from its folder.
 *
 * @throws {Error} the importer's message, prefixed with the file's name.
 */
export function loadModel(path) {
  const bytes = new Uint8Array(readFileSync(path));
  const name = basename(path);
  try {
    if (/\.glb$/i.test(path)) {
      // The importer first: its message names what is wrong with a broken file.
      const character = api.Character.fromGlb(bytes);
      return { name, path, json: glbJson(bytes), character };
    }
    const json = JSON.parse(new TextDecoder().decode(bytes).replace(/^\uFEFF/, ''));
    const folder = dirname(path);
    const readUri = (uri) => (existsSync(join(folder, uri)) ? new Uint8Array(readFileSync(join(folder, uri))) : null);
    return { name, path, json, character: api.Character.fromGltf(bytes, readUri) };
  } catch (error) {
    throw new Error(`${name}: ${error.message}`);
  }
}

/** The JSON chunk of a `.glb`, parsed. */
export function glbJson(glb) {
  const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
  const jsonLength = view.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLength)));
}
