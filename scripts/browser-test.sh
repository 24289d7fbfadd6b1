#!/usr/bin/env bash
# Browser tests of the viewer page: builds both wasm builds (WebGPU and the WebGL2 fallback), serves
# the page on a free port (with ../shared/models at /models/), runs tests/browser/*.test.mjs in
# headless Debian Chromium (SwiftShader for WebGPU and WebGL2) and stops the server.
# CHROMIUM overrides the browser path (default /usr/bin/chromium, from apt: never downloaded).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/tools.sh"
cd "$root"
ensure_wasm_tools
ensure_npm_packages
chromium="${CHROMIUM:-/usr/bin/chromium}"
if ! "$chromium" --version >/dev/null 2>&1; then
  echo "no Chromium at $chromium: apt-get install chromium (or set CHROMIUM)" >&2
  exit 1
fi

# PAGES_BUILT=1 (scripts/test.sh, which has just built them): use www/pkg*/ as they are.
if [ "${PAGES_BUILT:-}" != 1 ]; then
  build_wasm web
  build_wasm webgl
  build_wasm draco
fi
node scripts/page-size.mjs
# The npm package of what was just built, for tests/browser/package.test.mjs and embed.test.mjs.
PACKAGE_BUILT=1 bash scripts/package.sh >/dev/null

log="$(mktemp)"
export MODELS_DIR="$root/../shared/models"
SITE_PREFIX=/docs/v1/ PORT=0 node scripts/serve.mjs >"$log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true; rm -f "$log"' EXIT
for _ in $(seq 100); do
  url="$(grep -o 'http://[0-9.:]*/' "$log" || true)"
  [ -n "$url" ] && break
  sleep 0.1
done
if [ -z "$url" ]; then
  echo "the server did not start:" >&2
  cat "$log" >&2
  exit 1
fi
# The suites the test command runs: views (with the continuous LOD, overlay and camera tests),
# fairness, pop-spike (measured by the viewer itself, on a small page), webgl2, the page for readers
# (files, URL state, progress, long tasks), embedding (<clod-viewer>, embed.html; from www/ and from the npm
# package), the package installed into an empty site, the element's error events, the crowd, morph targets,
# the default page's first impression (which takes the README's screenshot), FLIP against its reference's fixtures.
# frame-times only reports numbers and takes minutes on SwiftShader: `BROWSER_TESTS=all` runs every
# file; `BROWSER_TESTS="tests/browser/embed.test.mjs tests/browser/morph.test.mjs"` runs those (paths).
if [ "${BROWSER_TESTS:-}" = all ]; then
  files=(tests/browser/)
elif [ -n "${BROWSER_TESTS:-}" ]; then
  read -r -a files <<< "$BROWSER_TESTS"
else
  files=(tests/browser/views.test.mjs tests/browser/fairness.test.mjs tests/browser/pop-spike.test.mjs
    tests/browser/webgl2.test.mjs tests/browser/page.test.mjs tests/browser/embed.test.mjs tests/browser/package.test.mjs
    tests/browser/errors.test.mjs tests/browser/meter.test.mjs tests/browser/crowd.test.mjs
    tests/browser/morph.test.mjs tests/browser/first-impression.test.mjs tests/browser/flip.test.mjs)
fi
echo "== browser tests against $url: ${files[*]}"
# One file at a time: SwiftShader already uses every core.
CLOD_URL="$url" CHROMIUM="$chromium" node --test --test-concurrency=1 "${files[@]}"
