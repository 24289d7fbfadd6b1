// What a wasm module spends its bytes on: the code of every function by crate (from the module's
// `name` section, which rustc's output keeps: target/pages/wasm32-unknown-unknown/release/
// clod_viewer.wasm, before wasm-bindgen and wasm-opt strip it), its data segments, and the largest
// functions. Sizes are raw bytes of function bodies; `gzip` is each crate's functions gzipped
// together (what they add to the download, roughly).
//   node scripts/wasm-profile.mjs FILE.wasm [--top N] [--json]
import { readFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';

const args = process.argv.slice(2);
const file = args.find((a) => !a.startsWith('--') && !/^\d+$/.test(a));
if (!file) {
  console.error('usage: node scripts/wasm-profile.mjs FILE.wasm [--top N] [--json]');
  process.exit(2);
}
const top = Number(args[args.indexOf('--top') + 1]) || 25;
const bytes = readFileSync(file);

let at = 8;
const leb = () => {
  let result = 0;
  let shift = 0;
  for (;;) {
    const b = bytes[at++];
    result += (b & 0x7f) * 2 ** shift;
    shift += 7;
    if (b < 0x80) return result;
  }
};
const name = () => {
  const n = leb();
  const s = bytes.toString('utf8', at, at + n);
  at += n;
  return s;
};

let imported = 0;
const bodies = []; // [start, end] of each defined function's body
const names = new Map();
let data = 0;
const sections = {};
while (at < bytes.length) {
  const id = bytes[at++];
  const size = leb();
  const end = at + size;
  const label = ['custom', 'type', 'import', 'function', 'table', 'memory', 'global', 'export', 'start', 'element', 'code', 'data', 'datacount'][id] ?? `id${id}`;
  if (id === 2) {
    for (let i = 0, n = leb(); i < n; i++) {
      name();
      name();
      const kind = bytes[at++];
      if (kind === 0) { leb(); imported++; } else if (kind === 1) { at++; const f = leb(); leb(); if (f & 1) leb(); } else if (kind === 2) { const f = leb(); leb(); if (f & 1) leb(); } else { at += 2; }
    }
  } else if (id === 10) {
    for (let i = 0, n = leb(); i < n; i++) {
      const len = leb();
      bodies.push([at, at + len]);
      at += len;
    }
  } else if (id === 11) {
    data = size;
  } else if (id === 0) {
    const section = name();
    sections[`custom ${section}`] = size;
    if (section === 'name') {
      while (at < end) {
        const sub = bytes[at++];
        const len = leb();
        const subEnd = at + len;
        if (sub === 1) for (let i = 0, n = leb(); i < n; i++) { const idx = leb(); names.set(idx, name()); }
        at = subEnd;
      }
    }
  }
  if (id !== 0) sections[label] = (sections[label] ?? 0) + size;
  at = end;
}

/**
 * A mangled Rust symbol as a path, roughly: legacy (`_ZN4core3fmt5write17h…E`) exactly, v0
 * (`_RNv…4core3num…`, the standard library's) by its identifiers; others unchanged.
 */
function demangle(symbol) {
  const legacy = symbol.match(/^_ZN(.*)E$/);
  if (!legacy && !symbol.startsWith('_R')) return symbol;
  const parts = [];
  if (legacy) {
    let s = legacy[1];
    while (s.length) {
      const len = s.match(/^\d+/);
      if (!len) break;
      s = s.slice(len[0].length);
      parts.push(s.slice(0, Number(len[0])));
      s = s.slice(Number(len[0]));
    }
  } else {
    // Each identifier is its length in decimal, then its characters (the crate's after `C`).
    for (let i = 2; i < symbol.length;) {
      const len = symbol.slice(i).match(/^[1-9]\d*/);
      const name = len && symbol.substr(i + len[0].length, Number(len[0]));
      if (name && name.length === Number(len[0]) && /^[a-z_][a-z0-9_]*$/.test(name)) {
        parts.push(name);
        i += len[0].length + name.length;
      } else {
        i++;
      }
    }
  }
  const codes = { SP: '@', BP: '*', RF: '&', LT: '<', GT: '>', LP: '(', RP: ')', C: ',' };
  return parts.map((p) => p.replace(/^_\$/, '$').replace(/\$([A-Z]{1,2})\$/g, (_, c) => codes[c] ?? c)
    .replace(/\$u([0-9a-f]+)\$/g, (_, h) => String.fromCodePoint(parseInt(h, 16))).replaceAll('..', '::'))
    .filter((p) => !/^h[0-9a-f]{16}$/.test(p)).join('::');
}

const STD = new Set(['core', 'alloc', 'std', 'compiler_builtins', 'dlmalloc']);

/**
 * The crate a function's code is counted under: the first crate its path names outside the
 * standard library (an impl's type, else its trait, else a generic argument: `drop_in_place<X>`
 * is X's), else the standard library.
 */
function crateOf(path) {
  const named = [...path.matchAll(/(?<![\w:])([a-z_][a-z0-9_]*)::/g)].map((m) => m[1]);
  if (!named.length) return /^(__|dl|mem[a-z]+$)/.test(path) ? '(compiler runtime)' : '(unnamed)';
  return named.find((c) => !STD.has(c)) ?? 'std (core, alloc)';
}

const crates = new Map();
const functions = [];
let descriptors = 0;
bodies.forEach(([start, end], i) => {
  const symbol = demangle(names.get(imported + i) ?? `function ${imported + i}`);
  // wasm-bindgen runs these to learn the types, then removes them from the module it writes.
  if (symbol.startsWith('__wbindgen_describe')) { descriptors += end - start; return; }
  const crate = names.size ? crateOf(symbol) : '(no name section)';
  const entry = crates.get(crate) ?? { crate, bytes: 0, functions: 0, chunks: [] };
  entry.bytes += end - start;
  entry.functions++;
  entry.chunks.push(bytes.subarray(start, end));
  crates.set(crate, entry);
  functions.push({ symbol, crate, bytes: end - start });
});
const rows = [...crates.values()].map((c) => ({ crate: c.crate, functions: c.functions, bytes: c.bytes, gzip: gzipSync(Buffer.concat(c.chunks), { level: 9 }).length }));
rows.sort((a, b) => b.bytes - a.bytes);
functions.sort((a, b) => b.bytes - a.bytes);
const code = rows.reduce((n, r) => n + r.bytes, 0);
const whole = bytes.length - descriptors;

if (args.includes('--json')) {
  console.log(JSON.stringify({ file, total: bytes.length, descriptors, sections, data, crates: rows, functions: functions.slice(0, top) }));
} else {
  const pct = (n) => `${((100 * n) / whole).toFixed(1)} %`;
  console.log(`${file}: ${bytes.length.toLocaleString('en-US')} bytes, of which ${descriptors.toLocaleString('en-US')} wasm-bindgen's type descriptors (removed by wasm-bindgen) and ${(sections['custom name'] ?? 0).toLocaleString('en-US')} names; of the rest (${whole.toLocaleString('en-US')}): code ${code.toLocaleString('en-US')} (${pct(code)}), data ${data.toLocaleString('en-US')} (${pct(data)})`);
  console.log('\n| crate | functions | code bytes | % of file | gzip alone |\n|---|---|---|---|---|');
  for (const r of rows.filter((r) => r.bytes >= 2048)) console.log(`| ${r.crate} | ${r.functions} | ${r.bytes.toLocaleString('en-US')} | ${pct(r.bytes)} | ${r.gzip.toLocaleString('en-US')} |`);
  const rest = rows.filter((r) => r.bytes < 2048);
  console.log(`| ${rest.length} others | ${rest.reduce((n, r) => n + r.functions, 0)} | ${rest.reduce((n, r) => n + r.bytes, 0).toLocaleString('en-US')} | | |`);
  console.log(`\n| largest functions | crate | bytes |\n|---|---|---|`);
  for (const f of functions.slice(0, top)) console.log(`| \`${f.symbol.slice(0, 110)}\` | ${f.crate} | ${f.bytes.toLocaleString('en-US')} |`);
}
