#!/usr/bin/env bash
# Installs what is missing, builds octarc with GCC and warnings as errors and runs every test;
# then builds once more with AddressSanitizer + UndefinedBehaviorSanitizer (build/asan) and runs
# the tests again there, except those labelled `slow` (tests/integration/CMakeLists.txt: the
# end-to-end cases that take 4 s or more in a release build) or `packaging` (installation and
# Debian package: they check what is installed, not how it was compiled), which the release pass
# has run, and last has every fuzz target replay its corpus (scripts/fuzz.sh 0: every seed and
# kept input once, in a clang tree of the fuzz targets alone; see README "Hostile input and
# fuzzing" for a long exploration). With CI=true in the environment a test skipped for a missing
# program or missing shared data fails instead.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh

jobs=$(nproc)
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DOCTARC_WERROR=ON
cmake --build build/release -j "$jobs"
ctest --test-dir build/release --output-on-failure -j "$jobs"

cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOCTARC_WERROR=ON \
  -DOCTARC_SANITIZE=ON
cmake --build build/asan -j "$jobs"
# Full allocation stacks (fast_unwind_on_malloc=0): the fast unwinder stops inside libraries
# built without frame pointers, and tests/lsan.supp names library functions.
ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=0 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE 'slow|packaging'

OCTARC_FUZZ_JOBS=$jobs scripts/fuzz.sh 0
