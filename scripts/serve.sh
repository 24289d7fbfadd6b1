#!/usr/bin/env bash
# Builds the wasm for the page (WebGPU, WebGL2, and the Draco decoder's module) and serves www/ on
# http://127.0.0.1:$PORT (default 8080).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/tools.sh"
ensure_wasm_tools
build_wasm web
build_wasm webgl
build_wasm draco
node "$root/scripts/page-size.mjs"
exec node "$root/scripts/serve.mjs"
