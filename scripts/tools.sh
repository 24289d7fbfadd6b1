#!/usr/bin/env bash
# Installs what the build needs when it is missing, and does nothing when it is there.
# Sourced by serve.sh and test.sh. Versions come from wasm-pack.toml (the project's build manifest).
# Nothing here downloads a prebuilt binary: tools are compiled from crates.io, browsers come from apt.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
manifest() { node "$root/scripts/manifest.mjs" "$1"; }
export PATH="$HOME/.cargo/bin:$PATH"

ensure_rust_target() {
  local target; target="$(manifest tools.rust-target)"
  if ! rustup target list --installed | grep -qx "$target"; then
    echo "== installing Rust target $target"
    rustup target add "$target"
  fi
}

ensure_cargo_tool() { # ensure_cargo_tool CRATE BINARY VERSION
  local crate="$1" bin="$2" version="$3"
  if ! "$bin" --version 2>/dev/null | grep -q " $version\b"; then
    echo "== installing $crate $version (cargo install --locked; a few minutes the first time)"
    cargo install --locked "$crate" --version "=$version"
  fi
}

ensure_wasm_tools() {
  ensure_rust_target
  local wb; wb="$(manifest tools.wasm-bindgen-cli)"
  # The CLI must match the library exactly, or generated bindings and the runtime disagree.
  if ! grep -A1 '^name = "wasm-bindgen"$' "$root/Cargo.lock" | grep -q "version = \"$wb\""; then
    echo "wasm-pack.toml pins wasm-bindgen-cli $wb but Cargo.lock has another wasm-bindgen:" >&2
    grep -A1 '^name = "wasm-bindgen"$' "$root/Cargo.lock" >&2
    exit 1
  fi
  ensure_cargo_tool wasm-bindgen-cli wasm-bindgen "$wb"
  ensure_cargo_tool wasm-pack wasm-pack "$(manifest tools.wasm-pack)"
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

# build_wasm SECTION: wasm-pack build with the target, out dir and features of wasm-pack.toml [SECTION].
build_wasm() {
  local section="$1"
  (cd "$root" && wasm-pack build --release --no-pack \
    --target "$(manifest "$section.target")" \
    --out-dir "$root/$(manifest "$section.out-dir")" \
    --out-name "$(manifest "$section.out-name")" \
    -- --features "$(manifest "$section.features")")
}
