#!/usr/bin/env bash
# Benchmark of `octarc simulate lenses` (issue 4, acceptance 3): N systems (default 90 000)
# rendered, detected at 15 levels and measured, on every core. Prints the wall time, the CPU
# time and the CPU cost of each stage per system. A benchmark, not a test: the figure depends
# on the machine and on what else runs on it.
#
# Usage: scripts/benchmark-simulate.sh [N] [extra options for octarc simulate lenses]
# The octarc binary is $OCTARC_BIN, else build/release/bin/octarc (built if missing).
set -euo pipefail
cd "$(dirname "$0")/.."

count=${1:-90000}
shift || true
bin=${OCTARC_BIN:-build/release/bin/octarc}
if [[ ! -x "$bin" ]]; then
  cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build/release --target octarc
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "octarc simulate lenses -n $count, 15 levels (DETECT_THRESH 2.5 to 20 sigma), $(nproc) cores"
/usr/bin/time -f '%e %U %S %M' -o "$work/time" \
  "$bin" simulate lenses -n "$count" --seed 1 -o "$work/lenses.fits" --nlevels 15 \
  --quiet --timing "$@" 2>"$work/log" || { cat "$work/log" "$work/time"; exit 1; }
read -r wall user sys rss <"$work/time"
cat "$work/log"
echo "wall ${wall} s, CPU ${user} s user + ${sys} s system, peak memory $((rss / 1024)) MiB"
awk -v n="$count" -v w="$wall" 'BEGIN { printf "throughput %.0f systems/s, %.2f ms wall per system\n", n / w, 1000 * w / n }'
