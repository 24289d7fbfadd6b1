// The test characters the generator makes that are not committed (too large, or made for the
// benchmark only): `hardsurface.glb` (61,974 triangles), `lowpoly-robot.glb` (658 KB) and
// `fingers.glb` (805 KB), see assets/README.md. `generated(name)` writes one into
// target/generated/ with the generator and returns its path; it runs the generator every time (about a second once it is built, so a file
// there is never stale) and moves the result into place in one step, so processes that ask at once
// never read a half-written file. The generator is the binary `cargo test --workspace` builds
// (target/debug/make-character) when that is newer than its sources and the library's, else
// `cargo run -p make-character`: that resolves the crates' features for the generator alone and
// rebuilds the library (minutes on 2 cores), which the test command, having just built the
// workspace's tests, need not pay.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readdirSync, renameSync, rmSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../', import.meta.url));
export const GENERATED_DIR = join(root, 'target', 'generated');

/** The newest modification time (ms) of the files under `dir`. */
function newest(dir) {
  return readdirSync(dir, { recursive: true }).reduce((t, f) => Math.max(t, statSync(join(dir, f)).mtimeMs), 0);
}

/** The command that runs the generator: `[program, args]`. */
function generator() {
  const built = join(root, 'target', 'debug', 'make-character');
  const sources = [join(root, 'tools', 'make-character', 'src'), join(root, 'src')];
  if (existsSync(built) && statSync(built).mtimeMs > Math.max(...sources.map(newest))) return [built, []];
  return ['cargo', ['run', '--quiet', '-p', 'make-character', '--']];
}

/** The generated characters the benchmarks measure by default, after the committed ones. */
export const GENERATED_NAMES = ['hardsurface.glb', 'lowpoly-robot.glb', 'fingers.glb'];

/**
 * The path of `target/generated/<name>`, made now by the generator; with `detail` (hardsurface.glb
 * only) `hardsurface-d<detail>.glb`, made with `--detail <detail>`.
 *
 * @throws {Error} when cargo or the generator fails (its messages are on stderr).
 */
export function generated(name, { detail } = {}) {
  const file = detail === undefined ? name : name.replace(/\.glb$/, `-d${detail}.glb`);
  mkdirSync(GENERATED_DIR, { recursive: true });
  const scratch = mkdtempSync(join(GENERATED_DIR, '.making-'));
  try {
    const [program, args] = generator();
    if (detail !== undefined) args.push('--detail', String(detail));
    execFileSync(program, [...args, join(scratch, file)], { cwd: root, stdio: ['ignore', 'ignore', 'inherit'] });
    renameSync(join(scratch, file), join(GENERATED_DIR, file));
  } finally {
    rmSync(scratch, { recursive: true, force: true });
  }
  return join(GENERATED_DIR, file);
}
