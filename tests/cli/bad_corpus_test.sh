#!/bin/sh
# The bad-input corpus (tests/data/bad/, README "Fuzzing"): every file there, and the hostile
# inputs made here (a FIFO, a 1 GB line, 10^7 columns), must make tpcal exit 2 within 30 s with
# exactly the expected `file:line: what was expected` on stderr, and write nothing.
# tests/data/bad/cases.tsv: FILE <tab> ARGS <tab> EXPECTED STDERR, where @F is the bad file,
# @O an output path that must not appear, @S the source tree; FILE `-`: an option is at fault.
# Usage: bad_corpus_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
BAD=$SRC/tests/data/bad
rm -rf "$WORK"; mkdir -p "$WORK"
failures=0; cases=0

# check FILE EXPECTED ARGS...: ARGS with @F/@O/@S replaced run tpcal.
check() {
  file=$1; expected=$2; shift 2
  cases=$((cases + 1))
  out=$WORK/out
  rm -rf "$out"
  set --  $(printf '%s\n' "$@" | sed "s|@F|$file|g; s|@O|$out|g; s|@S|$SRC|g")
  want=$(printf '%s' "$expected" | sed "s|@F|$file|g; s|@S|$SRC|g")
  set +e
  timeout 30 "$TPCAL" -q "$@" > "$WORK/stdout.txt" 2> "$WORK/stderr.txt"
  rc=$?
  set -e
  got=$(cat "$WORK/stderr.txt")
  if [ $rc -ne 2 ]; then
    echo "FAIL $(basename "$file"): exit $rc (expected 2): $got" >&2; failures=$((failures + 1))
  elif [ "$got" != "$want" ]; then
    printf 'FAIL %s:\n  expected: %s\n  got:      %s\n' "$(basename "$file")" "$want" "$got" >&2
    failures=$((failures + 1))
  elif [ -e "$out" ] || [ -s "$WORK/stdout.txt" ]; then
    echo "FAIL $(basename "$file"): wrote output" >&2; failures=$((failures + 1))
  fi
}

# The table: one case per line (tabs separate the three columns).
tab=$(printf '\t')
while IFS="$tab" read -r name args expected; do
  case $name in ''|'#'*) continue ;; esac
  if [ "$name" = - ]; then
    # shellcheck disable=SC2086
    check - "$expected" $args
    continue
  fi
  test -e "$BAD/$name" || { echo "FAIL: $name is in cases.tsv but not in tests/data/bad" >&2; failures=$((failures + 1)); continue; }
  # shellcheck disable=SC2086
  check "$BAD/$name" "$expected" $args
done < "$BAD/cases.tsv"
for f in "$BAD"/*; do
  n=$(basename "$f")
  [ "$n" = cases.tsv ] && continue
  grep -q "^$n$tab" "$BAD/cases.tsv" || { echo "FAIL: tests/data/bad/$n has no line in cases.tsv" >&2; failures=$((failures + 1)); }
done

# Hostile inputs made here (too large, or not files, to keep in the tree).
mkfifo "$WORK/fifo.csv"
check "$WORK/fifo.csv" "@F: not a regular file" fit @F --json @O
mkfifo "$WORK/fifo.yaml"
check "$WORK/fifo.yaml" "@F: not a regular file" fit @S/samples/turning/cmm_points.csv --plan @F --json @O
check "$WORK/fifo.yaml" "@F: not a regular file" run @F --out @O
truncate -s 1G "$WORK/one_line.csv"   # 1 GiB of NUL bytes, no line end (sparse: no disk used)
check "$WORK/one_line.csv" "@F:1: line longer than 1048576 bytes; expected at most 1048576 bytes per line" fit @F --json @O
{ printf 'feature,x,y,z'; head -c 10000000 /dev/zero | tr '\0' ','; printf '\nP1,1,2,3\n'; } > "$WORK/columns.csv"
check "$WORK/columns.csv" "@F:1: line longer than 1048576 bytes; expected at most 1048576 bytes per line" fit @F --json @O
rm -f "$WORK/one_line.csv" "$WORK/columns.csv"

echo "bad corpus: $cases cases, $failures failed"
test $failures -eq 0
