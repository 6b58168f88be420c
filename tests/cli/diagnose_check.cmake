# CTest driver of `tpcal diagnose` (pipeline/CMakeLists.txt, "diagnose CLI tests").
# -DTPCAL=<exe> -DPOINTS=<file> -DOUT=<json> [-DREFERENCE=<errors.yaml|points>] -DEXPECT_FAMILY=<family> | -DEXPECT_EXIT=<code>
# Runs the command, checks the exit code, and for a successful run the tpcal.diagnosis/1 JSON:
# schema, the required keys of docs/formats/diagnosis_json.md, the feature cross-validation block,
# the verdict family, and with a reference point file the point matching (every point matched).
file(REMOVE "${OUT}")
set(ref_args "")
if(DEFINED REFERENCE)
  set(ref_args --reference "${REFERENCE}")
endif()
execute_process(COMMAND "${TPCAL}" diagnose "${POINTS}" ${ref_args} --json "${OUT}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
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
        "verdict;family" "verdict;name" "verdict;shrink_pct" "verdict;indistinguishable_from"
        "cross_validation;not_held_out" "candidates;0;press_rms_after_um" "candidates;0;cv_not_held_out")
  string(JSON v ERROR_VARIABLE e GET "${json}" ${path})
  if(e)
    message(FATAL_ERROR "missing key ${path}: ${e}")
  endif()
endforeach()
string(JSON family GET "${json}" verdict family)
if(NOT family STREQUAL EXPECT_FAMILY)
  message(FATAL_ERROR "verdict ${family}, expected ${EXPECT_FAMILY}\n${out}")
endif()
if(DEFINED REFERENCE AND REFERENCE MATCHES "\\.(csv|ply|pcd|xyz|txt)$")
  string(JSON unmatched GET "${json}" reference_match unmatched)
  string(JSON n GET "${json}" gap n_points)
  if(NOT unmatched EQUAL 0 OR n LESS 300)
    message(FATAL_ERROR "reference points: ${unmatched} unmatched, ${n} diagnosed\n${out}")
  endif()
endif()
