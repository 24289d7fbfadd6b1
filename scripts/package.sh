#!/usr/bin/env bash
# Writes the npm package of the <clod-viewer> element: target/package/clod-viewer-VERSION.tgz, with
# the element and its worker, both wasm builds (www/pkg/, www/pkg-webgl/), the Draco module
# (www/pkg-draco/), the built-in character, the types and a README for authors (package/README.md).
# Builds the three wasm modules first (release, wasm-opt as wasm-pack.toml says); PACKAGE_BUILT=1
# packs the ones already built (scripts/browser-test.sh has just built them). Prints the tarball's path.
#   bash scripts/package.sh          then, in a site:  npm install /path/to/clod-viewer-VERSION.tgz
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/tools.sh"
cd "$root"
if [ "${PACKAGE_BUILT:-}" != 1 ]; then
  ensure_wasm_tools
  build_wasm web
  build_wasm webgl
  build_wasm draco
fi
node scripts/package.mjs
