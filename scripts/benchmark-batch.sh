#!/usr/bin/env bash
# Times `octarc batch` over a survey of simulated tiles on this machine, as the README's batch
# benchmark reports it: one rank with one thread, one rank with every core, and two MPI ranks of
# one thread each (tiles per minute, parallel efficiency); and `octarc simulate lenses` on one
# and two ranks (the cost per simulated system). The tiles are made once in the work directory:
# TILES fields of SIZE^2 pixels from `octarc simulate field` (0.257"/px, 40 lenses each, seeds
# 1..TILES, 0.3 deg apart), each with its MAP_WEIGHT weight map.
# Usage: scripts/benchmark-batch.sh [WORKDIR] [TILES] [SIZE] [SYSTEMS]
set -euo pipefail
cd "$(dirname "$0")/.."
octarc=$PWD/build/release/bin/octarc
work=${1:-/tmp/octarc-benchmark-batch}
tiles=${2:-8}
size=${3:-4096}
systems=${4:-20000}
mkdir -p "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none

manifest=$work/survey.csv
if [ ! -f "$manifest" ]; then
  echo "image,weight" > "$manifest.part"
  for k in $(seq "$tiles"); do
    ra=$(/usr/bin/python3 -c "print(150 + 0.3 * $k)")
    "$octarc" simulate field -o "$work/tile$k.fits" --size "$size" --lenses 40 \
      --min-einstein-radius 1.5 --seed "$k" --ra "$ra" --quiet
    echo "tile$k.fits,tile$k.weight.fits" >> "$manifest.part"
  done
  mv "$manifest.part" "$manifest"
fi

config=(-c params/octarc.sex -GRID_NAME params/demo.grid.fits -WEIGHT_TYPE MAP_WEIGHT
        -VERBOSE_TYPE QUIET)
timed() {
  local label=$1
  shift
  rm -rf "$work/out"
  sync
  /usr/bin/time -f "$label: %e s wall, %U s user, %S s system, %M KiB peak (per process)" "$@"
}
timed "batch, 1 rank x 1 thread" \
  "$octarc" batch "$manifest" "${config[@]}" -NTHREADS 1 -OUTPUT_DIR "$work/out" > /dev/null
timed "batch, 1 rank x 2 threads" \
  "$octarc" batch "$manifest" "${config[@]}" -NTHREADS 2 -OUTPUT_DIR "$work/out" > /dev/null
timed "batch, 2 ranks x 1 thread" \
  mpirun --oversubscribe -np 2 "$octarc" batch "$manifest" "${config[@]}" -NTHREADS 1 \
  -OUTPUT_DIR "$work/out" > /dev/null
cut -f3- "$work/out/journal.txt"
timed "simulate lenses -n $systems --preset dls, 1 rank x 2 threads" \
  "$octarc" simulate lenses -n "$systems" --preset dls --seed 1 -o "$work/lenses1.fits" --quiet
timed "simulate lenses -n $systems --preset dls, 2 ranks x 1 thread" \
  mpirun --oversubscribe -np 2 "$octarc" simulate lenses -n "$systems" --preset dls --seed 1 \
  --threads 1 -o "$work/lenses2.fits" --quiet
cmp "$work/lenses1.fits" "$work/lenses2.fits" && echo "simulate lenses: the same file on 1 and 2 ranks"
