// www/clod-viewer.d.ts, the element's types for documentation pages, against what the viewer
// really produces and takes, with the TypeScript compiler (node_modules/typescript):
// - it compiles, and a page's typical use type-checks against it (tests/js/types/viewer-usage.ts);
// - tests/js/types/api-samples.json, written by `cargo test` from the Rust types the viewer hands
//   JavaScript (src/js_api/samples.rs: every key present, every optional value set, then every
//   optional value absent), type-checks against the declared types as object literals: no key
//   the viewer writes or takes is undeclared, no declared key is missing, every value has its
//   declared type, and each set of names (`overlay`, `variant`, …) is exactly the declared union;
// - the build options of `buildClod` (`BuildOptions` in the wasm build's own .d.ts) likewise;
// - the element's members, attributes and exports (read from the loaded module, not its text)
//   are declared.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../../', import.meta.url));
const ts = createRequire(import.meta.url)(`${root}node_modules/typescript`);
const samples = JSON.parse(readFileSync(`${root}tests/js/types/api-samples.json`, 'utf8'));
const nodeDts = `${root}target/pkg-node/clod_viewer.d.ts`;

// esnext: wasm-bindgen's .d.ts declares `[Symbol.dispose]`.
const OPTIONS = { strict: true, noEmit: true, target: ts.ScriptTarget.ES2022, module: ts.ModuleKind.ES2022,
  moduleResolution: ts.ModuleResolutionKind.Bundler, lib: ['lib.esnext.d.ts', 'lib.dom.d.ts'], types: [] };

/** Type-checks `files` plus the in-memory `virtual` sources; returns the diagnostics as text. */
function check(files, virtual = {}) {
  const host = ts.createCompilerHost(OPTIONS);
  const read = host.readFile.bind(host);
  const exists = host.fileExists.bind(host);
  host.readFile = (name) => virtual[name] ?? read(name);
  host.fileExists = (name) => name in virtual || exists(name);
  const getSourceFile = host.getSourceFile.bind(host);
  host.getSourceFile = (name, version) => (name in virtual ? ts.createSourceFile(name, virtual[name], version, true) : getSourceFile(name, version));
  const program = ts.createProgram([...files, ...Object.keys(virtual)], OPTIONS, host);
  const diagnostics = ts.getPreEmitDiagnostics(program);
  return { program, errors: diagnostics.map((d) => `${d.file ? `${d.file.fileName.replace(root, '')}:${d.file.getLineAndCharacterOfPosition(d.start).line + 1}: ` : ''}${ts.flattenDiagnosticMessageText(d.messageText, '\n')}`) };
}

/**
 * TypeScript that holds every sample of `types` (sample name → `[declared type, the type of its
 * full sample]`) as an object literal of its declared type, and each `names` list as an exact union.
 */
function samplesSource(importFrom, types) {
  const lines = [`import type { ${Object.values(types).map(([type]) => type).join(', ')} } from '${importFrom}';`,
    'type Exact<A, B> = [A] extends [B] ? ([B] extends [A] ? true : false) : false;',
    // Bytes (a replay's pictures) reach JavaScript as Uint8Array, JSON as arrays of numbers.
    'type AsJson<T> = T extends Uint8Array ? number[] : T extends object ? { [K in keyof T]: AsJson<T[K]> } : T;'];
  for (const [name, [type, declared]] of Object.entries(types)) {
    for (const [kind, value] of Object.entries(samples[name])) {
      if (kind === 'names') {
        for (const [key, names] of Object.entries(value)) {
          // A dotted key names a value further in: `preset.values.key` is the key of each of
          // `preset.values`.
          let item = type;
          let sample = samples[name].full;
          for (const part of key.split('.')) {
            item = `NonNullable<${item}['${part}']>`;
            sample = sample?.[part];
            if (Array.isArray(sample)) { item = `${item}[number]`; sample = sample[0]; }
          }
          lines.push(`export const ${name}_${key.replaceAll('.', '_')}_names: Exact<Extract<${item}, string>, ${names.map((n) => JSON.stringify(n)).join(' | ')}> = true;`);
        }
      } else {
        // Every declared key must be in the full sample (Required), none may be extra (a fresh literal).
        lines.push(`export const ${name}_${kind}: ${kind === 'full' ? declared : type} = ${JSON.stringify(value)};`);
      }
    }
  }
  return `${lines.join('\n')}\n`;
}

test('the element types compile, and a docs page\'s use of them type-checks', () => {
  const { errors } = check([`${root}www/clod-viewer.d.ts`, `${root}tests/js/types/viewer-usage.ts`]);
  assert.deepEqual(errors, []);
});

test('the samples were written by the current types', () => {
  assert.match(samples.about, /src\/js_api\/samples\.rs/);
  for (const name of ['ViewerState', 'ViewerSettings', 'MeterHistory', 'Replay', 'FlipResult', 'PopSpike', 'PopSpikeOptions', 'BuildOptions']) {
    assert.ok(samples[name]?.full, `${name} has a full sample`);
  }
});

test('state(), setState, meterHistory(), replay(), flipImages() and measurePopSpike() are declared as the viewer writes and reads them', () => {
  const virtual = `${root}tests/js/types/api-samples.check.ts`;
  const source = samplesSource('../../../www/clod-viewer.js', {
    ViewerState: ['ViewerState', 'ViewerState'], ViewerSettings: ['ViewerSettings', 'Required<ViewerSettings>'],
    MeterHistory: ['MeterHistory', 'MeterHistory'], Replay: ['Replay', 'AsJson<Replay>'],
    FlipResult: ['FlipResult', 'FlipResult'], PopSpike: ['PopSpike', 'PopSpike'],
    PopSpikeOptions: ['PopSpikeOptions', 'Required<PopSpikeOptions>'],
  });
  const { errors } = check([], { [virtual]: source });
  assert.deepEqual(errors, [], `${errors.join('\n')}\n\nin the samples as TypeScript:\n${source}`);
});

test('buildClod\'s options are declared in the wasm build\'s types as the build reads them', (t) => {
  if (!existsSync(nodeDts)) {
    if (process.env.CI === 'true') throw new Error(`${nodeDts} is missing: build_wasm node first`);
    return t.skip('target/pkg-node is not built');
  }
  const virtual = `${root}target/pkg-node/api-samples.check.ts`;
  const source = samplesSource('./clod_viewer.js', { BuildOptions: ['BuildOptions', "Required<Omit<BuildOptions, 'onProgress'>>"] });
  const { errors } = check([], { [virtual]: source });
  assert.deepEqual(errors, [], `${errors.join('\n')}\n\nin the samples as TypeScript:\n${source}`);
  // And the functions take them.
  const use = `${root}target/pkg-node/api-use.check.ts`;
  const { errors: useErrors } = check([], { [use]: "import { Character } from './clod_viewer.js';\ndeclare const c: Character;\nc.buildClod({ levels: [100], onProgress: (f: number) => f });\nc.buildClodBytes({ pose: 'bind' }, undefined);\n// @ts-expect-error: an unknown option\nc.buildClod({ level: [100] });\n" });
  assert.deepEqual(useErrors, []);
});

test('every public member, attribute and export of the element is declared', async () => {
  // The module itself, loaded with the least DOM its top level needs.
  globalThis.HTMLElement ??= class {};
  globalThis.customElements ??= { get: () => undefined, define: () => {} };
  const module = await import('../../www/clod-viewer.js');
  const element = module.ClodViewerElement;
  const { program, errors } = check([`${root}www/clod-viewer.d.ts`]);
  assert.deepEqual(errors, []);
  const checker = program.getTypeChecker();
  const file = program.getSourceFile(`${root}www/clod-viewer.d.ts`);
  const exports = checker.getExportsOfModule(checker.getSymbolAtLocation(file));
  const declared = (name) => exports.find((s) => s.name === name);
  const classSymbol = declared('ClodViewerElement');
  const instance = checker.getDeclaredTypeOfSymbol(classSymbol);
  const members = new Set(checker.getPropertiesOfType(instance).map((s) => s.name));
  const lifecycle = ['constructor', 'connectedCallback', 'disconnectedCallback', 'attributeChangedCallback'];
  const own = Object.getOwnPropertyNames(element.prototype).filter((n) => !lifecycle.includes(n));
  assert.ok(own.includes('setState') && own.includes('load') && own.includes('backend'), `members found: ${own}`);
  assert.deepEqual(own.filter((n) => !members.has(n)), [], 'members of the element the .d.ts does not declare');
  // The attributes it observes are listed in the class's doc comment.
  const doc = ts.displayPartsToString(classSymbol.getDocumentationComment(checker));
  const tag = doc.match(/`<clod-viewer ([^>]*)>`/)[1].split(' ');
  assert.deepEqual(element.observedAttributes.filter((a) => !tag.includes(a)), []);
  assert.deepEqual(Object.keys(module).filter((n) => !declared(n)), [], 'exports the .d.ts does not declare');
  // Events: the element's `#emit` calls (private, so read from the text).
  const js = readFileSync(`${root}www/clod-viewer.js`, 'utf8');
  const events = [...js.matchAll(/#emit\('(\w+)'|new CustomEvent\('(\w+)'/g)].map((m) => m[1] ?? m[2]);
  const eventMap = checker.getDeclaredTypeOfSymbol(declared('ClodViewerEventMap'));
  const eventNames = new Set(checker.getPropertiesOfType(eventMap).map((s) => s.name));
  assert.deepEqual([...new Set(events)].filter((e) => !eventNames.has(e)), []);
});
