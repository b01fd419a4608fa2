#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan; CMake option FSS_FUZZ):
# PNG and TIFF decoding, code files, campaign files, campaign journals (as
# merge and a resumed run read them), the results and expectations of
# 'campaign check', and the range syntaxes (value lists of campaigns,
# --velocity/--snr of sweep), and the Python module's argument conversion
# (python/arguments.cpp); and
# runs each for FUZZ_SECONDS (default 60) from its seed corpus in
# tests/fuzz/corpus/, as many targets at a time as there are cores (each
# target is one process on one core). Fails on any crash, leak, timeout,
# out-of-memory or sanitizer report; prints the number of inputs each target
# executed, in the order of the targets.
# Limits: 2 GiB of resident memory, no single allocation above 1 GiB (the PNG
# target skips images of more than 2^24 pixels that a file could really hold,
# the TIFF target refuses decodings over 256 MiB),
# 20 s per input.
# Usage: [FUZZ_SECONDS=N] [FUZZ_TARGETS="fuzz_range ..."] scripts/fuzz.sh [build-dir]
#        (default build-dir: build-fuzz; default targets: all)
# Inputs found interesting go to <build-dir>/corpus/<target>/ (the seed
# corpus is only read); a crashing input is saved as <build-dir>/<target>-crash-*.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${FUZZ_SECONDS:-60}
jobs=$(nproc 2>/dev/null || echo 2)
if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ not found (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
source scripts/build-flags.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" "${fast_link[@]}" \
  -DFSS_FUZZ=ON -DFSS_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target fuzz_png fuzz_tiff fuzz_code fuzz_campaign_file \
  fuzz_campaign_journal fuzz_campaign_check fuzz_range fuzz_python_arguments
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

# run TARGET SEEDS MAX_LEN DICTIONARY: fuzzes TARGET; prints one line, or the
# failure and the end of its log and returns 1.
run() {
  local target=$1 seeds=$2 max_len=$3 dict=$4
  local corpus="$build/corpus/$target" log="$build/$target.log"
  mkdir -p "$corpus"
  if "$build/tests/fuzz/$target" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len="$max_len" -timeout=20 -dict="$dict" -print_final_stats=1 \
    -artifact_prefix="$build/$target-" "$corpus" "$seeds" >"$log" 2>&1; then
    local runs
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz: $target: ${runs:-?} inputs executed in ${seconds} s, no failure" \
      "(corpus $(find "$corpus" -type f | wc -l) files)"
  else
    echo "fuzz: $target FAILED (full log: $log):"
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written|deadly signal' "$log" | head -20
    tail -n 40 "$log"
    return 1
  fi
}

# start TARGET SEEDS MAX_LEN DICTIONARY: runs `run` in the background, $jobs
# at a time; its output goes to $build/TARGET.summary, its exit status to
# $build/TARGET.status.
started=()
start() {
  local target=$1
  case " ${FUZZ_TARGETS:-$target} " in *" $target "*) ;; *) return 0 ;; esac
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  rm -f "$build/$target.status"
  { if run "$@" >"$build/$target.summary" 2>&1; then echo 0; else echo 1; fi >"$build/$target.status"; } &
  started+=("$target")
}
start fuzz_png tests/fuzz/corpus/png 65536 tests/fuzz/png.dict
start fuzz_tiff tests/fuzz/corpus/tiff 65536 tests/fuzz/tiff.dict
start fuzz_code tests/fuzz/corpus/code 4096 tests/fuzz/code.dict
start fuzz_campaign_file tests/fuzz/corpus/campaign_file 4096 tests/fuzz/campaign_file.dict
start fuzz_campaign_journal tests/fuzz/corpus/campaign_journal 16384 tests/fuzz/campaign_journal.dict
start fuzz_campaign_check tests/fuzz/corpus/campaign_check 8192 tests/fuzz/campaign_check.dict
start fuzz_range tests/fuzz/corpus/range 1024 tests/fuzz/range.dict
start fuzz_python_arguments tests/fuzz/corpus/python_arguments 1024 tests/fuzz/python_arguments.dict
wait
status=0
for target in "${started[@]}"; do
  cat "$build/$target.summary"
  [ "$(cat "$build/$target.status" 2>/dev/null)" = 0 ] || status=1
done
exit "$status"
