# CTest driver (pipeline/CMakeLists.txt, "datum-ball simulate/identify CLI tests"): the virtual
# datum-ball instrument read back by identify. -DTPCAL=<exe> -DERRORS=<tpcal.errors/1> -DWORK=<dir>
# Truth: seed 001 Table 1(a)'s 11 errors (samples/errors/seed001_table1a.yaml, um / urad, listed
# below under the names identify reports) on the nominal B/C table, the default plan (36
# readings), 0.5 um noise per coordinate, seed 3. `tpcal simulate --instrument datum_ball` writes
# the readings and the truth; `tpcal identify --instrument datum_ball` must put every error within
# 4 u (analytic, k = 1) of the truth, report the three uncertainty methods and no weights (the
# simulated file has no u_um column).
set(truth "E_A(0Y)Z=-34" "E_B(0X)Z=29" "E_C(0X)Y=17" "E_A0B=-17" "E_C0B=75" "E_X0B=-12" "E_Z0B=19"
          "E_A0C=-87" "E_B0C=42" "E_X0C=10" "E_Y0C=-15")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(COMMAND "${TPCAL}" simulate --instrument datum_ball --errors "${ERRORS}" --noise-um 0.5 --seed 3
  -o "${WORK}/ball.csv" --truth "${WORK}/truth.yaml" RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tpcal simulate --instrument datum_ball failed (${rc}):\n${err}")
endif()
file(READ "${WORK}/truth.yaml" truth_yaml)
if(NOT truth_yaml MATCHES "instrument: datum_ball\n.*seed: 3 .*noise_um: 0.5 .*E_C0B_urad: 75")
  message(FATAL_ERROR "the truth file does not state the run:\n${truth_yaml}")
endif()
execute_process(COMMAND "${TPCAL}" identify "${WORK}/ball.csv" --instrument datum_ball --json "${WORK}/id.json"
  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tpcal identify --instrument datum_ball failed (${rc}):\n${err}")
endif()
file(READ "${WORK}/id.json" json)
string(JSON weights GET "${json}" fit weights)
string(JSON runs GET "${json}" fit monte_carlo_runs)
if(NOT weights STREQUAL "none" OR NOT runs EQUAL 200)
  message(FATAL_ERROR "fit.weights '${weights}', fit.monte_carlo_runs ${runs}: expected none and 200")
endif()
string(JSON n LENGTH "${json}" parameters)
list(LENGTH truth n_truth)
if(NOT n EQUAL n_truth)
  message(FATAL_ERROR "${n} parameters, expected ${n_truth}")
endif()
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  string(JSON name GET "${json}" parameters ${i} name)
  string(JSON value GET "${json}" parameters ${i} value)
  string(JSON u GET "${json}" parameters ${i} u)
  foreach(method analytic jackknife_points monte_carlo)
    string(JSON um ERROR_VARIABLE e GET "${json}" parameters ${i} uncertainty ${method} u)
    if(e OR um STREQUAL "null")
      message(FATAL_ERROR "${name}: no ${method} u")
    endif()
  endforeach()
  set(expected "")
  foreach(t ${truth})
    string(FIND "${t}" "=" eq)
    string(SUBSTRING "${t}" 0 ${eq} tname)
    if(tname STREQUAL name)
      math(EXPR from "${eq} + 1")
      string(SUBSTRING "${t}" ${from} -1 expected)
    endif()
  endforeach()
  if(expected STREQUAL "")
    message(FATAL_ERROR "unexpected parameter ${name}")
  endif()
  # CMake has no floating-point arithmetic: awk compares |value - truth| with 4 u.
  execute_process(COMMAND awk -v v=${value} -v t=${expected} -v u=${u}
    "BEGIN { d = v - t; if (d < 0) d = -d; exit !(u > 0 && d < 4 * u) }" RESULT_VARIABLE far)
  if(NOT far EQUAL 0)
    message(FATAL_ERROR "${name}: ${value} +- ${u}, truth ${expected}: not within 4 u")
  endif()
  message(STATUS "${name}: ${value} +- ${u} (truth ${expected})")
endforeach()
message(STATUS "simulate --instrument datum_ball -> identify: every error within 4 u of the truth")
