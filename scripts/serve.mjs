// Static file server on 127.0.0.1: www/ at /, the repository's assets/ at /assets/, and, when
// MODELS_DIR is set (the browser tests point it at ../shared/models), that folder at /models/.
// SITE_PREFIX (e.g. /docs/v1/) serves www/ and assets/ there too, as a docs site hosting the
// viewer under a path would (the tests check the element finds its files relative to itself).
// Honours PORT (0 picks a free port); prints the page's URL once it listens. Serves .wasm as
// application/wasm (needed for streaming compilation) and never leaves those folders.
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const repo = resolve(fileURLToPath(new URL('..', import.meta.url)));
const mounts = [['/assets/', join(repo, 'assets')]];
if (process.env.MODELS_DIR) mounts.push(['/models/', resolve(process.env.MODELS_DIR)]);
const prefix = process.env.SITE_PREFIX;
if (prefix) mounts.push([`${prefix}assets/`, join(repo, 'assets')], [prefix, join(repo, 'www')]);
mounts.push(['/', join(repo, 'www')]);
const port = Number(process.env.PORT ?? 8080);
const types = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8', '.wasm': 'application/wasm', '.json': 'application/json', '.glb': 'model/gltf-binary',
  '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream', '.png': 'image/png', '.jpg': 'image/jpeg', '.svg': 'image/svg+xml',
};

const server = createServer(async (req, res) => {
  try {
    const url = new URL(req.url, 'http://localhost');
    const pathname = decodeURIComponent(url.pathname);
    const [prefix, dir] = mounts.find(([p]) => pathname.startsWith(p));
    let path = normalize(join(dir, pathname.slice(prefix.length)));
    if (path !== dir && !path.startsWith(dir + sep)) { res.writeHead(403).end('forbidden'); return; }
    if ((await stat(path).catch(() => null))?.isDirectory()) path = join(path, 'index.html');
    const body = await readFile(path);
    res.writeHead(200, { 'content-type': types[extname(path)] ?? 'application/octet-stream', 'cache-control': 'no-cache' });
    res.end(body);
  } catch {
    res.writeHead(404, { 'content-type': 'text/plain' }).end('not found');
  }
});
server.listen(port, '127.0.0.1', () => console.log(`serving www/ at http://127.0.0.1:${server.address().port}/`));
