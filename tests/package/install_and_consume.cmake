# The CMake package, as a user meets it: install this build tree into an empty prefix,
# then configure and build tests/package/consumer (find_package(tvid CONFIG REQUIRED))
# against that prefix alone, run it on the installed CVT experiment, and check that the
# library gives the cost that the installed `tvid simulate` prints for the same parameters.
# Called by ctest with -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=...

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

# Fails with `what` unless the numbers a and b agree to `rel` of b.
function(require_close what a b rel)
  execute_process(COMMAND /usr/bin/python3 -c
    "import sys; a, b, rel = map(float, sys.argv[1:]); sys.exit(0 if abs(a - b) <= rel * max(abs(b), 1e-300) else 1)"
    ${a} ${b} ${rel} RESULT_VARIABLE same)
  if(NOT same EQUAL 0)
    message(FATAL_ERROR "${what}: ${a} against ${b}")
  endif()
endfunction()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed include/tvid/tvid.hpp share/tvid/configs/cvt_tipin.yaml bin/tvid share/tvid/scripts/plot_report.py
                  share/tvid/scripts/report_plots/common.py share/tvid/README.md share/tvid/docs/api.md
                  share/tvid/docs/getting-started.md share/tvid/tests/package/consumer/simulate_experiment.cpp)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "the install has no ${installed}")
  endif()
endforeach()
# Every link of the installed README and docs resolves in the installed tree.
run("the installed docs' links" /usr/bin/python3 ${SOURCE_DIR}/tests/docs/check_links.py ${prefix}/share/tvid)
file(GLOB_RECURSE headers RELATIVE ${prefix}/include ${prefix}/include/*)
if(NOT headers STREQUAL "tvid/tvid.hpp")
  message(FATAL_ERROR "the install has headers besides the public tvid/tvid.hpp: ${headers}")
endif()
file(GLOB_RECURSE config_files ${prefix}/*/tvidConfig.cmake)
if(NOT config_files)
  message(FATAL_ERROR "the install has no tvidConfig.cmake")
endif()
file(READ ${config_files} config_text)
if(NOT config_text MATCHES "CMAKE_LIBRARY_ARCHITECTURE")
  message(FATAL_ERROR "tvidConfig.cmake looks for NLopt only at a fixed path")
endif()
# What the exported target asks of its consumers: C++20, no vector-instruction or
# floating-point flags, no include folders of the library's dependencies.
file(GLOB_RECURSE target_files ${prefix}/*/tvidTargets.cmake)
file(READ ${target_files} targets_text)
foreach(flag -mavx2 -mfma -ffp-contract Eigen3::Eigen Boost::headers)
  string(FIND "${targets_text}" "${flag}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "the exported tvid::lib passes ${flag} to its consumers")
  endif()
endforeach()
if(NOT targets_text MATCHES "cxx_std_20")
  message(FATAL_ERROR "the exported tvid::lib does not ask for C++20")
endif()

# CMAKE_FIND_USE_PACKAGE_REGISTRY OFF and only this prefix: the build tree cannot be found
# by accident.
run("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/consumer
  -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)

set(experiment ${prefix}/share/tvid/configs/cvt_tipin.yaml)
run("the consumer" ${WORK_DIR}/consumer/simulate_experiment ${experiment} fit estimation.optimizer=lm estimation.cost=l2)
set(consumer_output "${run_output}")
if(NOT consumer_output MATCHES "cost ([-+0-9.eE]+)\n")
  message(FATAL_ERROR "the consumer printed no cost:\n${consumer_output}")
endif()
set(consumer_cost ${CMAKE_MATCH_1})
if(NOT consumer_output MATCHES "rmse_[A-Za-z0-9_]+ [0-9]")
  message(FATAL_ERROR "the consumer printed no output RMSE:\n${consumer_output}")
endif()

run("the installed tvid simulate" ${prefix}/bin/tvid simulate ${experiment} --json
  --set estimation.optimizer=lm --set estimation.cost=l2)
string(JSON tvid_cost GET "${run_output}" cost)
# Same library, same parameters, same windows: the same number to the last printed digit
# up to the 17-digit round trip of two formatters.
if(NOT consumer_cost GREATER 0)
  message(FATAL_ERROR "the consumer's cost ${consumer_cost} is not positive")
endif()
require_close("the consumer's cost against tvid simulate's" ${consumer_cost} ${tvid_cost} 1e-12)

# The fit through the API: the parameters `tvid fit` finds for the same experiment.
run("the installed tvid fit" ${prefix}/bin/tvid fit ${experiment} --set estimation.optimizer=lm --set estimation.cost=l2
  -o ${WORK_DIR}/fit --quiet --threads 2)
file(READ ${WORK_DIR}/fit/params.json params_text)
string(JSON count LENGTH "${params_text}" parameters)
set(compared 0)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  string(JSON name GET "${params_text}" parameters ${i} name)
  string(JSON fixed GET "${params_text}" parameters ${i} fixed)
  if(fixed)
    continue()
  endif()
  string(JSON value GET "${params_text}" parameters ${i} value)
  if(NOT consumer_output MATCHES "param ${name} ([-+0-9.eE]+) ")
    message(FATAL_ERROR "the consumer's fit printed no ${name}:\n${consumer_output}")
  endif()
  require_close("the consumer's fit against tvid fit for ${name}" ${CMAKE_MATCH_1} ${value} 1e-9)
  math(EXPR compared "${compared} + 1")
endforeach()
if(compared EQUAL 0)
  message(FATAL_ERROR "no free parameter compared")
endif()
message("the installed package: consumer cost ${consumer_cost}, tvid simulate ${tvid_cost}; ${compared} fitted parameters as tvid fit's")
