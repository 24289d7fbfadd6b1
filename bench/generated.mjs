// The test characters the generator makes that are not committed (too large, or made for the
// benchmark only): `hardsurface.glb` (61,974 triangles) and `lowpoly-robot.glb` (658 KB), see
// assets/README.md. `generated(name)` writes one into target/generated/ with
// `cargo run -p make-character` and returns its path; it runs the generator every time (about a
// second once it is built, so a file there is never stale) and moves the result into place in one
// step, so processes that ask at once never read a half-written file.
import { execFileSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, renameSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../', import.meta.url));
export const GENERATED_DIR = join(root, 'target', 'generated');

/** The generated characters the benchmarks measure by default, after the committed ones. */
export const GENERATED_NAMES = ['hardsurface.glb', 'lowpoly-robot.glb'];

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
    const args = ['run', '--quiet', '-p', 'make-character', '--'];
    if (detail !== undefined) args.push('--detail', String(detail));
    execFileSync('cargo', [...args, join(scratch, file)], { cwd: root, stdio: ['ignore', 'ignore', 'inherit'] });
    renameSync(join(scratch, file), join(GENERATED_DIR, file));
  } finally {
    rmSync(scratch, { recursive: true, force: true });
  }
  return join(GENERATED_DIR, file);
}
