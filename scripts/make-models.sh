#!/usr/bin/env bash
# Rebuilds the lens model octarc ships for SELECTION_METHOD TREES:
#   params/demo.model.fits  gradient-boosted trees trained on the simulated arcs of the demo
#                           grid's two runs (550 000 importance-sampled `dls` systems each,
#                           seeds 11 and 12, the setup of `octarc demo`'s field) against the
#                           rows of a simulated 4096^2 field of that setup without lenses
#                           (`octarc demo --seed 1001 --lenses 0`, a seed no study uses), rows
#                           above S/N 40 and resolved, as the demo searches them.
# About 10 CPU-minutes (7 minutes on two cores). Usage: scripts/make-models.sh [path/to/octarc]
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=${1:-build/release/bin/octarc}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
outputs=()
for seed in 11 12; do
  "$octarc" simulate lenses -n 550000 --seed "$seed" --preset dls --sky-sigma 1.283 \
    -o "$work/demo-$seed.fits" --quiet &
  outputs+=("$work/demo-$seed.fits")
done
wait
"$octarc" demo --seed 1001 --size 4096 --lenses 0 --method GRID --out "$work/field" --quiet \
  > /dev/null
"$octarc" calibrate "${outputs[@]}" -SURVEY_CATALOG "$work/field/field.ldac" \
  -MODEL_NAME "$work/demo.model.fits" -GRID_NAME NONE -NOISE_STUDY N -CHECKPLOT_TYPE NONE \
  -CALIBRATION_NAME "$work/calibration.fits" > "$work/summary.txt"
grep -E "simulated systems|Lens model|WARNING" "$work/summary.txt" || true
mv "$work/demo.model.fits" params/demo.model.fits
