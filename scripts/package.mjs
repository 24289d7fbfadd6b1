// Assembles the npm package of the <clod-viewer> element in target/package/clod-viewer/ from what
// the wasm builds left in www/ (scripts/package.sh runs them first) and packs it with `npm pack`
// into target/package/clod-viewer-VERSION.tgz (VERSION: Cargo.toml's). Prints the tarball's path.
//
// The layout is www/'s: the element finds every file relative to its own URL (clod-viewer.js),
// so node_modules/clod-viewer/ can be served as it is, or bundled (the element names its files as
// literal `import('./…')` and `new URL('./…', import.meta.url)`).
import { copyFileSync, existsSync, mkdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { readManifest } from './manifest.mjs';

const repo = fileURLToPath(new URL('..', import.meta.url));
const manifest = readManifest();
const cargo = readFileSync(join(repo, 'Cargo.toml'), 'utf8');
const field = (name) => cargo.match(new RegExp(`^${name} = "([^"]*)"`, 'm'))[1];
const version = field('version');
const out = join(repo, 'target/package');
const stage = join(out, 'clod-viewer');

// [package path, repository path]
const files = [
  ['clod-viewer.js', 'www/clod-viewer.js'],
  // The replay's drawing (drawReplay), which clod-viewer.js imports and re-exports.
  ['clod-replay.js', 'www/clod-replay.js'],
  // Its wasm builds, worker and chain cache (loadBuild, loadDraco, …), which it imports and re-exports.
  ['clod-loading.js', 'www/clod-loading.js'],
  ['clod-worker.js', 'www/clod-worker.js'],
  ['clod-viewer.d.ts', 'www/clod-viewer.d.ts'],
  ['README.md', 'package/README.md'],
  // The element's default model: `new URL('./assets/character.glb', import.meta.url)`.
  ['assets/character.glb', 'assets/character.glb'],
];
for (const section of ['web', 'webgl', 'draco']) {
  const dir = manifest[`${section}.out-dir`];
  const name = manifest[`${section}.out-name`];
  const to = dir.replace(/^www\//, '');
  for (const suffix of ['.js', '_bg.wasm', '.d.ts']) files.push([`${to}/${name}${suffix}`, `${dir}/${name}${suffix}`]);
}
const missing = files.filter(([, from]) => !existsSync(join(repo, from))).map(([, from]) => from);
if (missing.length) {
  console.error(`missing (build them: bash scripts/package.sh): ${missing.join(', ')}`);
  process.exit(1);
}

rmSync(stage, { recursive: true, force: true });
for (const [to, from] of files) {
  mkdirSync(dirname(join(stage, to)), { recursive: true });
  copyFileSync(join(repo, from), join(stage, to));
}
const pkg = {
  name: 'clod-viewer',
  version,
  description: 'The <clod-viewer> custom element: LOD transitions (popping, alpha-blending, geomorphing) on skinned glTF characters, side by side, in WebGPU or WebGL2.',
  license: field('license'),
  type: 'module',
  main: './clod-viewer.js',
  module: './clod-viewer.js',
  types: './clod-viewer.d.ts',
  exports: {
    '.': { types: './clod-viewer.d.ts', default: './clod-viewer.js' },
    './clod-viewer.js': { types: './clod-viewer.d.ts', default: './clod-viewer.js' },
    './clod-replay.js': './clod-replay.js',
    './clod-loading.js': './clod-loading.js',
    './clod-worker.js': './clod-worker.js',
    './assets/*': './assets/*',
    './pkg/*': './pkg/*',
    './pkg-webgl/*': './pkg-webgl/*',
    './pkg-draco/*': './pkg-draco/*',
    './package.json': './package.json',
  },
  files: files.map(([to]) => to).filter((to) => to !== 'README.md'),
  // Importing the module defines the element.
  sideEffects: ['./clod-viewer.js'],
  keywords: ['webcomponent', 'custom-element', 'gltf', 'lod', 'level-of-detail', 'progressive-mesh', 'webgpu', 'webgl2', 'wasm'],
};
writeFileSync(join(stage, 'package.json'), `${JSON.stringify(pkg, null, 2)}\n`);
const tarball = execFileSync('npm', ['pack', '--pack-destination', out, '--json'], { cwd: stage, encoding: 'utf8' });
const [{ filename, size, unpackedSize, entryCount }] = JSON.parse(tarball);
const path = join(out, filename);
const kib = (n) => `${(n / 1024).toFixed(1)} KiB`;
console.error(`${filename}: ${entryCount} files, ${kib(size)} packed, ${kib(unpackedSize)} unpacked (${kib(statSync(path).size)} on disk)`);
console.log(path);
