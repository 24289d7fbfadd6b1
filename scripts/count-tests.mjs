// Reads a `cargo test` / `wasm-pack test` / `node --test` log and checks that every test binary ran tests.
// Usage: node scripts/count-tests.mjs SUITE LOGFILE SUMMARYFILE
// Fails when the suite ran no test at all, when one test binary (the unit tests, or a file under tests/ that
// is a binary of its own) ran zero, or when one file of the integration tests' binary (a module of
// tests/integration.rs) ran zero: `wasm-pack test --node` silently skips browser-only files and still says
// "ok". Doc-tests may be empty. Appends "SUITE passed failed" to SUMMARYFILE.
import { appendFileSync, readFileSync } from 'node:fs';

const [suite, logFile, summaryFile] = process.argv.slice(2);
const log = readFileSync(logFile, 'utf8');
// The modules of the integration tests' binary, one a file (tests/integration.rs), and the tests each ran.
const INTEGRATION = 'tests/integration.rs';
const modules = new Map(readFileSync(new URL(`../${INTEGRATION}`, import.meta.url), 'utf8')
  .split('\n').flatMap((l) => l.match(/^mod (\w+);/)?.slice(1) ?? [])
  .filter((m) => m !== 'common' && m !== 'meshgen').map((m) => [m, 0]));
let binary = null;
let passed = 0, failed = 0;
const empty = [];
for (const line of log.split('\n')) {
  const running = line.match(/^\s*(Running|Doc-tests)\s+(.*?)(\s+\(.*\))?$/);
  if (running) { binary = running[1] === 'Doc-tests' ? null : running[2]; continue; }
  const ran = binary === INTEGRATION && line.match(/^test (\w+)::\S+ \.\.\. (ok|FAILED)/);
  if (ran && modules.has(ran[1])) modules.set(ran[1], modules.get(ran[1]) + 1);
  const result = line.match(/^test result: \w+\. (\d+) passed; (\d+) failed/);
  if (result) {
    const [p, f] = [Number(result[1]), Number(result[2])];
    passed += p; failed += f;
    if (binary && p + f === 0) empty.push(binary);
    binary = null;
    continue;
  }
  const node = line.match(/^# (pass|fail) (\d+)$/); // node --test's closing summary
  if (node) node[1] === 'pass' ? (passed += Number(node[2])) : (failed += Number(node[2]));
}
if (log.includes(`Running ${INTEGRATION}`)) {
  for (const [module, count] of modules) if (count === 0) empty.push(`${INTEGRATION}: ${module}`);
}
appendFileSync(summaryFile, `${suite} ${passed} ${failed}\n`);
console.log(`== ${suite}: ${passed} passed, ${failed} failed`);
if (empty.length) {
  console.error(`== ${suite}: these test binaries ran no test: ${empty.join(', ')}`);
  process.exit(1);
}
if (passed + failed === 0) {
  console.error(`== ${suite}: no test ran`);
  process.exit(1);
}
