#!/usr/bin/env bash
# Checks that every pattern of long_tests.txt still matches a test of its binary, so that a renamed
# long test is not silently run under the sanitizers. Usage (CTest, tests/CMakeLists.txt):
#   check_long_tests.sh LIST NAME=PATH_OF_NAME_tests...
# Exit 0 when each line matches; 1 with "LIST:LINE: why" for each one that does not.
set -u
list=$1
shift
declare -A exe names
for arg in "$@"; do exe[${arg%%=*}]=${arg#*=}; done
bad=0
n=0
while IFS= read -r line || [[ -n $line ]]; do
  n=$((n + 1))
  [[ -z $line || $line == \#* ]] && continue
  name=${line%%/*} pattern=${line#*/}
  if [[ -z ${exe[$name]:-} ]]; then
    echo "$list:$n: $line: no unit-test binary ${name}_tests is known"
    bad=1
    continue
  fi
  if [[ -z ${names[$name]:-} ]]; then  # Suite.Test per line, from gtest's two-level listing
    names[$name]=$("${exe[$name]}" --gtest_list_tests | awk '/^[^ ]/ {suite = $1} /^  / {print suite $1}')
  fi
  found=0
  while IFS= read -r test; do
    # shellcheck disable=SC2053  # the pattern is a glob on purpose: gtest's * and ?
    if [[ $test == $pattern ]]; then found=1; break; fi
  done <<< "${names[$name]}"
  if [[ $found == 0 ]]; then
    echo "$list:$n: $line: matches no test of ${name}_tests"
    bad=1
  fi
done < "$list"
exit $bad
