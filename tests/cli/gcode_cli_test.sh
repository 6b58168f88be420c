#!/bin/sh
# CTest driver for `tpcal gcode` (pipeline/CMakeLists.txt, "# gcode CLI tests").
#   gcode_cli_test.sh TPCAL WORKDIR rs274       every piece in the LinuxCNC dialect, run through
#                                               LinuxCNC's interpreter `rs274 -g P -t P.tbl`;
#                                               fails on any interpreter error; then the effective
#                                               configuration written beside P reproduces P
#   gcode_cli_test.sh TPCAL WORKDIR bad_input   bad input: exit 2, "file[:line]: message", nothing written
# rs274 exits 0 on errors with `-n 0` (not used here) and prints errors to stderr; it keeps its
# tool data in $HOME/.tool.mmap, so every run gets its own HOME (parallel runs collide otherwise).
set -u
TPCAL=$1
WORK=$2
MODE=$3
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$WORK" && mkdir -p "$WORK" || fail "cannot create $WORK"
cd "$WORK" || fail "cannot enter $WORK"

case "$MODE" in
rs274)
  RS274=$(command -v rs274 || true)
  [ -n "$RS274" ] || fail "LinuxCNC's rs274 is not installed (apt-get install --no-install-recommends linuxcnc-uspace)"
  for piece in turning turning_enriched iso10791_m1_160 iso10791_m1_320 iso10791_m2 cone_frustum cone_frustum_enriched; do
    skip=""
    # Known defect of testpieces/turning_piece.cc: the insert retracts by rapids through the
    # uncut S_i stock after each facing pass; the safety check rejects it (gcode/safety_test.cc).
    [ "${piece%_enriched}" = turning ] && skip="--skip-check rapids"
    prog="$piece.ngc"
    # shellcheck disable=SC2086
    "$TPCAL" -q gcode --testpiece "$piece" --dialect linuxcnc -o "$prog" --svg "$piece.svg" --date 2025-01-01 $skip \
      2> "$piece.tpcal.err" || { cat "$piece.tpcal.err" >&2; fail "tpcal gcode $piece exited $?"; }
    for f in "$prog" "$prog.tbl" "$piece.svg" "$prog.testpiece.yaml" "$prog.post.yaml"; do
      [ -s "$f" ] || fail "$piece: $f not written"
    done
    mkdir -p "home_$piece"
    HOME="$WORK/home_$piece" "$RS274" -g "$prog" -t "$prog.tbl" > "$piece.canon" 2> "$piece.rs274.err" < /dev/null
    rc=$?
    [ $rc -eq 0 ] || { cat "$piece.rs274.err" >&2; fail "$piece: rs274 exited $rc"; }
    if grep -v '^executing$' "$piece.rs274.err" | grep -q .; then
      cat "$piece.rs274.err" >&2
      fail "$piece: rs274 reported errors"
    fi
    grep -q 'PROGRAM_END()' "$piece.canon" || fail "$piece: rs274 never reached PROGRAM_END"
    feeds=$(grep -c 'STRAIGHT_FEED\|ARC_FEED' "$piece.canon")
    [ "$feeds" -gt 0 ] || fail "$piece: no feed moves in the canonical output"
    echo "$piece: rs274 clean, $feeds feed moves"

    # The effective configuration reproduces the program byte for byte.
    # shellcheck disable=SC2086
    "$TPCAL" -q gcode --testpiece "$piece" --config "$prog.testpiece.yaml" --post "$prog.post.yaml" \
      --dialect linuxcnc -o "again_$prog" --date 2025-01-01 --no-effective-config $skip 2> /dev/null ||
      fail "$piece: rerun from the effective configuration failed"
    # Only the program name (from the output stem) and the table name differ.
    sed "s/AGAIN_//g; s/again_//g" "again_$prog" | cmp -s - "$prog" ||
      fail "$piece: the effective configuration does not reproduce $prog"
  done
  ;;
bad_input)
  expect_bad() {  # expect_bad PATTERN ARGS...: exit 2, stderr matches PATTERN, nothing written
    pattern=$1
    shift
    "$TPCAL" -q gcode "$@" > out.txt 2> err.txt
    rc=$?
    [ $rc -eq 2 ] || fail "exit $rc (expected 2) for: $*"
    grep -Eq "$pattern" err.txt || { cat err.txt >&2; fail "stderr does not match '$pattern' for: $*"; }
    left=$(ls | grep -v '^out.txt$\|^err.txt$\|^cfg_\|^post_' || true)
    [ -z "$left" ] || fail "files written on bad input ($left) for: $*"
    echo "ok: $(head -n 1 err.txt | cut -c1-150)"
  }
  # A safety violation names the block; nothing written. The only one a valid configuration
  # reaches today is the known turning retract through the S_i stock (testpieces validates tool
  # sizes and strokes before gcode sees the piece); once testpieces is fixed this case says so
  # and is skipped (a machine file with short strokes fails earlier, in the piece's IK).
  if "$TPCAL" -q gcode --testpiece turning --dialect linuxcnc -o fixed.ngc --no-effective-config 2> /dev/null; then
    echo "note: the turning program passes the rapid check now (testpieces fixed): drop this case"
    rm -f fixed.ngc fixed.ngc.tbl
  else
    expect_bad '^p\.ngc: N[0-9]+: rapid move enters the stock envelope' --testpiece turning --dialect linuxcnc -o p.ngc
  fi
  printf 'schema: tpcal.machine/1\nname: short X\ntype: xyz\nworkpiece_chain: [Y, X]\ntool_chain: [Z]\naxes:\n  X: {min_mm: -50, max_mm: 50}\n  Y: {min_mm: -200, max_mm: 200}\n  Z: {min_mm: -10, max_mm: 500}\n' > cfg_short_x.yaml
  expect_bad '^cfg_short_x\.yaml: .*axis X at -?[0-9.]+ mm is outside its stroke' --testpiece iso10791_m2 \
    --machine cfg_short_x.yaml --dialect linuxcnc -o p.ngc
  expect_bad 'unknown test piece .square.' --testpiece square --dialect fanuc -o p.nc
  expect_bad '^tpcal gcode: --dialect: expected fanuc, linuxcnc, sinumerik or heidenhain' \
    --testpiece iso10791_m2 --dialect haas -o p.nc
  # A test-piece configuration with a bad value: file:line.
  printf 'schema: tpcal.testpiece/1\npiece: iso10791_m2\niso10791_m2:\n  size_mmm: 3\n' > cfg_typo.yaml
  expect_bad '^cfg_typo\.yaml:4: ' --testpiece iso10791_m2 --config cfg_typo.yaml --dialect fanuc -o p.nc
  # A configuration for another piece.
  printf 'schema: tpcal.testpiece/1\npiece: cone_frustum\n' > cfg_cone.yaml
  expect_bad '^cfg_cone\.yaml: piece: the configuration is for the cone_frustum piece' \
    --testpiece iso10791_m2 --config cfg_cone.yaml --dialect fanuc -o p.nc
  # Post options for another control, and an unknown post key with its line.
  printf 'schema: tpcal.gcode/1\ndialect: heidenhain\n' > post_h.yaml
  expect_bad '^post_h\.yaml: dialect: the post options are for heidenhain' \
    --testpiece iso10791_m2 --post post_h.yaml --dialect fanuc -o p.nc
  printf 'schema: tpcal.gcode/1\ndialect: fanuc\nblock_stepp: 5\n' > post_typo.yaml
  expect_bad '^post_typo\.yaml:3: ' --testpiece iso10791_m2 --post post_typo.yaml --dialect fanuc -o p.nc
  printf 'schema: tpcal.gcode/1\ndialect: fanuc\ntools:\n  - {piece_tool: 2, number: 7}\n' > post_tools.yaml
  expect_bad '^post_tools\.yaml: tools: piece tool 2 is not used' \
    --testpiece iso10791_m2 --post post_tools.yaml --dialect fanuc -o p.nc
  # An output directory that does not exist: found before the program is written.
  expect_bad "^no_such_dir/p\.svg: cannot write here" --testpiece iso10791_m2 --dialect fanuc -o p.nc --svg no_such_dir/p.svg
  expect_bad '^tpcal gcode: --skip-check: expected strokes, rapids or tool_fit' \
    --testpiece iso10791_m2 --dialect fanuc -o p.nc --skip-check everything
  expect_bad '^tpcal gcode: --date: expected YYYY-MM-DD' --testpiece iso10791_m2 --dialect fanuc -o p.nc --date today
  ;;
*)
  fail "unknown mode $MODE"
  ;;
esac
echo "PASS"
