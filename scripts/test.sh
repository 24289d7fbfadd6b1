#!/usr/bin/env bash
# Runs every test: formatting, the paths named in the docs, lints (native and wasm32), native tests,
# the same tests under node (wasm-pack test --node), the JavaScript API from node, and the viewer in
# headless Chromium. Installs missing tools first (Rust target, wasm-bindgen-cli, wasm-pack, npm
# packages, Debian chromium). Fails if any suite — or any test file within one — ran zero tests.
# Each step's time goes to target/test-logs/timings.txt (docs/testing.md).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/tools.sh"
cd "$root"

logs="$root/target/test-logs"
mkdir -p "$logs"
summary="$logs/summary.txt"
timings="$logs/timings.txt"
: > "$summary"
: > "$timings"
target="$(manifest tools.rust-target)"
# A fresh clone's build never reuses an incremental cache; not writing one saves its time.
export CARGO_INCREMENTAL=0

step_name=""
step_started=$SECONDS
step() {
  [ -n "$step_name" ] && printf '%5d s  %s\n' $((SECONDS - step_started)) "$step_name" >> "$timings"
  step_name="$*"
  step_started=$SECONDS
  echo
  echo "== $*"
}

# Debian's chromium is a download, not a build: apt fetches it while the CPUs compile.
chromium_log="$logs/chromium-install.log"
ensure_chromium > "$chromium_log" 2>&1 &
chromium_install=$!

step "tools: the wasm32 target, wasm-bindgen-cli and wasm-pack, npm packages"
ensure_wasm_tools
ensure_npm_packages

step "cargo fmt --check"
cargo fmt --all --check

step "paths named in docs and comments exist"
node scripts/check-paths.mjs

# The pages' release builds (target/pages/, see build_wasm) run in the background from here to the
# JavaScript API step, beside the lints and tests, one after the other: the WebGPU page, its wasm
# bound for node (before the WebGL2 page's build replaces it in target/pages/), the Draco module,
# the WebGL2 page. Each build ends in a long single-threaded stretch (the LTO of its last crate, one
# codegen unit, then wasm-opt), and the lints and tests leave a core idle now and then: measured on
# 2 cores, the steps before the browser's took 938 s, the machine 97 % busy, against 1,048 s and
# 84 % when the pages were built beside the node and JS-API tests alone.
build_pages() {
  build_wasm web && node_from_web && build_wasm draco && build_wasm webgl
}
build_pages > "$logs/pages-build.log" 2>&1 &
pages_build=$!

step "clippy (native, all targets; wasm32 library with the JS API, and with the renderer)"
cargo clippy --workspace --all-targets -- -D warnings
cargo clippy --lib --target "$target" --features "$(manifest node.features)" -- -D warnings
cargo clippy --lib --target "$target" --features "$(manifest webgl.features)" -- -D warnings

step "rustdoc: no broken or private intra-doc links (native core; wasm32 with the renderer)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib --quiet
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib --quiet --target "$target" --features "$(manifest webgl.features)"

step "the core builds without the JS layer (native and wasm32)"
cargo check --lib --no-default-features
cargo check --lib --no-default-features --target "$target"

# With the generator's check that assets/*.glb are byte for byte what it makes
# (tools/make-character/tests/committed_assets.rs).
step "native tests"
cargo test --workspace 2>&1 | tee "$logs/native.log"
node scripts/count-tests.mjs native "$logs/native.log" "$summary"

step "the same tests under node (wasm-pack test --node)"
CI="${CI:-}" wasm-pack test --node 2>&1 | tee "$logs/wasm-node.log"
node scripts/count-tests.mjs wasm-node "$logs/wasm-node.log" "$summary"

step "JavaScript API from node (the WebGPU page's release wasm, bound for node)"
# tests/js/draco.test.mjs hands the import the Draco module built with the page: the page's builds
# link no Draco decoder.
if ! wait "$pages_build"; then
  cat "$logs/pages-build.log" >&2
  exit 1
fi
node --test tests/js/ 2>&1 | tee "$logs/js-api.log"
node scripts/count-tests.mjs js-api "$logs/js-api.log" "$summary"

step "browser tests: the viewer in headless Chromium (WebGPU and WebGL2 on SwiftShader)"
if ! wait "$chromium_install"; then
  cat "$chromium_log" >&2
  exit 1
fi
# The three page builds are those started before the lints.
PAGES_BUILT=1 bash scripts/browser-test.sh 2>&1 | tee "$logs/browser.log"
node scripts/count-tests.mjs browser "$logs/browser.log" "$summary"

step "done"
echo
cat "$timings"
awk '{p += $2; f += $3} END {printf "total: %d passed, %d failed\n", p, f}' "$summary"
