#!/usr/bin/env bash
# The worked example and benchmark of `octarc batch -TASK MEASURE` in the README: a field from
# `octarc simulate field` (SIZE^2 pixels, 40 lenses) cut into TILES tiles (two rows of TILES/2),
# each run through source-extractor for its SEGMENTATION check-image and FITS-LDAC catalog, then
# the batch appending octarc's columns to every catalog, on one rank and on two MPI ranks (one
# thread each), timed with /usr/bin/time. The tiles are made once in the work directory.
# Usage: scripts/benchmark-batch-measure.sh [WORKDIR] [TILES] [SIZE]
set -euo pipefail
cd "$(dirname "$0")/.."
source=$PWD
octarc=${OCTARC:-$PWD/build/release/bin/octarc}
work=${1:-/tmp/octarc-benchmark-batch-measure}
tiles=${2:-8}
size=${3:-4096}
mkdir -p "$work"
cd "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none HWLOC_COMPONENTS=-gl

if [ ! -f tiles.csv ]; then
  # 1. A field, and tiles cut from it (astropy keeps each tile's WCS).
  "$octarc" simulate field -o field.fits --size "$size" --lenses 40 --seed 1 --quiet
  /usr/bin/python3 - "$tiles" "$size" <<'PY'
import sys
from astropy.io import fits
tiles, size = int(sys.argv[1]), int(sys.argv[2])
columns = tiles // 2
width, height = size // columns, size // 2
with fits.open("field.fits") as f:
    data, header = f[0].data, f[0].header
    for k in range(tiles):
        x0, y0 = (k % columns) * width, (k // columns) * height
        h = header.copy()
        h["CRPIX1"] -= x0
        h["CRPIX2"] -= y0
        fits.PrimaryHDU(data[y0:y0 + height, x0:x0 + width], h).writeto("tile%d.fits" % (k + 1))
PY
  # 2. source-extractor on each tile: its catalog and SEGMENTATION check-image.
  printf 'NUMBER\nX_IMAGE\nY_IMAGE\nFLUX_ISO\nMAG_AUTO\nFLUX_RADIUS\nFLAGS\n' > sex.param
  echo "image,segmentation,catalog" > tiles.csv.part
  for k in $(seq "$tiles"); do
    source-extractor "tile$k.fits" -c /usr/share/source-extractor/default.sex \
      -PARAMETERS_NAME sex.param -FILTER_NAME /usr/share/source-extractor/default.conv \
      -CATALOG_TYPE FITS_LDAC -CATALOG_NAME "tile$k.ldac" -DETECT_THRESH 3 -ANALYSIS_THRESH 3 \
      -CHECKIMAGE_TYPE SEGMENTATION -CHECKIMAGE_NAME "tile$k.seg.fits" -VERBOSE_TYPE QUIET
    echo "tile$k.fits,tile$k.seg.fits,tile$k.ldac" >> tiles.csv.part
  done
  mv tiles.csv.part tiles.csv
fi

# 3. The batch: each catalog with octarc's columns (params/octarc.param) appended.
config=(-TASK MEASURE -c /usr/share/source-extractor/default.sex
        -PARAMETERS_NAME "$source/params/octarc.param" -NTHREADS 1 -VERBOSE_TYPE QUIET)
timed() {
  local label=$1
  shift
  rm -rf out
  sync
  /usr/bin/time -f "$label: %e s wall, %U s user, %S s system, %M KiB peak (per process)" "$@"
}
timed "batch -TASK MEASURE, 1 rank x 1 thread" \
  "$octarc" batch tiles.csv "${config[@]}" -OUTPUT_DIR out > /dev/null
cat out/summary.txt
timed "batch -TASK MEASURE, 2 ranks x 1 thread" \
  mpirun --oversubscribe -np 2 "$octarc" batch tiles.csv "${config[@]}" -OUTPUT_DIR out > /dev/null
cut -f3- out/journal.txt
