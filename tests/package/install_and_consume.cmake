# The CMake package, as a user meets it: install this build tree into an empty prefix,
# then configure and build tests/package/consumer (find_package(tvid CONFIG REQUIRED))
# against that prefix alone, run it on the installed CVT experiment, and check that the
# library gives the cost that the installed `tvid simulate` prints for the same parameters.
# Called by ctest with -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=...

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed include/tvid/experiment/experiment.hpp share/tvid/configs/cvt_tipin.yaml bin/tvid)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "the install has no ${installed}")
  endif()
endforeach()
file(GLOB_RECURSE config_files ${prefix}/*/tvidConfig.cmake)
if(NOT config_files)
  message(FATAL_ERROR "the install has no tvidConfig.cmake")
endif()

# CMAKE_FIND_USE_PACKAGE_REGISTRY OFF and only this prefix: the build tree cannot be found
# by accident.
run("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/consumer
  -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)

set(experiment ${prefix}/share/tvid/configs/cvt_tipin.yaml)
run("the consumer" ${WORK_DIR}/consumer/simulate_experiment ${experiment})
set(consumer_output "${run_output}")
if(NOT consumer_output MATCHES "cost ([-+0-9.eE]+)\n")
  message(FATAL_ERROR "the consumer printed no cost:\n${consumer_output}")
endif()
set(consumer_cost ${CMAKE_MATCH_1})
if(NOT consumer_output MATCHES "rmse_[A-Za-z0-9_]+ [0-9]")
  message(FATAL_ERROR "the consumer printed no output RMSE:\n${consumer_output}")
endif()

run("the installed tvid simulate" ${prefix}/bin/tvid simulate ${experiment} --json)
string(JSON tvid_cost GET "${run_output}" cost)
# Same library, same parameters, same windows: the same number to the last printed digit
# up to the 17-digit round trip of two formatters.
execute_process(COMMAND /usr/bin/python3 -c
  "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if a > 0 and abs(a - b) <= 1e-12 * abs(b) else 1)"
  ${consumer_cost} ${tvid_cost} RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "the consumer's cost ${consumer_cost} differs from tvid simulate's ${tvid_cost}")
endif()
message("the installed package: consumer cost ${consumer_cost}, tvid simulate ${tvid_cost}")
