#!/bin/sh
# Every tpcal command the README shows runs as written on the bundled samples.
# Usage: readme_commands_test.sh TPCAL SOURCE_DIR WORK_DIR
#
# Reads SOURCE_DIR/README.md, takes every line of a ```sh fenced block (lines ending in `\` joined
# with the next; comment lines dropped; a trailing `# comment` cut off the way the shell does it,
# outside quotes and at the start of a word) that starts with `build/tpcal `, and runs it in order
# with `build/tpcal` replaced by TPCAL, each under `timeout 300`, from WORK_DIR (emptied first),
# where `samples`, `tests` and `docs` are symlinks to SOURCE_DIR's: relative inputs resolve,
# outputs land in WORK_DIR, and a later line may read what an earlier one wrote (as a reader would
# run them). A line must exit 0, or N when its trailing comment says so (`# exits N`, `# exit N`,
# `# exit code N`). A line that cannot run as written (a synopsis with placeholders) is skipped only
# by one of the named rules below, and every skipped line is listed with its rule; lines of the
# blocks that are not tpcal commands are listed too. A line piping tpcal into another command has
# the exit status of the last command (POSIX sh has no pipefail). POSIX sh; needs awk, timeout(1).
set -u

if [ $# -ne 3 ]; then
  echo "usage: $0 TPCAL SOURCE_DIR WORK_DIR" >&2
  exit 2
fi
abspath() { case $1 in /*) printf '%s\n' "$1" ;; *) printf '%s\n' "$(pwd)/$1" ;; esac; }
TPCAL=$(abspath "$1"); SRC=$(abspath "$2"); WORK=$(abspath "$3")
README=$SRC/README.md
TIMEOUT_S=300
# `tpcal diagnose --validate` simulates and diagnoses every family x magnitude x noise level
# --trials times (default 2): minutes. It runs here only with --trials at most this.
VALIDATE_MAX_TRIALS=1
# Example inputs the README names for the reader's own data; none is bundled. A line naming one is
# skipped (rule example-input) unless an earlier README line has created it in WORK_DIR.
EXAMPLE_INPUTS="cmm.csv scan.ply 'lab/*.csv'"
# Flags whose value a command writes: an example name there is an output, not a placeholder.
OUTPUT_FLAGS="-o --out --json --html --svg --step --markdown"

test -f "$README" || { echo "readme_commands: no README at $README" >&2; exit 1; }
test -x "$TPCAL" || { echo "readme_commands: $TPCAL is not an executable" >&2; exit 1; }
command -v timeout > /dev/null || { echo "readme_commands: timeout(1) not found" >&2; exit 1; }

rm -rf "$WORK"
mkdir -p "$WORK" || exit 1
for d in samples tests docs; do ln -s "$SRC/$d" "$WORK/$d" || exit 1; done
LOGS=$WORK/.readme_commands      # per-line stdout/stderr: LOGS/<n>.out, LOGS/<n>.err
mkdir -p "$LOGS" || exit 1
: > "$LOGS/stamp"
US=$(printf '\037')              # field separator of the extracted lines (never in a command)

# --- extraction --------------------------------------------------------------------------------
# One record per shell line of a ```sh block: kind (cmd: starts with build/tpcal; other), README
# line number of its first physical line, the command without its comment, the comment.
awk -v US="$US" '
function split_comment(s,   i, n, c, q, prev) {
  q = ""; prev = " "; n = length(s)
  for (i = 1; i <= n; i++) {
    c = substr(s, i, 1)
    if (q == "") {
      if (c == "\\") { i++; prev = "x"; continue }
      if (c == "\047" || c == "\"") q = c
      else if (c == "#" && prev == " ") { CMD = substr(s, 1, i - 1); COMMENT = substr(s, i + 1); return }
    } else if (c == q) q = ""
    else if (q == "\"" && c == "\\") i++
    prev = c
  }
  CMD = s; COMMENT = ""
}
function emit(   kind) {
  split_comment(pend); pend = ""
  sub(/ +$/, "", CMD); sub(/^ +/, "", COMMENT); sub(/ +$/, "", COMMENT)
  if (CMD == "") return
  kind = (CMD ~ /^build\/tpcal( |$)/) ? "cmd" : "other"
  print kind US pline US CMD US COMMENT
}
BEGIN { inblk = 0; pend = "" }
/^[ \t]*```/ {
  if (inblk) { if (pend != "") emit(); inblk = 0 }
  else if ($0 ~ /^[ \t]*```sh[ \t]*$/) inblk = 1
  next
}
!inblk { next }
{
  line = $0; gsub(/\t/, " ", line); sub(/^ +/, "", line)
  if (pend == "") {
    if (line == "" || line ~ /^#/) next          # blank and comment lines
    pline = NR; pend = line
  } else pend = pend " " line
  if (pend ~ /\\$/) { sub(/ *\\$/, "", pend); next }   # continued on the next line
  emit()
}
END { if (pend != "") emit() }
' "$README" > "$LOGS/lines" || { echo "readme_commands: awk failed on $README" >&2; exit 1; }

# --- skip rules --------------------------------------------------------------------------------
# skip_rule CMD: prints "RULE: WORD" and succeeds when CMD cannot run as written. Rules, in order:
#   synopsis-optional     a word starting with `[`: an optional part of a synopsis ([--seed N])
#   synopsis-alternative  a `|` inside a word: alternatives (fanuc|linuxcnc); a `|` or `||` word
#                         alone is a real pipe or or-list and runs
#   synopsis-ellipsis     a word containing `...`: "more of the same"
#   placeholder-word      a word (or the value of --flag=VALUE) made only of upper-case letters
#                         and _ = @ , (DIR, N, NAME, POINTS, OUT, F=KIND, FEATURE@X,Y,Z); real
#                         upper-case names carry a digit or an extension (M1.nc, H1@120,-80,40)
#   placeholder-file      an input-type file (.yaml .yml .csv .ply .pcd .xyz .txt) whose name
#                         before the extension is only upper-case letters and _ (M.yaml, E.yaml,
#                         T.yaml, TP.yaml, PIPELINE.yaml, POST.yaml, REF.csv): bundled files are
#                         lower-case
#   example-input         a word of EXAMPLE_INPUTS (cmm.csv, scan.ply, 'lab/*.csv'), not the value of
#                         one of OUTPUT_FLAGS, that no earlier README line has created in WORK_DIR
#   long-validate         diagnose --validate without --trials <= VALIDATE_MAX_TRIALS (minutes)
# A file the README names that is none of these and does not exist is not skipped: the line runs
# and fails, which is what this test is for.
UC=ABCDEFGHIJKLMNOPQRSTUVWXYZ
is_placeholder_word() {
  case $1 in
    *[!$UC=@,_]*) return 1 ;;
    *[$UC]*) return 0 ;;
  esac
  return 1
}
is_placeholder_file() {
  case $1 in
    *.yaml | *.yml | *.csv | *.ply | *.pcd | *.xyz | *.txt) ;;
    *) return 1 ;;
  esac
  _stem=${1##*/}; _stem=${_stem%.*}
  case $_stem in
    '' | *[!${UC}_]*) return 1 ;;
  esac
  return 0
}
example_input_missing() {
  _p=$(printf '%s\n' "$1" | tr -d "\"'")
  case $_p in
    *'*'* | *'?'*) test ! -d "$WORK/$(dirname "$_p")" ;;
    *) test ! -e "$WORK/$_p" ;;
  esac
}
skip_rule() {
  set -f
  _validate=0; _trials=; _prev=; _flag=
  for _w in $1; do
    case $_w in
      \[*) echo "synopsis-optional: $_w"; set +f; return 0 ;;
      '|' | '||') ;;
      *'|'*) echo "synopsis-alternative: $_w"; set +f; return 0 ;;
      *...*) echo "synopsis-ellipsis: $_w"; set +f; return 0 ;;
    esac
    case $_w in
      --validate) _validate=1 ;;
      --trials=*) _trials=${_w#--trials=} ;;
    esac
    test "$_prev" = --trials && _trials=$_w
    _flag=$_prev; _prev=$_w
    case $_w in
      -*=*) _v=${_w#*=}; _flag=${_w%%=*} ;;
      -*) continue ;;
      *) _v=$_w ;;
    esac
    if is_placeholder_word "$_v"; then echo "placeholder-word: $_w"; set +f; return 0; fi
    if is_placeholder_file "$_v"; then echo "placeholder-file: $_w"; set +f; return 0; fi
    case " $OUTPUT_FLAGS " in *" $_flag "*) continue ;; esac
    for _e in $EXAMPLE_INPUTS; do
      if [ "$_v" = "$_e" ] && example_input_missing "$_v"; then
        echo "example-input: $_w"; set +f; return 0
      fi
    done
  done
  set +f
  if [ $_validate = 1 ]; then
    case $_trials in
      '' | *[!0-9]*) echo "long-validate: --validate with --trials ${_trials:-2 (default)}"; return 0 ;;
    esac
    if [ "$_trials" -gt $VALIDATE_MAX_TRIALS ]; then
      echo "long-validate: --validate with --trials $_trials"; return 0
    fi
  fi
  return 1
}

# The exit code a line's comment announces ("# exits 2", "# exit 1 ...", "# exit code 2"), else 0.
expected_exit() {
  _x=$(printf '%s\n' "$1" | sed -n 's/.*[Ee][Xx][Ii][Tt][Ss]\{0,1\}\( code\)\{0,1\}[ :=]*\([0-9][0-9]*\).*/\2/p')
  echo "${_x:-0}"
}

# --- run ---------------------------------------------------------------------------------------
ran=0; skipped=0; failed=0; other=0; n=0
: > "$LOGS/skipped"; : > "$LOGS/other"; : > "$LOGS/failed"
echo "readme_commands: $README with $TPCAL in $WORK"
while IFS=$US read -r kind lineno cmd comment; do
  if [ "$kind" = other ]; then
    other=$((other + 1))
    echo "  README.md:$lineno: $cmd" >> "$LOGS/other"
    continue
  fi
  if reason=$(skip_rule "$cmd"); then
    skipped=$((skipped + 1))
    echo "  README.md:$lineno ($reason): $cmd" >> "$LOGS/skipped"
    continue
  fi
  n=$((n + 1)); ran=$((ran + 1))
  want=$(expected_exit "$comment")
  rest=${cmd#build/tpcal}
  start=$(date +%s)
  (cd "$WORK" && TPCAL="$TPCAL" timeout $TIMEOUT_S sh -c "\"\$TPCAL\"$rest") \
    < /dev/null > "$LOGS/$n.out" 2> "$LOGS/$n.err"
  rc=$?
  secs=$(($(date +%s) - start))
  if [ $rc -eq "$want" ]; then
    echo "ok    README.md:$lineno (exit $rc, ${secs} s): $cmd"
  else
    failed=$((failed + 1))
    echo "  README.md:$lineno: $cmd" >> "$LOGS/failed"
    if [ $rc -eq 124 ]; then what="timed out after $TIMEOUT_S s"; else what="exit $rc, expected $want"; fi
    echo "FAIL  README.md:$lineno ($what, ${secs} s): $cmd"
    echo "      stderr ($LOGS/$n.err):"
    sed -n '1,60s/^/      | /p' "$LOGS/$n.err"
    test "$(wc -l < "$LOGS/$n.err")" -gt 60 && echo "      | ... (truncated)"
  fi
done < "$LOGS/lines"

# Outputs belong in WORK_DIR: nothing may have been written into the source tree's data through
# the symlinks.
leaked=$(find "$SRC/samples/" "$SRC/docs/" -type f -newer "$LOGS/stamp" 2> /dev/null)
if [ -n "$leaked" ]; then
  failed=$((failed + 1))
  echo "FAIL  README commands wrote into SOURCE_DIR (outputs must land in WORK_DIR):"
  printf '%s\n' "$leaked" | sed 's/^/      | /'
  echo "  (files written into $SRC/samples or $SRC/docs, listed above)" >> "$LOGS/failed"
fi

echo "skipped ($skipped; cannot run as written, by rule):"
cat "$LOGS/skipped"
echo "not selected ($other; lines of the sh blocks that do not start with build/tpcal, not run here):"
cat "$LOGS/other"
if [ $failed -gt 0 ]; then
  echo "failed ($failed):"
  cat "$LOGS/failed"
fi
if [ $ran -eq 0 ]; then
  failed=$((failed + 1))
  echo "FAIL  no build/tpcal line ran: were the README's sh blocks moved or renamed?"
fi
echo "readme_commands: $ran ran, $skipped skipped, $failed failed"
test $failed -eq 0
