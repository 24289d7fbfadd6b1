#!/usr/bin/env bash
# Refreshes the README's picture, docs/page.png: builds the page and runs the browser suite's
# first-impression test alone (tests/browser/first-impression.test.mjs), which photographs the
# default page mid-transition on WebGPU (tests/browser/screenshot.mjs) and fails if a view is blank.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCREENSHOT_OUT="$root/docs/page.png" BROWSER_TESTS=tests/browser/first-impression.test.mjs bash "$root/scripts/browser-test.sh"
