#!/usr/bin/env bash
# Installs what is missing, builds octarc with warnings as errors, runs every test, then builds
# once more with AddressSanitizer + UndefinedBehaviorSanitizer and runs the tests again, except
# those labelled `slow` (tests/integration/CMakeLists.txt: the end-to-end cases that take 4 s or
# more in a release build; the release pass has run them). With CI=true in the environment a
# test skipped for a missing program or missing shared data fails instead.
# Last it runs every fuzz target briefly (scripts/fuzz.sh, as many at once as there are cores).
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
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE slow

# 7 seconds per target, 9 targets, as many at a time as there are cores: a short smoke run;
# see README "Fuzzing" for a long one.
OCTARC_FUZZ_JOBS=$jobs scripts/fuzz.sh 7
