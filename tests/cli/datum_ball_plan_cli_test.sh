#!/bin/sh
# CTest driver for `tpcal plan --instrument datum_ball` (pipeline/CMakeLists.txt, after
# cli/identify_datum_ball_bad).
#   datum_ball_plan_cli_test.sh TPCAL SOURCE WORKDIR plan       the plan and the program in all four
#       dialects; the LinuxCNC program through rs274 (180 STRAIGHT_PROBE, clean; fails when rs274 is
#       missing unless TPCAL_ALLOW_NO_RS274=1); the plan identified by `tpcal identify` gives zeros
#   datum_ball_plan_cli_test.sh TPCAL SOURCE WORKDIR bad_input  exit 2, the option or file named,
#       nothing written
set -u
TPCAL=$1
SRC=$2
WORK=$3
MODE=$4
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$WORK" && mkdir -p "$WORK" || fail "cannot create $WORK"
cd "$WORK" || fail "cannot enter $WORK"

case "$MODE" in
plan)
  for d in linuxcnc fanuc sinumerik heidenhain; do
    "$TPCAL" -q plan --instrument datum_ball -o "plan_$d.csv" --nc "db_$d.prog" --dialect "$d" --date 2025-01-01 \
      2> "$d.err" || { cat "$d.err" >&2; fail "tpcal plan --dialect $d exited $?"; }
    [ -s "plan_$d.csv" ] && [ -s "db_$d.prog" ] || fail "$d: outputs not written"
    cmp -s plan_linuxcnc.csv "plan_$d.csv" || fail "$d: the plan depends on the dialect"
  done
  head -n 1 plan_linuxcnc.csv | grep -qx '# tpcal ballpos v1' || fail "plan: not a tpcal ballpos v1 file"
  grep -q '^# plan: nominal centring commands' plan_linuxcnc.csv || fail "plan: no plan comment line"
  rows=$(grep -c '^-\{0,1\}[0-9]' plan_linuxcnc.csv)
  [ "$rows" -eq 36 ] || fail "plan: $rows rows, expected 36"
  [ "$(grep -c 'G38\.2 ' db_linuxcnc.prog)" -eq 180 ] || fail "linuxcnc: expected 180 G38.2 blocks"
  [ "$(grep -c 'G31 ' db_fanuc.prog)" -eq 180 ] || fail "fanuc: expected 180 G31 blocks"
  [ "$(grep -c 'MEAS=1 G1 ' db_sinumerik.prog)" -eq 180 ] || fail "sinumerik: expected 180 MEAS=1 blocks"
  [ "$(grep -c 'TCH PROBE 0\.0 REF\. PLANE' db_heidenhain.prog)" -eq 180 ] || fail "heidenhain: expected 180 TCH PROBE 0"
  RS274=$(command -v rs274 || true)
  if [ -n "$RS274" ]; then
    mkdir -p home
    HOME="$WORK/home" "$RS274" -g db_linuxcnc.prog -t db_linuxcnc.prog.tbl > db.canon 2> rs274.err < /dev/null
    rc=$?
    [ $rc -eq 0 ] || { cat rs274.err >&2; fail "rs274 exited $rc"; }
    if grep -v '^executing$' rs274.err | grep -q .; then cat rs274.err >&2; fail "rs274 reported errors"; fi
    grep -q 'PROGRAM_END()' db.canon || fail "rs274 never reached PROGRAM_END"
    probes=$(grep -c 'STRAIGHT_PROBE(' db.canon)
    [ "$probes" -eq 180 ] || fail "rs274: $probes probe moves, expected 180"
    echo "rs274 clean, $probes probe moves"
  elif [ "${TPCAL_ALLOW_NO_RS274:-0}" = 1 ]; then
    echo "note: rs274 not installed, LinuxCNC run skipped (TPCAL_ALLOW_NO_RS274=1)"
  else
    fail "LinuxCNC's rs274 is not installed (apt-get install --no-install-recommends linuxcnc-uspace)"
  fi
  # The plan is what an error-free machine reads: identified, every error is 0 within 4 u (u from
  # the plan's 0.1 um rounding) + 0.001 for the printed digits.
  "$TPCAL" -q identify plan_linuxcnc.csv --instrument datum_ball > identify.txt 2> identify.err ||
    { cat identify.err >&2; fail "identify exited $?"; }
  n=$(grep -c '^  E_' identify.txt)
  [ "$n" -eq 11 ] || { cat identify.txt >&2; fail "identify: $n errors, expected 11"; }
  bad=$(awk '/^  E_/ { v = $2 < 0 ? -$2 : $2; if (v > 4 * $4 + 0.001) print }' identify.txt)
  [ -z "$bad" ] || fail "identify: an error of the plan is not zero: $bad"
  echo "PASS plan"
  ;;
bad_input)
  expect_bad() {  # expect_bad PATTERN ARGS...: exit 2, stderr matches PATTERN, nothing written
    pattern=$1
    shift
    "$TPCAL" -q plan "$@" > out.txt 2> err.txt
    rc=$?
    [ $rc -eq 2 ] || fail "exit $rc (expected 2) for: $*"
    grep -Eq "$pattern" err.txt || { cat err.txt >&2; fail "stderr does not match '$pattern' for: $*"; }
    left=$(ls | grep -v '^out.txt$\|^err.txt$\|^cfg_' || true)
    [ -z "$left" ] || fail "files written on bad input ($left) for: $*"
    echo "ok: $(head -n 1 err.txt | cut -c1-150)"
  }
  expect_bad '^tpcal plan: --ball: expected x,y,z' --instrument datum_ball --ball 200,0 -o p.csv --nc p.ngc
  expect_bad '^tpcal plan: --c-step-deg' --instrument datum_ball --c-step-deg 0 -o p.csv
  expect_bad '^tpcal plan: --dialect: needed for --nc p\.txt' --instrument datum_ball -o p.csv --nc p.txt
  expect_bad '^tpcal plan: --dialect: expected fanuc' --instrument datum_ball -o p.csv --nc p.nc --dialect okuma
  expect_bad '^tpcal plan: --testpiece is for test pieces' --instrument datum_ball --testpiece iso10791_m2 -o p.csv
  expect_bad '^tpcal plan: --nc needs --instrument datum_ball' --testpiece iso10791_m2 -o p.csv --nc p.ngc
  expect_bad '^tpcal plan: --testpiece NAME \(or --instrument datum_ball, probe_artifacts or ballbar\) is required' -o p.csv
  expect_bad 'datum-ball plan: machine type xyz' --instrument datum_ball --machine "$SRC/samples/machines/xyz.yaml" -o p.csv
  # A ball beyond the X stroke of the sample B/C table: the program's stroke check names the
  # block, and neither the plan nor the program is written.
  expect_bad "^p\.ngc: .*N[0-9]+: rapid target outside the machine's travel" --instrument datum_ball \
    --machine "$SRC/samples/machines/bc_table.yaml" --ball 600,0,300 -o p.csv --nc p.ngc
  expect_bad "^no_such_dir/p\.ngc: cannot write here" --instrument datum_ball -o p.csv --nc no_such_dir/p.ngc
  expect_bad "^tpcal plan: .*--nc.*same file|same file" --instrument datum_ball -o p.ngc --nc p.ngc
  echo "PASS bad_input"
  ;;
*)
  fail "unknown mode $MODE"
  ;;
esac
