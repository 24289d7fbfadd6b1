// www/clod-viewer.d.ts, the element's types for documentation pages: it must compile, a page's
// typical use must type-check against it (tests/js/types/viewer-usage.ts), and it must declare
// every name the viewer reports or takes (state(), setState, measurePopSpike, the element's
// members, attributes, events and exports), read here from their sources.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../../', import.meta.url));
const read = (path) => readFileSync(`${root}${path}`, 'utf8');
const dts = read('www/clod-viewer.d.ts');

/** The body of `interface name` or `class name` in the .d.ts (up to its closing brace at column 0). */
function block(kind, name) {
  const start = dts.indexOf(`${kind} ${name} `);
  assert.ok(start >= 0, `${kind} ${name} is missing`);
  return dts.slice(start, dts.indexOf('\n}', start));
}
const all = (text, re) => [...text.matchAll(re)].map((m) => m[1]);
const missing = (names, text, declared) => [...new Set(names)].filter((n) => !declared(n, text));
const property = (n, text) => new RegExp(`\\b${n}\\??:`).test(text);

test('the element types compile, and a docs page\'s use of them type-checks', () => {
  const tsc = `${root}node_modules/typescript/bin/tsc`;
  const args = ['--noEmit', '--strict', '--target', 'es2022', '--module', 'es2022', '--moduleResolution', 'bundler',
    '--lib', 'es2022,dom', 'www/clod-viewer.d.ts', 'tests/js/types/viewer-usage.ts'];
  try {
    execFileSync(process.execPath, [tsc, ...args], { cwd: root, encoding: 'utf8' });
  } catch (e) {
    assert.fail(`tsc: ${e.stdout}${e.stderr}`);
  }
});

test('every key of state() and every setState key is declared', () => {
  // The JSON keys src/web/state.rs writes (state(), its meter, crowd and views, meterHistory()).
  const stateKeys = all(read('src/web/state.rs'), /\\"([A-Za-z]+)\\":/g);
  assert.ok(stateKeys.length > 50, 'the keys were found');
  assert.deepEqual(missing(stateKeys, dts, property), []);
  // `KEYS`, the list `parse_update` accepts.
  const keysList = read('src/web/settings.rs').match(/const KEYS: \[&str; (\d+)\] = \[([^\]]*)\]/);
  const settingKeys = all(keysList[2], /"(\w+)"/g);
  assert.equal(settingKeys.length, Number(keysList[1]), 'the setState keys were found');
  assert.deepEqual(missing(settingKeys, block('interface', 'ViewerSettings'), property), []);
  const spikeKeys = all(read('src/web/pop_spike.rs'), /\\"([A-Za-z]+)\\":/g);
  assert.deepEqual(missing(spikeKeys, dts, property), []);
});

test('every public member, attribute, event and export of the element is declared', () => {
  const js = read('www/clod-viewer.js');
  const element = block('class', 'ClodViewerElement');
  const classBody = js.slice(js.indexOf('export class ClodViewerElement'));
  const lifecycle = ['connectedCallback', 'disconnectedCallback', 'attributeChangedCallback'];
  const methods = all(classBody, /^ {2}(?:async )?([a-zA-Z]\w*)\(/gm).filter((m) => !lifecycle.includes(m));
  assert.ok(methods.includes('setState') && methods.includes('load'), `methods found: ${methods}`);
  assert.deepEqual(missing(methods, element, (n, t) => new RegExp(`\\b${n}\\(`).test(t)), []);
  const getters = all(classBody, /^ {2}get ([a-zA-Z]\w*)\(/gm);
  assert.deepEqual(missing(getters, element, (n, t) => new RegExp(`readonly ${n}:`).test(t)), []);
  const attributes = JSON.parse(js.match(/observedAttributes = (\[[^\]]*\])/)[1].replaceAll("'", '"'));
  const tag = dts.match(/\/\*\* `<clod-viewer ([^>]*)>`/)[1].split(' ');
  assert.deepEqual(missing(attributes, tag, (n, t) => t.includes(n)), []);
  const events = [...all(js, /#emit\('(\w+)'/g), ...all(js, /new CustomEvent\('(\w+)'/g)];
  assert.deepEqual(missing(events, block('interface', 'ClodViewerEventMap'), property), []);
  const exports = all(js, /^export function (\w+)\(/gm);
  assert.deepEqual(missing(exports, dts, (n, t) => t.includes(`export function ${n}(`)), []);
});
