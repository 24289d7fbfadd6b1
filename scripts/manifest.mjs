// Reads one value from wasm-pack.toml, the project's build manifest: `node scripts/manifest.mjs web.out-dir`
// (`node scripts/manifest.mjs web.crate .` prints `.` when the key is absent).
// The manifest uses a small TOML subset (sections, `key = "string" | number | bool`, comments), which this parses.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

export function readManifest(path = join(dirname(fileURLToPath(import.meta.url)), '..', 'wasm-pack.toml')) {
  const out = {};
  let section = '';
  for (const [n, raw] of readFileSync(path, 'utf8').split('\n').entries()) {
    const line = raw.replace(/\s+#.*$/, '').replace(/^#.*$/, '').trim();
    if (!line) continue;
    const header = line.match(/^\[([\w.-]+)\]$/);
    if (header) { section = header[1]; continue; }
    const kv = line.match(/^([\w-]+)\s*=\s*(.+)$/);
    if (!kv) throw new Error(`wasm-pack.toml:${n + 1}: cannot read ${JSON.stringify(raw)}`);
    const [, key, value] = kv;
    out[section ? `${section}.${key}` : key] = JSON.parse(value);
  }
  return out;
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const manifest = readManifest();
  const [key, fallback] = process.argv.slice(2);
  if (!(key in manifest) && fallback !== undefined) {
    console.log(fallback);
    process.exit(0);
  }
  if (!(key in manifest)) {
    console.error(`wasm-pack.toml has no ${key}; keys: ${Object.keys(manifest).join(', ')}`);
    process.exit(2);
  }
  console.log(manifest[key]);
}
