#!/usr/bin/env bash
# Installs what the build needs when it is missing, and does nothing when it is there.
# Sourced by serve.sh and test.sh. Versions come from wasm-pack.toml (the project's build manifest).
# Nothing here downloads a prebuilt binary: tools are compiled from crates.io, browsers come from apt.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
manifest() { node "$root/scripts/manifest.mjs" "$@"; }
export PATH="$HOME/.cargo/bin:$PATH"

ensure_rust_target() {
  local target; target="$(manifest tools.rust-target)"
  if ! rustup target list --installed | grep -qx "$target"; then
    echo "== installing Rust target $target"
    rustup target add "$target"
  fi
}

# Whether BINARY --version names VERSION.
has_tool() { "$1" --version 2>/dev/null | grep -q " $2\b"; }

ensure_wasm_tools() {
  ensure_rust_target
  local wb wp; wb="$(manifest tools.wasm-bindgen-cli)"; wp="$(manifest tools.wasm-pack)"
  # The CLI must match the library exactly, or generated bindings and the runtime disagree.
  if ! grep -A1 '^name = "wasm-bindgen"$' "$root/Cargo.lock" | grep -q "version = \"$wb\""; then
    echo "wasm-pack.toml pins wasm-bindgen-cli $wb but Cargo.lock has another wasm-bindgen:" >&2
    grep -A1 '^name = "wasm-bindgen"$' "$root/Cargo.lock" >&2
    exit 1
  fi
  # Both at once when both are missing: each build ends in a long single-threaded link, so two
  # side by side keep both cores busy (3.1 minutes one after the other on 2 cores).
  local installs=() crate bin version
  for tool in "wasm-bindgen-cli wasm-bindgen $wb" "wasm-pack wasm-pack $wp"; do
    read -r crate bin version <<<"$tool"
    has_tool "$bin" "$version" && continue
    echo "== installing $crate $version (cargo install --locked; a few minutes the first time)"
    local log; log="$(mktemp)"
    cargo install --locked --quiet "$crate" --version "=$version" >"$log" 2>&1 &
    installs+=("$!:$crate:$log")
  done
  local entry failed=0
  for entry in ${installs[@]+"${installs[@]}"}; do
    IFS=: read -r pid crate log <<<"$entry"
    if ! wait "$pid"; then
      echo "cargo install $crate failed:" >&2
      cat "$log" >&2
      failed=1
    fi
    rm -f "$log"
  done
  [ "$failed" = 0 ]
}

# Debian's Chromium for the browser tests (never a browser downloaded by a test tool).
ensure_chromium() {
  if ! command -v chromium >/dev/null 2>&1; then
    echo "== installing Debian's chromium and chromium-driver (apt)"
    local sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q chromium chromium-driver
  fi
}

ensure_npm_packages() {
  if [ -f "$root/package-lock.json" ] && ! (cd "$root" && npm ls --all >/dev/null 2>&1); then
    echo "== npm ci"
    (cd "$root" && npm ci --no-audit --no-fund)
  fi
}

# node_from_web: the JavaScript API for node (wasm-pack.toml [node]: out dir and name) made by
# wasm-bindgen from the WebGPU page's release wasm, which `build_wasm web` has just built. That wasm
# has the same API (`Character`, `Clod`) and the viewer's classes beside it, which node never
# calls, so the node tests need no third release build of the crate.
node_from_web() {
  wasm-bindgen --target nodejs \
    --out-dir "$root/$(manifest node.out-dir)" --out-name "$(manifest node.out-name)" \
    "$root/target/pages/$(manifest tools.rust-target)/release/clod_viewer.wasm"
}

# build_wasm SECTION: wasm-pack build of the crate (`crate`, default the root) with the target, out
# dir, features (`default-features = false` drops the crate's defaults) of wasm-pack.toml [SECTION],
# then wasm-opt at the section's level (`wasm-opt = "-Oz"`; false: none; the environment's WASM_OPT,
# when set, replaces it: WASM_OPT=false for a quick build, WASM_OPT=-O3 to compare levels).
# The release builds of the pages compile into target/pages/, a target directory of their own: they
# share no artifact with the dev and test builds, and with a directory of their own they build
# without waiting for cargo's lock on target/ (scripts/test.sh builds them beside the lints and
# tests).
build_wasm() {
  local section="$1"
  local crate; crate="$(manifest "$section.crate" .)"
  local out; out="$root/$(manifest "$section.out-dir")"
  local name; name="$(manifest "$section.out-name")"
  local defaults=()
  [ "$(manifest "$section.default-features" true)" = false ] && defaults=(--no-default-features)
  (cd "$root/$crate" && CARGO_TARGET_DIR="$root/target/pages" wasm-pack build --release --no-pack \
    --target "$(manifest "$section.target")" \
    --out-dir "$out" \
    --out-name "$name" \
    -- "${defaults[@]}" --features "$(manifest "$section.features")")
  local level; level="${WASM_OPT:-$(manifest "$section.wasm-opt" false)}"
  if [ "$level" != false ]; then
    optimize_wasm "$out/${name}_bg.wasm" "$level"
  fi
  if [ "$(manifest "$section.minify-js" false)" = true ]; then
    minify_js "$out/$name.js"
  fi
}

# minify_js FILE: terser from npm (package.json) on wasm-bindgen's JS glue, in place: names and
# whitespace only shrink; exports, the wasm's import names and `new URL('…_bg.wasm',
# import.meta.url)` stay as they are.
minify_js() {
  local file="$1"
  ensure_npm_packages
  "$root/node_modules/.bin/terser" --module --compress --mangle --output "$file.min" "$file"
  mv "$file.min" "$file"
}

# optimize_wasm FILE LEVEL: binaryen's wasm-opt from npm (package.json pins it; never a binary
# downloaded from elsewhere) on wasm-bindgen's output, in place, with the wasm features rustc
# uses (SIMD from .cargo/config.toml, reference types for wasm-bindgen's externref table, …).
optimize_wasm() {
  local file="$1" level="$2"
  ensure_npm_packages
  "$root/node_modules/.bin/wasm-opt" "$level" \
    --enable-simd --enable-reference-types --enable-bulk-memory --enable-nontrapping-float-to-int \
    --enable-sign-ext --enable-mutable-globals \
    "$file" -o "$file.opt"
  mv "$file.opt" "$file"
}
