#!/usr/bin/env bash
# Installs what is missing, builds octarc with GCC and warnings as errors and runs every test
# once or twice:
# - build/release (-O3) runs the end-to-end tests (tests/integration: octarc against
#   source-extractor, astropy and the other real clients) and the packaging tests, on the
#   optimised octarc that users install;
# - build/asan (AddressSanitizer + UndefinedBehaviorSanitizer) runs the unit tests, built in this
#   tree only. The libraries compute the same numbers at -Og and -O3 (no -ffast-math, and no FMA
#   without -march: GCC reorders no floating-point operation), and here the unit tests also catch
#   memory and undefined-behaviour errors in the code they call. It has no Python module (an
#   instrumented extension cannot be loaded by Debian's python3): the module's tests run in
#   build/release only. This tree runs the end-to-end
#   tests again, on the instrumented octarc, except those labelled `slow`
#   (tests/integration/CMakeLists.txt: the cases that take 4 s or more in a release build) or
#   `packaging` (installation and Debian package: they check what is installed, not how it was
#   compiled), and every fuzz target replays its seed corpus (the tests fuzz.TARGET: every seed
#   once, as libFuzzer's -runs=0 does; see README "Hostile input and fuzzing" for exploring).
# With CI=true in the environment a test skipped for a missing program or missing shared data
# fails instead.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each stage's start, with the seconds since the script began (the CI log's time line).
started=$(date +%s)
stage() { echo "== test.sh: $1 (at $(($(date +%s) - started)) s)"; }

stage "installing what is missing"
scripts/install-deps.sh

jobs=$(nproc)
stage "release build"
# The unit tests are built and run in the sanitizer tree only (see the top of this script):
# building them here took 40 % of this tree's compile time. OCTARC_PYTHON ON: without pybind11
# the configure fails rather than leaving the Python module and its tests out.
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DOCTARC_WERROR=ON \
  -DOCTARC_UNIT_TESTS=OFF -DOCTARC_PYTHON=ON
cmake --build build/release -j "$jobs"
stage "release tests"
ctest --test-dir build/release --output-on-failure -j "$jobs"

stage "sanitizer build"
# -Og -g1 (line tables: the sanitizers' reports name file and line). Instrumented code is slow to
# optimise: -Og compiled the largest unity batches in 30-55 % less CPU time than -O1, and the
# instrumented octarc ran as fast (0.24 s of CPU for a 15-level detection of the NTT frame at
# both).
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g1 -DNDEBUG" -DOCTARC_WERROR=ON -DOCTARC_SANITIZE=ON \
  -DOCTARC_UNIT_TESTS=ON -DOCTARC_PYTHON=OFF
cmake --build build/asan -j "$jobs"
stage "sanitizer tests"
# Allocation stacks by the fast unwinder (ASan's default): it stops at the first frame inside a
# library built without frame pointers, which is enough to name octarc's own leaks. The one
# library leak tests/lsan.supp names by function needs the full unwind, which doubles the CPU
# time of every short octarc run; the test that expects it asks for it itself
# (octarc_testlib.full_allocation_stacks), as the fuzz targets do.
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE 'slow|packaging'
stage "done"
