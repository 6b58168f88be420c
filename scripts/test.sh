#!/usr/bin/env bash
# Builds tpcal and runs every test: a Release build with the full CTest suite, then the unit
# tests once more under AddressSanitizer + UndefinedBehaviorSanitizer (clang) and every reader's
# libFuzzer target for 20 s. README command 2; CI runs it.
# Both builds are unity builds (cmake/tpcal.cmake, TPCAL_UNITY_BUILD): each target's sources are
# compiled in batches, so the Eigen/Ceres/CGAL headers and templates are compiled once per batch.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
stage() { echo "tpcal test.sh: $1 ($(date -u +%H:%M:%S))"; }

# Both builds use clang: GCC 12 spends most of its compile of the Eigen-heavy files in its own type
# lookup (get_qualified_type, perf), 1812 s of CPU for the Release build against clang's 1062 s
# (2026-11-30, 2 cores); the tests and the sample outputs are the same under both (README, "Tests").
stage "Release build"
cmake -S . -B build -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
  -DCMAKE_BUILD_TYPE=Release -DTPCAL_WERROR=ON -DTPCAL_UNITY_BUILD=ON
cmake --build build -j "$JOBS"
stage "Release tests"
ctest --test-dir build --output-on-failure -j "$JOBS" --timeout 900

# Sanitizers: the unit-test binaries only (label "unit"), no benchmarks, CLI or studies, and the
# libFuzzer target of every reader, from one clang build (its objects carry libFuzzer's coverage
# too: cmake/tpcal.cmake, TPCAL_LIBFUZZER). -O1 with line tables: the tests run several times faster
# than at -O0 (Eigen is not inlined at -O0), which more than pays for the slower compile.
stage "sanitizer build"
cmake -S . -B build-asan -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DTPCAL_SANITIZE=ON -DTPCAL_BUILD_BENCH=OFF -DTPCAL_UNITY_BUILD=ON -DTPCAL_TEST_SHARDS=4
cmake --build build-asan -j "$JOBS" --target core_tests fitting_tests gdt_tests kinematics_tests testpieces_tests \
  gcode_tests io_tests diagnosis_tests report_tests pipeline_tests fuzz_targets
# Leaks inside OpenCASCADE's own libraries are suppressed (tests/sanitizers/lsan.supp says why).
# Each unit-test binary runs as 4 gtest shards (TPCAL_TEST_SHARDS, cmake/tpcal.cmake: a process
# per test cost more than most tests), without the long unit tests of tests/sanitizers/long_tests.txt
# (studies of many simulated pieces, the 100-file batch): they ran in the Release stage above, and
# here their code paths are covered by the short tests of the same suites. A failing shard's output
# names its test.
stage "sanitizer tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
LSAN_OPTIONS=suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$JOBS" -L unit --timeout 1200
# Every reader's libFuzzer target for FUZZ_SECONDS (20) from its seed corpus: a new reader cannot
# land unfuzzed (README, "Fuzzing"). Findings fail the run; reproducers stay in build-asan/fuzz-smoke.
# A fixed seed: a run's mutations are repeatable (the number of runs in 20 s still varies).
stage "fuzz smoke"
FUZZ_BUILD=$PWD/build-asan FUZZ_JOBS="$JOBS" FUZZ_PARALLEL="$JOBS" FUZZ_SEED="${FUZZ_SEED:-1}" scripts/fuzz_smoke.sh
stage "done"
echo "tpcal: all tests passed (Release + ASan/UBSan + fuzz smoke)"
