#!/bin/sh
# Bad input: a clear error (file, line, what was expected), exit 2, nothing written.
# Usage: run_bad_input_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect2() {  # expect2 PATTERN ARGS...: exit 2 with PATTERN on stderr, no output directory
  pattern=$1; shift
  set +e; "$TPCAL" "$@" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  test $rc -eq 2 || fail "exit $rc for '$*', expected 2"
  grep -q "$pattern" "$WORK/err.txt" || fail "'$*': stderr lacks '$pattern': $(cat "$WORK/err.txt")"
  test ! -e "$WORK/out" || fail "'$*' wrote an output directory"
}
expect2 'no_such.csv' run --testpiece turning --points "$WORK/no_such.csv" --out "$WORK/out"
printf 'schema: tpcal.pipeline/1\npoints: x.csv\nsede: 3\n' > "$WORK/bad.yaml"
expect2 'bad.yaml:3.*sede' run "$WORK/bad.yaml" --out "$WORK/out"
expect2 'unknown test piece' run --testpiece lathe --points "$SRC/samples/turning/cmm_points.csv" --out "$WORK/out"
expect2 'output directory' run --testpiece turning --points "$SRC/samples/turning/cmm_points.csv"
# A feature with too few points: names the feature.
grep -v '^S4,' "$SRC/samples/turning/cmm_points.csv" > "$WORK/no_s4.csv"
grep '^S4,' "$SRC/samples/turning/cmm_points.csv" | head -2 >> "$WORK/no_s4.csv"
expect2 'S4' run --testpiece turning --points "$WORK/no_s4.csv" --out "$WORK/out"
# An unrelated directory is never replaced.
mkdir -p "$WORK/precious"; echo keep > "$WORK/precious/notes.txt"
set +e; "$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --out "$WORK/precious" > /dev/null 2>&1; rc=$?; set -e
test $rc -eq 2 || fail "replacing an unrelated directory: exit $rc"
test -f "$WORK/precious/notes.txt" || fail "unrelated directory touched"
echo "run_bad_input: ok"
