#!/usr/bin/env bash
# Installs the Debian 12 packages octarc needs to build and test, those of `packages` below that
# are missing (with sudo when not root). Recommended packages are not installed: whatever a test
# needs is listed here. Every Python module a test or a script imports must come from a package
# listed here (tests/check_test_imports.py reads this list and checks it).
set -euo pipefail
cd "$(dirname "$0")/.."

# One package per line, grouped by what needs it.
packages=(
  # Build
  build-essential
  cmake
  ninja-build
  pkg-config
  libcfitsio-dev
  wcslib-dev
  libeigen3-dev
  libboost-program-options-dev
  # Boost.Math (header-only): the exact binomial intervals of the calibration
  libboost-dev
  libmuparser-dev
  # Check-plots (as SCAMP and PSFEx make them): PLplot with its cairo (PNG, PDF, SVG) driver
  libplplot-dev
  plplot-driver-cairo
  # Postage stamps: cairo, PLplot's own drawing back end, called directly (thread-safe, so the
  # stamps of a search are drawn on every core)
  libcairo2-dev
  libpng-dev
  # Least-squares fits (the Gaussian FWHM of the skewness distributions): Ceres Solver
  libceres-dev
  # The learned selection (SELECTION_METHOD TREES): gradient-boosted trees, XGBoost's C API
  libxgboost-dev
  libgtest-dev
  googletest
  # The Python module (import octarc, python/): pybind11 and the Python headers it compiles
  # against (CMake builds the module when it finds them)
  pybind11-dev
  python3-pybind11
  python3-dev
  # Cluster runs (octarc batch, simulate lenses under mpirun or srun): Open MPI; its mpirun
  # refuses to start without an ssh client (how it reaches other machines), even for one
  libopenmpi-dev
  openmpi-bin
  openssh-client

  # Packaging: dpkg-shlibdeps finds the Debian package's runtime dependencies (cpack -G DEB)
  dpkg-dev
  # cpack -G DEB runs file(1) on what it packages
  file
  # The fuzz targets read gzip inputs (fuzz/FuzzInput.h); the tests replay their seeds
  zlib1g-dev

  # Real peers and clients the tests run
  source-extractor
  fitsverify
  libcfitsio-bin
  stilts
  psfex
  scamp
  # The installation test records every file octarc opens
  strace
  # and checks the installed man pages with mandoc's linter
  mandoc
  # The benchmark scripts time whole runs (wall, CPU, peak memory)
  time

  # Python for the end-to-end tests (Debian's /usr/bin/python3)
  python3
  python3-astropy
  python3-numpy
  python3-scipy
  python3-sep
  python3-photutils
  # DS9 region files: the oracle of the region-mask tests (astropy regions)
  python3-regions
  # Screenshots read back in the contact-sheet test
  python3-pil
  # The Python module's lens-model scores checked against XGBoost's own Python package
  python3-xgboost
  # The search's inspection outputs in their real clients: SAOImage DS9 (headless under Xvfb)
  # loads the region file, Chromium (headless) the contact sheet
  saods9
  xvfb
  xauth
  libtk-img
  chromium
)

# Exploring with libFuzzer (scripts/fuzz.sh, not a test): Debian's clang, only when asked for
# (scripts/install-deps.sh fuzz).
fuzz_packages=(
  clang-14
  libfuzzer-14-dev
  libclang-rt-14-dev
)
if [ "${1:-}" = fuzz ]; then
  packages+=("${fuzz_packages[@]}")
elif [ $# -ne 0 ]; then
  echo "usage: scripts/install-deps.sh [fuzz]" >&2
  exit 2
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "Installing: ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
# --force-unsafe-io: dpkg skips its fsync per unpacked file (over a third of the installation
# time on a new machine); an installation cut short by a crash is simply run again.
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
  -o Dpkg::Options::=--force-unsafe-io "${missing[@]}"
