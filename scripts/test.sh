#!/usr/bin/env bash
# Builds tpcal and runs every test: a Release build with the full CTest suite, then the unit
# tests once more under AddressSanitizer + UndefinedBehaviorSanitizer. README command 2; CI runs it.
# Both builds are unity builds (cmake/tpcal.cmake, TPCAL_UNITY_BUILD): each target's sources are
# compiled in batches, so the Eigen/Ceres/CGAL headers and templates are compiled once per batch.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
stage() { echo "tpcal test.sh: $1 ($(date -u +%H:%M:%S))"; }

stage "Release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTPCAL_WERROR=ON -DTPCAL_UNITY_BUILD=ON
cmake --build build -j "$JOBS"
stage "Release tests"
ctest --test-dir build --output-on-failure -j "$JOBS" --timeout 900

# Sanitizers: the unit-test binaries only (label "unit"), no benchmarks, CLI or studies. -O1 with
# line tables: the tests run several times faster than at -O0 (Eigen is not inlined at -O0), which
# more than pays for the slower compile.
stage "sanitizer build"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DTPCAL_SANITIZE=ON -DTPCAL_BUILD_BENCH=OFF -DTPCAL_UNITY_BUILD=ON
cmake --build build-asan -j "$JOBS" --target core_tests fitting_tests gdt_tests kinematics_tests testpieces_tests \
  gcode_tests io_tests diagnosis_tests report_tests pipeline_tests
# Leaks inside OpenCASCADE's own libraries are suppressed (tests/sanitizers/lsan.supp says why).
# The long unit tests of tests/sanitizers/long_tests.txt (studies of many simulated pieces, the
# 100-file batch) ran in the Release stage above; here their code paths are covered by the
# short tests of the same suites.
stage "sanitizer tests"
LONG_TESTS=$(grep -v '^#' tests/sanitizers/long_tests.txt | grep -v '^[[:space:]]*$' | paste -sd'|')
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
LSAN_OPTIONS=suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$JOBS" -L unit -E "$LONG_TESTS" --timeout 1200
stage "done"
echo "tpcal: all tests passed (Release + ASan/UBSan)"
