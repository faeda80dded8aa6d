#!/usr/bin/env bash
# Rebuilds params/demo.grid.fits, the occupation grid `octarc demo` searches with: 40 000
# simulated lenses of the `dls` population (the one `simulate field` injects) through the
# survey setup of the demo's field (`octarc simulate field` defaults: 0.257"/px, 0.9" seeing,
# gain 54, 15 levels from 2.5 to 20 sigma, and its sky noise of 1.283 ADU: the field sets the
# noise from a 5-sigma limit of 26 mag in a 2 x FWHM aperture, `simulate lenses` from a 2" one),
# from the fixed seed 11, and a
# 3-D grid over ARCNESS, E_IMAGE and log10(SNR_ISO) (some hundred arcs fill six axes too thinly).
# About 3 minutes on 2 cores. Usage: scripts/make-demo-grid.sh [path/to/octarc]
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=${1:-build/release/bin/octarc}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$octarc" simulate lenses -n 40000 --seed 11 --preset dls --sky-sigma 1.283 \
  -o "$work/sim.fits" --quiet
"$octarc" calibrate "$work/sim.fits" -GRID_AXES 'ARCNESS,E_IMAGE,log10(SNR_ISO)' \
  -NOISE_STUDY N -CHECKPLOT_TYPE NONE -CALIBRATION_NAME "$work/calibration.fits" \
  -GRID_NAME "$work/demo.grid.fits" > "$work/summary.txt"
grep "Occupation grid" "$work/summary.txt"
mv "$work/demo.grid.fits" params/demo.grid.fits
