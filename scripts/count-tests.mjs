// Reads a `cargo test` / `wasm-pack test` / `node --test` log and checks that every test binary ran tests.
// Usage: node scripts/count-tests.mjs SUITE LOGFILE SUMMARYFILE
// Fails when the suite ran no test at all, or when one test binary (a file under tests/, or the unit tests)
// ran zero: `wasm-pack test --node` silently skips browser-only files and still says "ok".
// Doc-tests may be empty. Appends "SUITE passed failed" to SUMMARYFILE.
import { appendFileSync, readFileSync } from 'node:fs';

const [suite, logFile, summaryFile] = process.argv.slice(2);
const log = readFileSync(logFile, 'utf8');
let binary = null;
let passed = 0, failed = 0;
const empty = [];
for (const line of log.split('\n')) {
  const running = line.match(/^\s*(Running|Doc-tests)\s+(.*?)(\s+\(.*\))?$/);
  if (running) { binary = running[1] === 'Doc-tests' ? null : running[2]; continue; }
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
