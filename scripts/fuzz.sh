#!/usr/bin/env bash
# Fuzzes every reader: builds the libFuzzer targets of fuzz/ with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in build/fuzz, writes their seed corpus (scripts/make-fuzz-corpus.py:
# testdata/, params/ and small generated files) and runs each target for SECONDS (default 600).
# SECONDS=0 explores nothing: each target replays its corpus (seeds and kept inputs), every input
# once (libFuzzer's -runs=0). The test suite replays the seeds the same way without libFuzzer, in
# its sanitizer build (fuzz/CMakeLists.txt: the ctest tests fuzz.TARGET).
# Inputs that grow coverage are kept in build/fuzz/corpus/TARGET and reused by the next run; a
# crash, sanitizer report, leak (tests/lsan.supp lists the known leaks of cfitsio itself), hang
# (an input taking over 30 s: the targets run under ASan, at low priority, beside other work) or
# out-of-memory (2 GB) is saved in
# build/fuzz/crashes/TARGET/ and makes the script fail. Reproduce one with
#   build/fuzz/fuzz/TARGET build/fuzz/crashes/TARGET/crash-...
#
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]     (every target when none is named)
# OCTARC_FUZZ_JOBS=N runs N targets at a time (default 1).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-600}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fuzz_fits_image fuzz_segmentation fuzz_input_catalog fuzz_real_galaxy_catalog
           fuzz_sex_config fuzz_param fuzz_conv fuzz_assoc fuzz_population)
fi
jobs=${OCTARC_FUZZ_JOBS:-1}

scripts/install-deps.sh fuzz
CC=clang-14 CXX=clang++-14 cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DOCTARC_FUZZ=ON -DOCTARC_BUILD_TESTS=OFF >/dev/null
cmake --build build/fuzz -j "$(nproc)" --target octarc_fuzz
/usr/bin/python3 scripts/make-fuzz-corpus.py build/fuzz/seeds
mkdir -p build/fuzz/logs

export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1:fast_unwind_on_malloc=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0

# One target; its summary line goes to build/fuzz/logs/TARGET.result.
run_target() {
  local t=$1 options result
  case "$t" in
    fuzz_fits_image|fuzz_segmentation|fuzz_input_catalog|fuzz_real_galaxy_catalog)
      options=(-max_len=65536 -dict=fuzz/fits.dict) ;;
    *)
      options=(-max_len=8192 -dict=fuzz/sex.dict) ;;
  esac
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/crashes/$t"
  local log="build/fuzz/logs/$t.log"
  local length=(-max_total_time="$seconds")
  [ "$seconds" = 0 ] && length=(-runs=0)
  result=ok
  if ! nice -n 10 "build/fuzz/fuzz/$t" "${options[@]}" "${length[@]}" -timeout=30 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="build/fuzz/crashes/$t/" \
      "build/fuzz/corpus/$t" "build/fuzz/seeds/$t" >"$log" 2>&1; then
    result="FAILED (see $log and build/fuzz/crashes/$t/)"
  fi
  local runs corpus
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(ls "build/fuzz/corpus/$t" | wc -l)
  printf '%-26s %12s %10s  %s\n' "$t" "${runs:-?}" "$corpus" "$result" >"build/fuzz/logs/$t.result"
}

for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  run_target "$t" &
done
wait

printf '%-26s %12s %10s  %s\n' target executions corpus result
failed=()
for t in "${targets[@]}"; do
  cat "build/fuzz/logs/$t.result"
  grep -q FAILED "build/fuzz/logs/$t.result" && failed+=("$t")
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzzing found a problem in: ${failed[*]}" >&2
  exit 1
fi
