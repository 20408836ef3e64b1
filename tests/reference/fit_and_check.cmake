# One reference-fit regression for ctest: `tvid fit` into a fresh report directory, then
# `tvid check` against the reference, whose table of checks lands in the test's output.
#   cmake -DTVID=... -DEXPERIMENT=... -DREFERENCE=... -DREPORT_DIR=... [-DFIT_ARGS=a|b|c] -P fit_and_check.cmake
# FIT_ARGS are extra `tvid fit` arguments separated by | (a ; would split the ctest command).
string(REPLACE "|" ";" fit_args "${FIT_ARGS}")
file(REMOVE_RECURSE "${REPORT_DIR}")  # never check a stale report

execute_process(COMMAND "${TVID}" fit "${EXPERIMENT}" -o "${REPORT_DIR}" ${fit_args} RESULT_VARIABLE fit_status)
# Exit 1 (no finite cost) still writes a report: let the check show what failed.
if(NOT fit_status EQUAL 0 AND NOT fit_status EQUAL 1)
  message(FATAL_ERROR "tvid fit ${EXPERIMENT} failed with exit status ${fit_status}")
endif()

execute_process(COMMAND "${TVID}" check "${REPORT_DIR}" --reference "${REFERENCE}" RESULT_VARIABLE check_status)
if(NOT check_status EQUAL 0)
  message(FATAL_ERROR "tvid check ${REPORT_DIR} --reference ${REFERENCE}: exit status ${check_status}")
endif()
