#!/usr/bin/env bash
# Remakes docs/vetting-page.png, the README's picture of the vetting page: `octarc demo` (its
# field, lenses and search), the search's index.html opened in headless Chromium (as
# docs/CLIENTS.md runs it) with its stamps loaded, and saved as a 1400 x 1000 screenshot.
# Usage: scripts/vetting-page-screenshot.sh [path/to/octarc]
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=${1:-build/release/bin/octarc}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$octarc" demo --out "$work/demo" --quiet > /dev/null
page=$work/demo/candidates/index.html  # the demo's search output (OUTPUT_DIR)
chromium --headless=new --no-sandbox --disable-gpu --allow-file-access-from-files \
  --hide-scrollbars --virtual-time-budget=5000 --window-size=1400,1000 \
  --screenshot="$work/shot.png" "file://$page" 2> /dev/null
mv "$work/shot.png" docs/vetting-page.png
echo "docs/vetting-page.png: $page"
