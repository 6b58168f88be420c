#!/bin/sh
# Killed (SIGKILL) at any moment, `tpcal run` leaves the previous run or the new one, each whole,
# never a mix or a partial directory; the next run removes the siblings a killed run left.
# 20 kills at moments spread over the second half of a run and a little beyond (the output is
# written at its end), drawn from a fixed seed. report.html carries a time stamp: it is checked to
# be complete (ends with </html>), every other file byte for byte against a finished run.
# Usage: run_kill_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { "$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --mc-trials 0 --seed "$1" --out "$WORK/out"; }
now_ms() { date +%s%3N; }

run 1 > /dev/null && mv "$WORK/out" "$WORK/ref_old"
t0=$(now_ms); run 2 > /dev/null; t1=$(now_ms)
mv "$WORK/out" "$WORK/ref_new"
T=$((t1 - t0))

same() {  # same DIR REF: same file list; same bytes except report.html, which must be complete
  (cd "$1" && find . -type f | sort) > "$WORK/list_a"
  (cd "$2" && find . -type f | sort) > "$WORK/list_b"
  cmp -s "$WORK/list_a" "$WORK/list_b" || return 1
  for f in $(cat "$WORK/list_a"); do
    if [ "$f" = ./report.html ]; then
      tail -c 16 "$1/$f" | grep -q '</html>' || return 1
    else
      cmp -s "$1/$f" "$2/$f" || return 1
    fi
  done
}

old=0; new=0
for i in $(seq 1 20); do
  rm -rf "$WORK/out"; cp -a "$WORK/ref_old" "$WORK/out"
  delay=$(awk -v i="$i" -v T="$T" 'BEGIN { srand(1000 + i); printf "%.3f", T * (0.5 + 0.7 * rand()) / 1000 }')
  # tpcal itself in the background (a shell function would run in a subshell, and the kill
  # would hit the subshell only).
  "$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --mc-trials 0 --seed 2 --out "$WORK/out" > /dev/null 2>&1 &
  pid=$!
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  if same "$WORK/out" "$WORK/ref_old"; then old=$((old + 1))
  elif same "$WORK/out" "$WORK/ref_new"; then new=$((new + 1))
  else fail "kill $i after ${delay} s left a directory that is neither run whole: $(ls "$WORK/out" | tr '\n' ' ')"
  fi
done
run 2 > /dev/null
same "$WORK/out" "$WORK/ref_new" || fail "a finished run after the kills differs from the reference"
left=$(ls -a "$WORK" | grep -c '^out\.\(tmp\|old\)\.' || true)
[ "$left" -eq 0 ] || fail "$left sibling(s) of killed runs left after a finished run: $(ls -a "$WORK")"
echo "run_kill: ok (run ${T} ms; 20 kills: old run whole $old times, new run whole $new times)"
