# One FFloor_* test: runs `PROGRAM eval DATASET` and checks that the F-measure it prints is at
# least FLOOR (in units of 1e-4, the precision eval prints), and that the ground-truth count is
# still TRUTH (a different count means a different dataset: the floor must be measured again).
# SKIP (the test's SKIP_REGULAR_EXPRESSION) when DATASET does not exist and SKIP_IF_MISSING is set.
if(NOT EXISTS "${DATASET}")
  if(SKIP_IF_MISSING)
    message("SKIP: no dataset at ${DATASET}")
    return()
  endif()
  message(FATAL_ERROR "no dataset at ${DATASET}")
endif()
execute_process(COMMAND ${PROGRAM} eval ${DATASET} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 300)
if(NOT rc STREQUAL "0")
  message(FATAL_ERROR "${PROGRAM} eval ${DATASET}: exit status ${rc}\n--- stdout:\n${out}--- stderr:\n${err}")
endif()
foreach(field "ground truth" detected correct F-measure)
  if(NOT out MATCHES "${field}: ([0-9.]+)")
    message(FATAL_ERROR "no '${field}:' line in the output of ${PROGRAM} eval ${DATASET}:\n${out}")
  endif()
  string(REPLACE " " "_" key "${field}")
  set(${key} ${CMAKE_MATCH_1})
endforeach()
if(NOT ground_truth STREQUAL TRUTH)
  message(FATAL_ERROR "${DATASET}: ground truth ${ground_truth}, the floor was measured on ${TRUTH}: measure it again")
endif()
# "0.9492" -> 9492, "1.0000" -> 10000 (CMake has integer arithmetic only).
string(REPLACE "." "" f_digits "${F-measure}")
math(EXPR f_e4 "${f_digits}")
message(STATUS "${DATASET}: truth ${ground_truth}, detected ${detected}, correct ${correct}, F ${F-measure} (floor 0.${FLOOR})")
if(f_e4 LESS FLOOR)
  message(FATAL_ERROR "${DATASET}: F ${F-measure} fell below the floor 0.${FLOOR} (more than one detection lost; "
                      "detected ${detected}, correct ${correct}, truth ${ground_truth})\n--- stdout:\n${out}")
endif()
