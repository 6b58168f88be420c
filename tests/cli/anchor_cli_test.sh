#!/bin/sh
# --anchor FEATURE@X,Y,Z of `tpcal identify`, `diagnose` and `run` (pipeline/cli/anchor_option.h)
# on the bundled raw turning scan: a malformed value exits 2 with the expected form; an unknown
# feature exits 2 naming it (the option reached the labelling); `run`: the flag overrides the
# pipeline YAML's raw_scan anchor and the labelling reports "anchor H1". (fit: CTest properties in
# pipeline/CMakeLists.txt.)
# Usage: anchor_cli_test.sh TPCAL SOURCE_DIR WORK_DIR identify|diagnose|run
set -eu
TPCAL=$1; SRC=$2; WORK=$3; CMD=$4
SCAN=$SRC/samples/turning_raw/cmm_scan.csv
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect2() {  # expect2 TEXT ARGS...: exit 2 with TEXT (fixed string) on stderr, no output
  pattern=$1; shift
  set +e; "$TPCAL" "$@" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  test $rc -eq 2 || fail "exit $rc for '$*', expected 2"
  grep -qF -e "$pattern" "$WORK/err.txt" || fail "'$*': stderr lacks '$pattern': $(cat "$WORK/err.txt")"
  test ! -e "$WORK/out" || fail "'$*' wrote output"
}
case "$CMD" in
identify | diagnose) ARGS="$CMD $SCAN --testpiece turning --json $WORK/out" ;;
run) ARGS="run --testpiece turning --points $SCAN --out $WORK/out --mc-trials 0" ;;
*) fail "unknown mode $CMD" ;;
esac
# shellcheck disable=SC2086
{
  expect2 "--anchor: expected FEATURE@X,Y,Z (mm), got 'H1@1,2'" $ARGS --anchor H1@1,2
  expect2 "--anchor: expected FEATURE@X,Y,Z (mm), got '@1,2,3'" $ARGS --anchor @1,2,3
  expect2 "--anchor: expected FEATURE@X,Y,Z (mm), got 'H1@1,2,nan'" $ARGS --anchor H1@1,2,nan
  expect2 "cmm_scan.csv: raw-scan anchor: 'Q9' is not a feature of the" $ARGS --anchor Q9@1,2,3
}
if [ "$CMD" = run ]; then
  # The YAML anchors H1 where file order puts it; --anchor (near H5 of the file-order labelling) wins.
  printf 'schema: tpcal.pipeline/1\ntestpiece: turning\npoints: %s\nraw_scan: {anchor_feature: H1, anchor_near_mm: [-343.2, 93.2, -162.1]}\n' \
    "$SCAN" > "$WORK/pipeline.yaml"
  "$TPCAL" -q run "$WORK/pipeline.yaml" --out "$WORK/out" --mc-trials 0 --anchor H1@-377,-25,-317 > /dev/null 2> "$WORK/err.txt" ||
    fail "run with --anchor: $(cat "$WORK/err.txt")"
  grep -q 'anchor_near_mm: \[-377, -25, -317\]' "$WORK/out/config.yaml" || fail "config.yaml lacks the --anchor point"
  grep -q '"symmetry_resolved_by": "anchor H1"' "$WORK/out/result.json" || fail "result.json: not resolved by the anchor"
fi
echo "anchor_cli $CMD: ok"
