#!/bin/sh
# Faults while writing the output of `tpcal run`: a file-size limit (RLIMIT_FSIZE, the write
# fails with EFBIG as it would with ENOSPC on a full disk), a full file system (a 64 KiB tmpfs,
# where mounting is allowed) and a read-only output directory. Each is a clear error naming the
# path, exit 2, and leaves the previous run whole with no sibling of the failed one.
# Usage: run_faults_test.sh TPCAL SOURCE_DIR WORK_DIR
set -eu
TPCAL=$1; SRC=$2; WORK=$3
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { "$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --mc-trials 0 --out "$1"; }

expect_clean_failure() {  # DIR WHAT: exit 2, stderr names DIR's parent, previous run untouched
  dir=$1; what=$2
  test "$rc" -eq 2 || fail "$what: exit $rc, expected 2 ($(cat "$WORK/err.txt"))"
  grep -q "$(basename "$dir")" "$WORK/err.txt" || fail "$what: stderr does not name the output: $(cat "$WORK/err.txt")"
  test "$(cat "$dir/result.json")" = "$(cat "$WORK/previous.json")" || fail "$what: previous run changed"
  left=$(ls -a "$(dirname "$dir")" | grep -c "^$(basename "$dir")\.\(tmp\|old\)\." || true)
  test "$left" -eq 0 || fail "$what: $left sibling(s) left"
  echo "$what: $(head -c 200 "$WORK/err.txt")"
}

# 1. File-size limit: 8 blocks; SIGXFSZ ignored so that write(2) returns EFBIG.
run "$WORK/out" > /dev/null
cp "$WORK/out/result.json" "$WORK/previous.json"
set +e
(trap '' XFSZ; ulimit -f 8; exec "$TPCAL" -q run "$SRC/samples/pipelines/turning.yaml" --mc-trials 0 --seed 2 \
  --out "$WORK/out") > /dev/null 2> "$WORK/err.txt"
rc=$?
set -e
expect_clean_failure "$WORK/out" "file-size limit"

# 2 and 3 need a file system of their own: a tmpfs, where this user may mount one.
if mkdir -p "$WORK/tiny" && mount -t tmpfs -o size=64k tmpfs "$WORK/tiny" 2> /dev/null; then
  trap 'umount "$WORK/tiny" 2> /dev/null || true' EXIT
  mkdir "$WORK/tiny/out"
  printf '{"previous": true}\n' > "$WORK/tiny/out/result.json"
  cp "$WORK/tiny/out/result.json" "$WORK/previous.json"
  set +e; run "$WORK/tiny/out" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  expect_clean_failure "$WORK/tiny/out" "full file system"
  mount -o remount,ro "$WORK/tiny"
  set +e; run "$WORK/tiny/out" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  expect_clean_failure "$WORK/tiny/out" "read-only file system"
  umount "$WORK/tiny"; trap - EXIT
elif [ "$(id -u)" -ne 0 ]; then
  mkdir -p "$WORK/ro/out"; cp "$WORK/out/result.json" "$WORK/ro/out/"; cp "$WORK/out/result.json" "$WORK/previous.json"
  chmod 555 "$WORK/ro"
  set +e; run "$WORK/ro/out" > /dev/null 2> "$WORK/err.txt"; rc=$?; set -e
  chmod 755 "$WORK/ro"
  expect_clean_failure "$WORK/ro/out" "read-only directory"
else
  echo "full and read-only file systems: skipped (root without permission to mount a tmpfs)"
fi
echo "run_faults: ok"
