// Fails when a repository path named in the docs or in a source comment does not exist.
//
// Markdown is read whole (README.md, docs/*.md, bench/README.md, assets/README.md and any
// README.md under tools/; not the dated runs under bench/, which stay as they were written); source
// files only in their comments (src/, tests/, www/, scripts/, bench/*.mjs, examples/, tools/,
// build.rs, Cargo.toml, wasm-pack.toml, .ci/). A repository path is a token that starts with a
// top-level folder of the repository (`src/`, `docs/`, `.ci/`, …) or is a top-level file name
// (`Cargo.toml`, `README.md`, …); trailing punctuation, `#anchor`, `:line` and `::item` suffixes
// are dropped; `*`, `**` and `?` match files and `{a,b}` expands. A Markdown link target
// (`[x](../README.md)`) resolves against the Markdown file's folder. A Markdown file may be named
// without its extension (`bench/README`). Built or outside paths (`target/`, `node_modules/`,
// `www/pkg*`, `../shared/`) are not checked.
//
// Usage: node scripts/check-paths.mjs          exit 1 listing file:line and the path of each miss
//        node scripts/check-paths.mjs --list   also print every path checked

import { existsSync, readdirSync, readFileSync, statSync } from 'node:fs';
import { dirname, join, posix, relative, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');

/** Never walked: git's own folder, and what builds and installs write. */
const SKIP_DIRS = new Set(['.git', 'target', 'node_modules']);
/** Paths that name built output (or a folder outside the repository), never checked. */
const NOT_CHECKED = [/^target\//, /^node_modules\//, /^www\/pkg/, /^pkg\//, /^tests\/js\/out\//, /^\.\.\//];
/** Paths in other repositories that comments name, with the repository (not checked). */
const ELSEWHERE = new Map([['src/simplifier.cpp', 'meshoptimizer']]);

/** Every file and folder under the repository, as `/`-separated relative paths. */
function walk(dir = root, out = { files: [], dirs: [] }) {
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    if (SKIP_DIRS.has(entry.name)) continue;
    const path = join(dir, entry.name);
    const rel = relative(root, path).split(sep).join('/');
    if (entry.isDirectory()) {
      out.dirs.push(rel);
      walk(path, out);
    } else {
      out.files.push(rel);
    }
  }
  return out;
}

const tree = walk();
const topDirs = readdirSync(root, { withFileTypes: true })
  .filter((e) => e.isDirectory() && !SKIP_DIRS.has(e.name))
  .map((e) => e.name);
const topFiles = new Set(
  readdirSync(root, { withFileTypes: true })
    .filter((e) => e.isFile())
    .map((e) => e.name),
);

/** `{a,b}` brace sets expanded (nested sets too). */
function expandBraces(pattern) {
  const open = pattern.indexOf('{');
  if (open < 0) return [pattern];
  let depth = 0;
  for (let i = open; i < pattern.length; i++) {
    if (pattern[i] === '{') depth++;
    else if (pattern[i] === '}' && --depth === 0) {
      const parts = [];
      let start = open + 1;
      let d = 0;
      for (let j = open + 1; j < i; j++) {
        if (pattern[j] === '{') d++;
        else if (pattern[j] === '}') d--;
        else if (pattern[j] === ',' && d === 0) {
          parts.push(pattern.slice(start, j));
          start = j + 1;
        }
      }
      parts.push(pattern.slice(start, i));
      return parts.flatMap((p) => expandBraces(pattern.slice(0, open) + p + pattern.slice(i + 1)));
    }
  }
  return [pattern]; // an unclosed brace: taken literally
}

function globRegex(glob) {
  let re = '';
  for (let i = 0; i < glob.length; i++) {
    const c = glob[i];
    if (c === '*' && glob[i + 1] === '*') {
      re += glob[i + 2] === '/' ? '(?:.*/)?' : '.*';
      i += glob[i + 2] === '/' ? 2 : 1;
    } else if (c === '*') re += '[^/]*';
    else if (c === '?') re += '[^/]';
    else re += c.replace(/[.+^${}()|[\]\\]/g, '\\$&');
  }
  return new RegExp(`^${re}$`);
}

/** Whether `path` (relative to the root, `/`-separated) names something in the repository. */
function exists(path) {
  if (ELSEWHERE.has(path) || NOT_CHECKED.some((re) => re.test(path))) return true;
  return expandBraces(path).every((one) => {
    const isDir = one.endsWith('/');
    const bare = one.replace(/\/+$/, '');
    if (/[*?]/.test(bare)) {
      const re = globRegex(bare);
      return (isDir ? tree.dirs : [...tree.files, ...tree.dirs]).some((p) => re.test(p));
    }
    const full = join(root, bare);
    if (!existsSync(full)) return !isDir && !posix.extname(bare) && existsSync(`${full}.md`);
    return !isDir || statSync(full).isDirectory();
  });
}

const PATH_CHAR = /[A-Za-z0-9_\-./*?{},~+@]/;
const BEFORE_TOKEN = /[A-Za-z0-9_\-./~@$]/;

/** The repository paths a piece of text names, each with its column. */
function pathTokens(text) {
  const found = [];
  for (let i = 0; i < text.length; i++) {
    if (i > 0 && BEFORE_TOKEN.test(text[i - 1])) continue;
    if (!PATH_CHAR.test(text[i])) continue;
    // The longest run of path characters (a comma only inside braces).
    let end = i;
    let depth = 0;
    while (end < text.length && PATH_CHAR.test(text[end])) {
      if (text[end] === '{') depth++;
      else if (text[end] === '}') depth--;
      else if (text[end] === ',' && depth <= 0) break;
      end++;
    }
    let token = text.slice(i, end);
    const skipTo = end;
    // Trailing punctuation is prose, and so is a closing brace that closes no set.
    for (;;) {
      const last = token.slice(-1);
      const unbalanced = (token.match(/\}/g) || []).length > (token.match(/\{/g) || []).length;
      if (/[.,;:!?'")\]>…]/u.test(last) || (last === '}' && unbalanced)) token = token.slice(0, -1);
      else break;
    }
    const top = token.split('/')[0];
    const isRepoPath =
      (token.includes('/') && topDirs.includes(top)) || (!token.includes('/') && topFiles.has(token));
    if (isRepoPath) found.push({ path: token, column: i });
    i = Math.max(i, skipTo - 1);
  }
  return found;
}

/** Markdown link targets (`[text](target)`, images too), with the rest of the line blanked. */
function markdownLinks(line) {
  const links = [];
  const rest = line.replace(/\]\(([^)\s]+)(?:\s+"[^"]*")?\)/g, (match, target) => {
    links.push(target);
    return ' '.repeat(match.length);
  });
  return { links, rest };
}

/** Comment text of each line of a source file, by the file's comment syntax. */
function commentLines(file, text) {
  const lines = text.split('\n');
  const ext = posix.extname(file);
  if (['.rs', '.wgsl', '.js', '.mjs', '.ts'].includes(ext)) return slashComments(lines, ext);
  if (ext === '.html') return htmlComments(lines);
  return hashComments(lines); // shell scripts, TOML
}

function slashComments(lines, ext) {
  const quotes = ext === '.rs' || ext === '.wgsl' ? '"' : `"'\``;
  let inBlock = false;
  return lines.map((line) => {
    let comment = '';
    let quote = null;
    for (let i = 0; i < line.length; i++) {
      const c = line[i];
      if (inBlock) {
        if (c === '*' && line[i + 1] === '/') {
          inBlock = false;
          comment += ' ';
          i++;
        } else comment += c;
      } else if (quote) {
        if (c === '\\') i++;
        else if (c === quote) quote = null;
      } else if (quotes.includes(c)) quote = c;
      else if (c === '/' && line[i + 1] === '/') {
        comment += ' ' + line.slice(i + 2);
        break;
      } else if (c === '/' && line[i + 1] === '*') {
        inBlock = true;
        i++;
      }
    }
    return comment;
  });
}

function hashComments(lines) {
  return lines.map((line) => {
    let quote = null;
    for (let i = 0; i < line.length; i++) {
      const c = line[i];
      if (quote) {
        if (c === '\\' && quote === '"') i++;
        else if (c === quote) quote = null;
      } else if (c === '"' || c === "'") quote = c;
      else if (c === '#' && (i === 0 || /\s/.test(line[i - 1]))) return line.slice(i + 1);
    }
    return '';
  });
}

function htmlComments(lines) {
  let inComment = false;
  let inScript = false;
  const script = [];
  const out = lines.map((line, n) => {
    let comment = '';
    let rest = line;
    while (rest.length > 0) {
      if (inComment) {
        const close = rest.indexOf('-->');
        comment += ' ' + (close < 0 ? rest : rest.slice(0, close));
        if (close < 0) break;
        inComment = false;
        rest = rest.slice(close + 3);
      } else {
        const open = rest.indexOf('<!--');
        if (open < 0) break;
        inComment = true;
        rest = rest.slice(open + 4);
      }
    }
    if (/<\/script>/i.test(line)) inScript = false;
    if (inScript) script.push(n);
    if (/<script\b[^>]*>(?!.*<\/script>)/i.test(line)) inScript = true;
    return comment;
  });
  const js = slashComments(
    script.map((n) => lines[n]),
    '.js',
  );
  script.forEach((n, k) => (out[n] += ' ' + js[k]));
  return out;
}

const MARKDOWN = [/^README\.md$/, /^docs\/[^/]+\.md$/, /^bench\/README\.md$/, /^assets\/README\.md$/, /^tools\/.+\/README\.md$/];
const SOURCES = [
  /^src\/.+\.(rs|wgsl)$/,
  /^tests\/.+\.(rs|mjs|ts)$/,
  /^www\/[^/]+\.(js|ts|html)$/,
  /^scripts\/[^/]+$/,
  /^bench\/[^/]+\.mjs$/,
  /^examples\/[^/]+\.rs$/,
  /^tools\/.+\.rs$/,
  /^tools\/[^/]+\/Cargo\.toml$/,
  /^\.ci\/[^/]+$/,
  /^(build\.rs|Cargo\.toml|wasm-pack\.toml)$/,
];

const list = process.argv.includes('--list');
const misses = [];
let checked = 0;
/** Counts and checks one named path. */
function check(file, n, shown, path) {
  checked++;
  const ok = exists(path);
  if (list) console.log(`${ok ? 'ok  ' : 'MISS'} ${file}:${n + 1}: ${shown}`);
  if (!ok) misses.push(`${file}:${n + 1}: ${shown}`);
}
for (const file of tree.files.sort()) {
  const markdown = MARKDOWN.some((re) => re.test(file));
  if (!markdown && !SOURCES.some((re) => re.test(file))) continue;
  const text = readFileSync(join(root, file), 'utf8');
  const lines = markdown ? text.split('\n') : commentLines(file, text);
  lines.forEach((line, n) => {
    let rest = line;
    if (markdown) {
      const split = markdownLinks(line);
      rest = split.rest;
      for (const target of split.links) {
        if (/^([a-z][a-z0-9+.-]*:|#|\/)/i.test(target)) continue; // URLs, anchors, site paths
        const path = posix.normalize(posix.join(posix.dirname(file), target.replace(/[#?].*$/, '')));
        check(file, n, target, path);
      }
    }
    for (const { path } of pathTokens(rest)) {
      check(file, n, path, path);
    }
  });
}

if (misses.length > 0) {
  console.error(`${misses.length} of ${checked} paths named in docs and comments do not exist:`);
  for (const miss of misses) console.error(`  ${miss}`);
  process.exit(1);
}
console.log(`${checked} paths named in docs and comments exist`);
