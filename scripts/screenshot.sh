#!/usr/bin/env bash
# Refreshes the README's picture, docs/page.png: builds the page and runs the browser suite's
# screenshot test alone (tests/browser/screenshot.test.mjs), which photographs the default page
# mid-transition on WebGPU and fails if any view is blank.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCREENSHOT_OUT="$root/docs/page.png" BROWSER_TESTS=tests/browser/screenshot.test.mjs bash "$root/scripts/browser-test.sh"
