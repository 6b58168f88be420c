# CTest driver of `tpcal diagnose` (pipeline/CMakeLists.txt, "diagnose CLI tests").
# -DTPCAL=<exe> -DPOINTS=<file> -DOUT=<json> -DEXPECT_FAMILY=<family> | -DEXPECT_EXIT=<code>
# Runs the command, checks the exit code, and for a successful run the tpcal.diagnosis/1 JSON:
# schema, the required keys of contracts README section 4 and the verdict family.
file(REMOVE "${OUT}")
execute_process(COMMAND "${TPCAL}" diagnose "${POINTS}" --json "${OUT}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(DEFINED EXPECT_EXIT)
  if(NOT rc EQUAL EXPECT_EXIT)
    message(FATAL_ERROR "exit code ${rc}, expected ${EXPECT_EXIT}\n${err}")
  endif()
  if(NOT rc EQUAL 0 AND EXISTS "${OUT}")
    message(FATAL_ERROR "a failed run left ${OUT} behind")
  endif()
  return()
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tpcal diagnose failed (${rc}):\n${err}")
endif()
file(READ "${OUT}" json)
string(JSON schema GET "${json}" schema)
if(NOT schema STREQUAL "tpcal.diagnosis/1")
  message(FATAL_ERROR "schema '${schema}'")
endif()
foreach(path "base_model" "gap;rms_um" "gap;max_abs_um" "gap;n_points" "gap;by_feature;0;feature"
        "candidates;0;family" "candidates;0;name" "candidates;0;rms_after_um" "candidates;0;shrink_pct"
        "candidates;0;cv_rms_before_um" "candidates;0;cv_rms_after_um" "candidates;0;parameters"
        "verdict;family" "verdict;name" "verdict;shrink_pct" "verdict;indistinguishable_from")
  string(JSON v ERROR_VARIABLE e GET "${json}" ${path})
  if(e)
    message(FATAL_ERROR "missing key ${path}: ${e}")
  endif()
endforeach()
string(JSON family GET "${json}" verdict family)
if(NOT family STREQUAL EXPECT_FAMILY)
  message(FATAL_ERROR "verdict ${family}, expected ${EXPECT_FAMILY}\n${out}")
endif()
