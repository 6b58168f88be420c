#!/bin/sh
# CMM formats end to end (docs/formats/qif.md, docs/formats/dmis.md): `tpcal plan --dmis` writes
# the DMIS program; the turning sample's points as DMIS output, QIF and PC-DMIS XYZIJK
# (tests/data/) give the same identification.csv as the CSV; bad QIF / DMIS files exit 2 with
# `file:line: what was expected` and write nothing.
# Usage: run_cmm_formats_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect2() {  # expect2 PATTERN ARGS...: exit 2 with PATTERN on stderr, no output directory
  pattern=$1; shift
  set +e; "$TPCAL" "$@" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  test $rc -eq 2 || fail "exit $rc for '$*', expected 2: $(cat "$WORK/err.txt")"
  grep -q "$pattern" "$WORK/err.txt" || fail "'$*': stderr lacks '$pattern': $(cat "$WORK/err.txt")"
  test ! -e "$WORK/out" || fail "'$*' wrote an output directory"
}

# The program: written next to the plan, one F/PTMEAS/OUTPUT per planned point.
"$TPCAL" -q plan --testpiece turning -o "$WORK/plan.csv" --dmis "$WORK/plan.dmi"
n_plan=$(grep -vc '^#\|^feature' "$WORK/plan.csv")
test "$(grep -c '^PTMEAS/' "$WORK/plan.dmi")" -gt "$n_plan" || fail "fewer PTMEAS than planned points"
test "$(grep -c '^OUTPUT/FA(' "$WORK/plan.dmi")" -eq "$n_plan" || fail "OUTPUT count differs from the plan"
grep -q '^D(TPCAL_DATUM)=DATSET/' "$WORK/plan.dmi" || fail "no datum alignment"
tail -n 1 "$WORK/plan.dmi" | grep -q '^ENDFIL$' || fail "no ENDFIL"
expect2 'name the same file' plan --testpiece turning -o "$WORK/same" --dmis "$WORK/same"

# The same points in four formats: the same identification.
"$TPCAL" -q run --testpiece turning --points "$SRC/samples/turning/cmm_points.csv" --out "$WORK/csv" > /dev/null
for f in dmis/turning_sample.dmo qif/turning_sample.qif dmis/turning_sample_xyzijk.txt; do
  name=$(basename "$f" | tr . _)
  "$TPCAL" -q run --testpiece turning --points "$SRC/tests/data/$f" --out "$WORK/$name" > /dev/null
  cmp -s "$WORK/csv/identification.csv" "$WORK/$name/identification.csv" || fail "$f identifies differently from the CSV"
  cmp -s "$WORK/csv/characteristics.csv" "$WORK/$name/characteristics.csv" || fail "$f: GD&T differs from the CSV"
done

# A table under its own column names, mapped with --column (run and identify): the same result.
sed '1s/.*/Pt ID;PX;PY;PZ;NI;NJ;NK;Probe/' "$SRC/tests/data/tables/turning_sample_semicolon.csv" > "$WORK/own_names.csv"
map='--column feature=pt_id --column x=PX --column y=PY --column z=PZ --column i=NI --column j=NJ --column k=NK'
sed -i '1s/Pt ID/pt_id/' "$WORK/own_names.csv"
# shellcheck disable=SC2086
"$TPCAL" -q run --testpiece turning --points "$WORK/own_names.csv" $map --out "$WORK/own_names" > /dev/null
cmp -s "$WORK/csv/identification.csv" "$WORK/own_names/identification.csv" || fail "--column: identifies differently from the CSV"
grep -q '^  feature: pt_id$' "$WORK/own_names/config.yaml" || fail "--column: the mapping is not in the effective config.yaml"
expect2 "own_names.csv:1: header lacks the required column 'feature'" identify "$WORK/own_names.csv" --testpiece turning
expect2 "own_names.csv:1: header has no column 'Point'" identify "$WORK/own_names.csv" --testpiece turning --column feature=Point
expect2 "column role 'w'" identify "$WORK/own_names.csv" --testpiece turning --column w=PX
expect2 'applies to CSV and TSV tables only' identify "$SRC/tests/data/qif/turning_sample.qif" --testpiece turning --column x=PX

# Bad files.
head -c 1500 "$SRC/tests/data/qif/turning_sample.qif" > "$WORK/unclosed.qif"
expect2 'unclosed.qif:[0-9]*: malformed XML' run --testpiece turning --points "$WORK/unclosed.qif" --out "$WORK/out"
sed 's|<UnitName>mm</UnitName><UnitConversion><Factor>0.001</Factor></UnitConversion>|<UnitName>furlong</UnitName>|' \
  "$SRC/tests/data/qif/turning_sample.qif" > "$WORK/units.qif"
expect2 "units.qif:4: unknown length unit 'furlong'" fit "$WORK/units.qif" --testpiece turning
sed 's|<WholePointSetId>15</WholePointSetId>||' "$SRC/tests/data/qif/turning_sample.qif" > "$WORK/orphan.qif"
expect2 'orphan.qif:[0-9]*: MeasuredPointSet id="15" belongs to no feature' identify "$WORK/orphan.qif" --testpiece turning
expect2 'QIF_PTS_SAMPLE_excerpt.QIF:223: .*not probe-compensated' fit "$SRC/tests/data/qif/QIF_PTS_SAMPLE_excerpt.QIF"
sed '10s/,[^,]*,[^,]*$//' "$SRC/tests/data/dmis/turning_sample.dmo" > "$WORK/short.dmo"
expect2 'short.dmo:10: FA(S_R_6) has 4 numbers' run --testpiece turning --points "$WORK/short.dmo" --out "$WORK/out"
sed '12s/FA(S_R_8)/FA(XX_8)/' "$SRC/tests/data/dmis/turning_sample.dmo" > "$WORK/label.dmo"
expect2 'label.dmo:12:.*XX' run --testpiece turning --points "$WORK/label.dmo" --out "$WORK/out"
echo "run_cmm_formats: ok"
