#!/usr/bin/env bash
# Installs what is missing, builds octarc, and runs the demo: a simulated survey field with
# injected strong lenses, detected at 15 thresholds in one pass and measured, with a report of
# the injected arcs that come back and their arcness. Extra arguments go to `octarc demo`.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release --target octarc -j "$(nproc)"
build/release/bin/octarc demo "$@"
