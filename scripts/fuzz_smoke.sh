#!/bin/sh
# Fuzz smoke run (README, "Fuzzing"): builds every libFuzzer target of tests/fuzz with clang and
# runs each for FUZZ_SECONDS (default 20) from its seed corpus and dictionary, FUZZ_PARALLEL targets
# at a time. Any finding (crash, leak, timeout, out-of-memory, malformed error message) fails the
# run; its reproducer is left in FUZZ_DIR/<target>/ (crash-*, leak-*, timeout-*, oom-*).
# Usage: scripts/fuzz_smoke.sh [TARGET...]      (default: every tests/fuzz/*_fuzz.cc)
# Env: FUZZ_SECONDS (20), FUZZ_BUILD (build-fuzz; scripts/test.sh passes its clang sanitizer
#      build), FUZZ_DIR (FUZZ_BUILD/fuzz-smoke), FUZZ_JOBS (ninja -j, 2), FUZZ_PARALLEL (1),
#      FUZZ_RSS_MB (-rss_limit_mb, 2048), FUZZ_SEED (-seed; 0, the default, lets libFuzzer pick one),
#      FUZZ_RUNS (-runs: stop a target after this many executions, whichever comes first; -1, none),
#      FUZZ_TIMEOUT (-timeout: seconds one input may take, 10; long runs on a shared machine, where
#      another job can starve the fuzzer for longer, need more or report false timeouts).
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SECONDS_EACH=${FUZZ_SECONDS:-20}
BUILD=${FUZZ_BUILD:-$ROOT/build-fuzz}
WORK=${FUZZ_DIR:-$BUILD/fuzz-smoke}
JOBS=${FUZZ_JOBS:-2}
PARALLEL=${FUZZ_PARALLEL:-1}
RSS_MB=${FUZZ_RSS_MB:-2048}
SEED=${FUZZ_SEED:-0}
RUNS=${FUZZ_RUNS:--1}
TIMEOUT=${FUZZ_TIMEOUT:-10}

# One target: `fuzz_smoke.sh --one TARGET` (the parallel runs below call it) prints one line,
# "fuzz T: ok ..." or "fuzz T: FINDING ...".
if [ "${1:-}" = "--one" ]; then
  t=$2
  dir="$WORK/$t"
  rm -rf "$dir"; mkdir -p "$dir/corpus"
  # Findings are written into $dir; the seed corpus in the tree is read, never written.
  set +e
  (cd "$dir" && ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    "$BUILD/fuzz/fuzz_$t" -max_total_time="$SECONDS_EACH" -runs="$RUNS" -timeout="$TIMEOUT" -rss_limit_mb="$RSS_MB" \
    -malloc_limit_mb="$RSS_MB" -seed="$SEED" -dict="$ROOT/tests/fuzz/$t.dict" -print_final_stats=1 \
    "$dir/corpus" "$ROOT/tests/fuzz/corpus/$t" > "$dir/log.txt" 2>&1)
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log.txt" | tail -1)
  took=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$dir/log.txt" | tail -1)
  if [ $rc -ne 0 ] || ls "$dir" | grep -Eq '^(crash|leak|timeout|oom|slow-unit)-'; then
    echo "fuzz $t: FINDING (exit $rc, ${runs:-?} runs); see $dir/log.txt"
    grep -E '^(==[0-9]+==ERROR|SUMMARY|tpcal fuzz)' "$dir/log.txt" | head -5 || true
  else
    echo "fuzz $t: ok, ${runs:-?} runs in ${took:-$SECONDS_EACH}s"
  fi
  exit 0
fi

if [ $# -gt 0 ]; then
  TARGETS="$*"
else
  TARGETS=$(cd "$ROOT/tests/fuzz" && ls *_fuzz.cc | sed 's/_fuzz\.cc$//')
fi

if [ ! -f "$BUILD/build.ninja" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
    -DTPCAL_FUZZ=ON -DTPCAL_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
ninja -C "$BUILD" -j "$JOBS" $(for t in $TARGETS; do printf 'fuzz_%s ' "$t"; done)

mkdir -p "$WORK"
report="$WORK/report.txt"
printf '%s\n' $TARGETS | xargs -P "$PARALLEL" -n 1 "$0" --one > "$report"
cat "$report"
failed=$(sed -n 's/^fuzz \([^:]*\): FINDING.*/\1/p' "$report" | tr '\n' ' ')
if [ -n "$failed" ] || [ "$(grep -c '^fuzz [^:]*: ok' "$report")" -ne "$(printf '%s\n' $TARGETS | wc -l)" ]; then
  echo "fuzz smoke: findings in: ${failed:-(a target gave no result)}"
  exit 1
fi
if [ "$RUNS" = "-1" ]; then limit="${SECONDS_EACH}s"; else limit="up to ${SECONDS_EACH}s or $RUNS runs"; fi
echo "fuzz smoke: every target ran $limit without a finding"
