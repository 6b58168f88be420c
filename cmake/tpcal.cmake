# Helpers: one library per folder, one test executable per folder (README, "Layers").

function(tpcal_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    # GCC 12 reports -Wrestrict on inlined std::string operator+ (GCC bug 105329), a false
    # positive that breaks -Werror builds at random call sites.
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(TPCAL_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Unity builds (scripts/test.sh turns them on): the .cc files of each target compiled in batches
# of TPCAL_UNITY_BATCH, so the Eigen/Ceres/CGAL/PCL headers are parsed and their templates
# instantiated once per batch instead of once per file. File-local names must then be unique
# within a target. Most targets are one batch: their cost is the headers each batch parses again
# (measured 2026-11-28, Release, one core, batch 8 -> one batch: diagnosis 89.6 -> 24.8 s, io 43.0
# -> 32.7 s, report 27.1 -> 19.6 s). The template-heavy targets (tpcal_unity_heavy) keep batches
# of TPCAL_UNITY_BATCH_HEAVY: fitting as one batch under ASan at -O1 took 520 s and 7.7 GB against
# 563 s in three batches, no gain for a single job on the critical path.
option(TPCAL_UNITY_BUILD "Compile each target's sources in unity batches" OFF)
set(TPCAL_UNITY_BATCH 48 CACHE STRING "Source files per unity batch")
set(TPCAL_UNITY_BATCH_HEAVY 8 CACHE STRING "Source files per unity batch of the template-heavy targets")
if(TPCAL_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE ${TPCAL_UNITY_BATCH})
endif()

# tpcal_unity_heavy(TARGET...): those targets in batches of TPCAL_UNITY_BATCH_HEAVY.
function(tpcal_unity_heavy)
  foreach(target ${ARGN})
    if(TARGET ${target})
      set_target_properties(${target} PROPERTIES UNITY_BUILD_BATCH_SIZE ${TPCAL_UNITY_BATCH_HEAVY})
    endif()
  endforeach()
endfunction()

# Fuzzing (README, "Fuzzing"): every target instrumented for libFuzzer's coverage and checked by
# ASan/UBSan; the fuzz_* executables under tests/fuzz link libFuzzer's main.
if(TPCAL_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "TPCAL_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang)")
  endif()
  # -O1 and line tables (enough for the findings' stack traces) compile far faster than
  # RelWithDebInfo's -O2 -g on the Eigen/CGAL/Ceres code the readers link.
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined -O1 -gline-tables-only)
  add_link_options(-fsanitize=address,undefined)
endif()

# UBSan's null and alignment checks are left out: they doubled the compile of the Eigen-heavy files
# (measured 2026-11-28, -O1 -g1: fitting/circle_fit.cc 105 -> 57 s, kinematics/identification.cc
# 68 -> 48 s) while a null dereference still stops ASan (SEGV) and Eigen's own alignment assertion
# is on in this build (no NDEBUG).
if(TPCAL_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize=null,alignment -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# TPCAL_LIBFUZZER: the fuzz_* targets link libFuzzer's main (tests/fuzz). With TPCAL_FUZZ, and in a
# clang sanitizer build (scripts/test.sh): there the same objects serve the unit tests and the fuzz
# smoke run, so a new reader cannot land unfuzzed without a second build of every layer.
set(TPCAL_LIBFUZZER OFF)
if(TPCAL_FUZZ)
  set(TPCAL_LIBFUZZER ON)
elseif(TPCAL_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  set(TPCAL_LIBFUZZER ON)
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# tpcal_add_library(NAME [DEPS public targets...] [PRIVATE_DEPS targets...])
# Sources: every NAME/*.cc that is not a *_test.cc. Public headers: NAME/*.h, included as "NAME/x.h".
function(tpcal_add_library name)
  cmake_parse_arguments(ARG "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cc)
  list(FILTER srcs EXCLUDE REGEX "(_test|_main)\\.cc$")
  if(NOT srcs)  # a layer whose sources are not written yet: headers only
    add_library(tpcal_${name} INTERFACE)
    add_library(tpcal::${name} ALIAS tpcal_${name})
    target_include_directories(tpcal_${name} INTERFACE ${PROJECT_SOURCE_DIR})
    target_link_libraries(tpcal_${name} INTERFACE ${ARG_DEPS})
    return()
  endif()
  add_library(tpcal_${name} STATIC ${srcs})
  add_library(tpcal::${name} ALIAS tpcal_${name})
  target_include_directories(tpcal_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(tpcal_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  tpcal_warnings(tpcal_${name})
  if(TPCAL_FUZZ AND name STREQUAL "fitting")
    # No reader and no fuzz target runs its code (it is only linked): -O0 halves the fuzz build.
    target_compile_options(tpcal_${name} PRIVATE -O0)
  endif()
endfunction()

# tpcal_add_tests(NAME [DEPS targets...]): NAME/*_test.cc into one gtest binary NAME_tests,
# registered with CTest as NAME/<Suite>.<Test> via gtest_discover_tests.
function(tpcal_add_tests name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc)
  if(NOT srcs)
    return()
  endif()
  add_executable(${name}_tests ${srcs})
  target_link_libraries(${name}_tests PRIVATE tpcal::${name} ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  target_compile_definitions(${name}_tests PRIVATE TPCAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  tpcal_warnings(${name}_tests)
  if(TPCAL_TEST_SHARDS GREATER 0)
    tpcal_add_test_shards(${name})
    return()
  endif()
  include(GoogleTest)
  gtest_discover_tests(${name}_tests TEST_PREFIX "${name}/" DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS "unit;${name}")
endfunction()

# TPCAL_TEST_SHARDS=N (the sanitizer stage of scripts/test.sh): each unit-test binary runs as N CTest
# tests NAME/shardI (gtest's own sharding) without the long tests of tests/sanitizers/long_tests.txt,
# instead of one process per test. Loading a binary costs more than most of its tests: under ASan
# pipeline_tests took 0.67 s to start and io_tests 0.39 s with 186 shared libraries, pipeline_tests
# 0.53 s with --as-needed's 118 (hyperfine, 2026-12-02), and 704 of the stage's 755 tests took
# under 2 s each, 385 s of its 748.
set(TPCAL_TEST_SHARDS 0 CACHE STRING "Run each unit-test binary as this many gtest shards (0: one CTest test per test)")
set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/tests/sanitizers/long_tests.txt ${PROJECT_SOURCE_DIR}/tests/sanitizers/binary_seconds.txt)

function(tpcal_add_test_shards name)
  file(STRINGS ${PROJECT_SOURCE_DIR}/tests/sanitizers/long_tests.txt long REGEX "^${name}/")
  list(TRANSFORM long REPLACE "^${name}/" "")
  list(JOIN long ":" skip)
  set(filter "*")
  if(skip)
    set(filter "*-${skip}")
  endif()
  # The slowest binaries' shards first (tests/sanitizers/binary_seconds.txt says why).
  file(STRINGS ${PROJECT_SOURCE_DIR}/tests/sanitizers/binary_seconds.txt seconds REGEX "^${name} +[0-9]+$")
  list(TRANSFORM seconds REPLACE "^${name} +" "")
  if(NOT seconds)
    set(seconds 0)
  endif()
  math(EXPR last "${TPCAL_TEST_SHARDS} - 1")
  foreach(i RANGE ${last})
    add_test(NAME ${name}/shard${i} COMMAND ${name}_tests --gtest_filter=${filter})
    set_tests_properties(${name}/shard${i} PROPERTIES LABELS "unit;${name}" COST ${seconds}
      ENVIRONMENT "GTEST_TOTAL_SHARDS=${TPCAL_TEST_SHARDS};GTEST_SHARD_INDEX=${i}")
  endforeach()
endfunction()
