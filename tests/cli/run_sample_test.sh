#!/bin/sh
# tpcal run on the bundled turning sample: every output is written, result.json is byte-identical
# for the same inputs and seed (YAML form and flags form alike), a new seed changes it, and -q
# keeps stderr silent. Usage: run_sample_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$TPCAL" run "$SRC/samples/pipelines/turning.yaml" --out "$WORK/a" -q > "$WORK/a.out" 2> "$WORK/a.err"
test ! -s "$WORK/a.err" || fail "-q run printed on stderr: $(cat "$WORK/a.err")"
for f in report.html result.json config.yaml identification.csv identifiability.csv characteristics.csv \
         features.csv figures/machine_errors.svg figures/hole_positions.svg figures/circularity.svg \
         figures/vectors.svg figures/gap.svg; do
  test -s "$WORK/a/$f" || fail "missing $f"
done
grep -q 'dx_CR(0)' "$WORK/a.out" || fail "no parameter table on stdout"
ls "$WORK" | grep -q '\.tmp\.' && fail "temporary directory left behind"

# Same inputs and seed: the same bytes, also into an existing run directory.
"$TPCAL" run "$SRC/samples/pipelines/turning.yaml" --out "$WORK/b" -q > /dev/null
cmp "$WORK/a/result.json" "$WORK/b/result.json" || fail "result.json differs between identical runs"
"$TPCAL" run "$SRC/samples/pipelines/turning.yaml" --out "$WORK/b" -q > /dev/null
cmp "$WORK/a/result.json" "$WORK/b/result.json" || fail "result.json differs after replacing a run"

# The flags form with the same inputs is the same run.
"$TPCAL" -q run --testpiece turning --points "$SRC/samples/turning/cmm_points.csv" \
  --machine "$SRC/samples/machines/ac_table.yaml" --truth "$SRC/samples/turning/truth.yaml" --seed 1 \
  --out "$WORK/c" > /dev/null
cmp "$WORK/a/result.json" "$WORK/c/result.json" || fail "flags form differs from the YAML form"

# Another seed: written to the output, and the Monte Carlo figures change.
"$TPCAL" run "$SRC/samples/pipelines/turning.yaml" --seed 2 --out "$WORK/d" -q > /dev/null
grep -q '"seed": 2' "$WORK/d/result.json" || fail "seed not written"
if cmp -s "$WORK/a/result.json" "$WORK/d/result.json"; then fail "seed has no effect"; fi
# Progress: none when stderr is not a terminal; a progress line on a terminal (script(1) gives one).
"$TPCAL" run "$SRC/samples/pipelines/turning.yaml" --mc-trials 0 --out "$WORK/e" > /dev/null 2> "$WORK/e.err"
grep -q 'identify\.\.\.' "$WORK/e.err" && fail "progress lines without a terminal"
grep -q '^wrote ' "$WORK/e.err" || fail "no closing info line without -q"
if command -v script > /dev/null; then
  script -qc "'$TPCAL' run '$SRC/samples/pipelines/turning.yaml' --mc-trials 0 --out '$WORK/f'" /dev/null > "$WORK/f.tty"
  grep -q 'tpcal run: identify\.\.\.' "$WORK/f.tty" || fail "no progress line on a terminal"
  grep -q 'stages: setup' "$WORK/f.tty" || fail "no stage times on a terminal"
fi
echo "run_sample: ok"
