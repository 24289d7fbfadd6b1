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

# The pages' release builds (target/pages/, see build_wasm) run beside the steps whose tests keep
# one core busy, and beside the LTO of their own last crate, which uses one.
# background_build SECTION: starts build_wasm SECTION, its output in
# target/test-logs/SECTION-build.log, its process id in $build_pid (for wait_build).
background_build() {
  build_wasm "$1" > "$logs/$1-build.log" 2>&1 &
  build_pid=$!
}
wait_build() {
  if ! wait "$1"; then
    cat "$logs/$2-build.log" >&2
    exit 1
  fi
}

step "the same tests under node (wasm-pack test --node), the WebGPU page built meanwhile"
background_build web
web_build=$build_pid
CI="${CI:-}" wasm-pack test --node 2>&1 | tee "$logs/wasm-node.log"
node scripts/count-tests.mjs wasm-node "$logs/wasm-node.log" "$summary"

step "JavaScript API from node (the WebGPU page's release wasm, bound for node), the WebGL2 page built meanwhile"
wait_build "$web_build" web
node_from_web
# The page's builds link no Draco decoder: tests/js/draco.test.mjs hands the import this module.
build_wasm draco
# The WebGL2 page builds for the browser step meanwhile: the node tests keep one core busy, and
# the build's last crate (LTO, one codegen unit) and its wasm-opt use one.
background_build webgl
webgl_build=$build_pid
node --test tests/js/ 2>&1 | tee "$logs/js-api.log"
node scripts/count-tests.mjs js-api "$logs/js-api.log" "$summary"
wait_build "$webgl_build" webgl

step "browser tests: the viewer in headless Chromium (WebGPU and WebGL2 on SwiftShader)"
if ! wait "$chromium_install"; then
  cat "$chromium_log" >&2
  exit 1
fi
# The three page builds are those of the step before.
PAGES_BUILT=1 bash scripts/browser-test.sh 2>&1 | tee "$logs/browser.log"
node scripts/count-tests.mjs browser "$logs/browser.log" "$summary"

step "done"
echo
cat "$timings"
awk '{p += $2; f += $3} END {printf "total: %d passed, %d failed\n", p, f}' "$summary"
