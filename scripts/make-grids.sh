#!/usr/bin/env bash
# Rebuilds the occupation grids octarc ships, each from two importance-sampled runs of 550 000
# systems of the `dls` population (about 5 000 effective arcs together) through one survey setup
# (0.257"/px, 0.9" seeing, gain 54, 15 levels from 2.5 to 20 sigma), calibrated together on the
# axes ARCNESS, E_IMAGE and log10(SNR_ISO): with about 5 000 effective arcs the six default axes
# stay connected at P = 0.99 only with 2 bins per axis (64 bins, 56 selected), four axes with 4,
# these three with 7 (dls: 204 of 246 occupied bins selected; demo: 6, 139 of 171), the finest
# of the subsets tried:
#   params/demo.grid.fits  the setup of `octarc demo`'s field (`octarc simulate field` sets its sky
#                          noise, 1.283 ADU, from a 5-sigma limit of 26 mag in a 2 x FWHM
#                          aperture), seeds 11 and 12;
#   params/dls.grid.fits   the `octarc simulate lenses` defaults (26 mag in a 2" aperture: 1.154
#                          ADU), seeds 41 and 42: the grid for a DLS-like survey searched with
#                          octarc.sex (-GRID_NAME dls.grid.fits finds it in the share folder).
# About 25 CPU-minutes in all. Usage: scripts/make-grids.sh [path/to/octarc] [demo|dls]...
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=${1:-build/release/bin/octarc}
shift || true
grids=("$@")
[ ${#grids[@]} -gt 0 ] || grids=(demo dls)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for grid in "${grids[@]}"; do
  case $grid in
    demo) seeds=(11 12); noise=(--sky-sigma 1.283) ;;
    dls) seeds=(41 42); noise=() ;;
    *) echo "make-grids.sh: unknown grid $grid (demo or dls)" >&2; exit 2 ;;
  esac
  outputs=()
  for seed in "${seeds[@]}"; do
    "$octarc" simulate lenses -n 550000 --seed "$seed" --preset dls "${noise[@]}" \
      -o "$work/$grid-$seed.fits" --quiet
    outputs+=("$work/$grid-$seed.fits")
  done
  "$octarc" calibrate "${outputs[@]}" -GRID_AXES 'ARCNESS,E_IMAGE,log10(SNR_ISO)' \
    -NOISE_STUDY N -CHECKPLOT_TYPE NONE \
    -CALIBRATION_NAME "$work/calibration.fits" -GRID_NAME "$work/$grid.grid.fits" \
    > "$work/$grid-summary.txt"
  grep -E "simulated systems|Occupation grid|WARNING" "$work/$grid-summary.txt" || true
  mv "$work/$grid.grid.fits" "params/$grid.grid.fits"
done
