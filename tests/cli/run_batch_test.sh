#!/bin/sh
# tpcal run --batch over copies of the sample and one corrupt file: goes on past the bad file,
# names it with its line, exits 1, and writes a summary row per file.
# Usage: run_batch_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK/in"
fail() { echo "FAIL: $*" >&2; exit 1; }
for i in 1 2 3 4; do cp "$SRC/samples/turning/cmm_points.csv" "$WORK/in/day$i.csv"; done
# day5: a non-number in the 10th data row
awk 'BEGIN{FS=OFS=","} /^[A-Z]/{n++; if(n==10) $2="12.3.4"} {print}' "$SRC/samples/turning/cmm_points.csv" > "$WORK/in/day5.csv"
set +e
"$TPCAL" run --batch "$WORK/in" --testpiece turning --machine "$SRC/samples/machines/ac_table.yaml" \
  --mc-trials 0 --out "$WORK/out" -j 2 > "$WORK/out.txt" 2> "$WORK/err.txt"
rc=$?
set -e
test $rc -eq 1 || fail "exit code $rc, expected 1: $(cat "$WORK/err.txt")"
grep -q 'day5.csv:1[0-9]' "$WORK/err.txt" || fail "error does not name day5.csv and its line: $(cat "$WORK/err.txt")"
grep -q '5 files, 4 ok, 1 failed' "$WORK/err.txt" || fail "no batch summary line: $(cat "$WORK/err.txt")"
test "$(wc -l < "$WORK/out/summary.csv")" -eq 6 || fail "summary.csv rows"
test "$(grep -c '^[0-9]*,[^,]*,ok,' "$WORK/out/summary.csv")" -eq 4 || fail "ok rows"
test "$(grep -c '^[0-9]*,[^,]*,error,' "$WORK/out/summary.csv")" -eq 1 || fail "error rows"
test -s "$WORK/out/summary_trend.svg" || fail "no trend figure"
for i in 1 2 3 4; do test -s "$WORK/out/day$i/report.html" || fail "no report for day$i"; done
test ! -e "$WORK/out/day5" || fail "a run directory for the failed file"
# The glob form picks the same files; all good: exit 0.
rm "$WORK/in/day5.csv"
"$TPCAL" -q run --batch "$WORK/in/day*.csv" --testpiece turning --mc-trials 0 --out "$WORK/out2" > /dev/null \
  || fail "clean batch failed"
test "$(wc -l < "$WORK/out2/summary.csv")" -eq 5 || fail "clean summary rows"
echo "run_batch: ok"
