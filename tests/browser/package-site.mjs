// A site that uses the npm package of the element as an author would: an empty folder where
// `npm install ./clod-viewer-VERSION.tgz` ran (offline: the package has no dependencies), with
// pages that load the element from node_modules/, served on 127.0.0.1 by a plain static server
// (.wasm as application/wasm; MODELS_DIR, when set, at /models/ as scripts/serve.mjs does).
// The tarball is CLOD_PACKAGE, else the newest target/package/clod-viewer-*.tgz
// (`bash scripts/package.sh`; scripts/browser-test.sh writes it before the tests).
import { execFileSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, readFileSync, readdirSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const repo = fileURLToPath(new URL('../../', import.meta.url));
const TYPES = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.wasm': 'application/wasm', '.glb': 'model/gltf-binary', '.json': 'application/json' };

/** The package tarball to test. */
export function packageTarball() {
  if (process.env.CLOD_PACKAGE) return resolve(process.env.CLOD_PACKAGE);
  const dir = join(repo, 'target/package');
  const found = (() => { try { return readdirSync(dir); } catch { return []; } })()
    .filter((f) => /^clod-viewer-.*\.tgz$/.test(f)).map((f) => join(dir, f))
    .sort((a, b) => statSync(b).mtimeMs - statSync(a).mtimeMs);
  if (!found.length) throw new Error('no target/package/clod-viewer-*.tgz: run bash scripts/package.sh (or set CLOD_PACKAGE)');
  return found[0];
}

/**
 * Installs the package into a fresh folder, writes `pages` (name → HTML) there and serves it.
 * Resolves to `{ url, dir, close() }`.
 */
export async function packageSite(pages) {
  const dir = mkdtempSync(join(tmpdir(), 'clod-site-'));
  const tarball = packageTarball();
  copyFileSync(tarball, join(dir, 'clod-viewer.tgz'));
  writeFileSync(join(dir, 'package.json'), '{ "name": "docs-site", "private": true }\n');
  execFileSync('npm', ['install', '--offline', '--no-audit', '--no-fund', './clod-viewer.tgz'], { cwd: dir, stdio: 'pipe' });
  for (const [name, html] of Object.entries(pages)) writeFileSync(join(dir, name), html);
  const mounts = [];
  if (process.env.MODELS_DIR) mounts.push(['/models/', resolve(process.env.MODELS_DIR)]);
  mounts.push(['/', dir]);
  const server = createServer((req, res) => {
    const pathname = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    const [prefix, root] = mounts.find(([p]) => pathname.startsWith(p));
    const path = normalize(join(root, pathname.slice(prefix.length)));
    if (path !== root && !path.startsWith(root + sep)) { res.writeHead(403).end(); return; }
    try {
      const body = readFileSync(path);
      res.writeHead(200, { 'content-type': TYPES[extname(path)] ?? 'application/octet-stream', 'cache-control': 'no-cache' }).end(body);
    } catch {
      res.writeHead(404).end('not found');
    }
  });
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  return {
    url: `http://127.0.0.1:${server.address().port}/`,
    dir,
    close: () => { server.close(); rmSync(dir, { recursive: true, force: true }); },
  };
}

/** A page of www/ (`page`) with its import of the element pointed at the installed package. */
export function pageFromWww(page) {
  const html = readFileSync(join(repo, 'www', page), 'utf8');
  const rewritten = html.replaceAll('src="clod-viewer.js"', 'src="node_modules/clod-viewer/clod-viewer.js"')
    .replaceAll("import './clod-viewer.js';", "import './node_modules/clod-viewer/clod-viewer.js';");
  if (rewritten === html) throw new Error(`www/${page} does not load clod-viewer.js as the tests expect`);
  return rewritten;
}
