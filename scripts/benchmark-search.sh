#!/usr/bin/env bash
# Times `octarc search` on a 10000^2 simulated field (detection at 15 levels, measurement,
# selection with the shipped demo grid, candidates, stamps and the contact sheet), as the
# README's search benchmark reports it. The field is made once in the work directory.
# Usage: scripts/benchmark-search.sh [WORKDIR] [runs]
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=$PWD/build/release/bin/octarc
work=${1:-/tmp/octarc-benchmark-search}
runs=${2:-3}
mkdir -p "$work"
if [ ! -f "$work/field.fits" ]; then
  "$octarc" simulate field -o "$work/field.fits" --size 10000 --lenses 200 \
    --min-einstein-radius 1.5 --seed 1 --quiet
fi
for run in $(seq "$runs"); do
  sync
  /usr/bin/time -f "run $run: %e s wall, %U s user, %S s system, %M KiB peak" \
    "$octarc" search "$work/field.fits" -c params/octarc.sex -GRID_NAME params/demo.grid.fits \
    -WEIGHT_TYPE MAP_WEIGHT -WEIGHT_IMAGE "$work/field.weight.fits" \
    -OUTPUT_DIR "$work/candidates" -VERBOSE_TYPE QUIET > "$work/summary.txt"
done
cat "$work/summary.txt"
