# scripts/plot_report.py on a real report: a fast fit (least squares on the noise-free CVT
# recording, < 1 s) and a sensitivity run, then every figure must be a non-empty PNG.
# Called by ctest with -DTVID=... -DSOURCE_DIR=... -DWORK_DIR=... -DPYTHON=/usr/bin/python3.
# Without matplotlib the test prints SKIPPED (ctest then reports it as skipped, not passed).

execute_process(COMMAND ${PYTHON} -c "import matplotlib" RESULT_VARIABLE no_matplotlib OUTPUT_QUIET ERROR_QUIET)
if(no_matplotlib)
  message("SKIPPED: ${PYTHON} cannot import matplotlib (Debian: apt-get install python3-matplotlib)")
  return()
endif()

file(REMOVE_RECURSE ${WORK_DIR})
set(report ${WORK_DIR}/report)
set(experiment ${SOURCE_DIR}/configs/cvt_tipin_clean.yaml)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
endfunction()

run("tvid fit" ${TVID} fit ${experiment} -o ${report} --optimizer lm --set estimation.cost=l2 --quiet)
run("tvid sensitivity" ${TVID} sensitivity ${experiment} --params ${report}/params.json -o ${WORK_DIR}/sens --quiet)
run("plot_report.py" ${PYTHON} ${SOURCE_DIR}/scripts/plot_report.py ${report} -o ${WORK_DIR}/plots
    --sensitivity ${WORK_DIR}/sens --dpi 60)

run("tvid profile" ${TVID} profile ${experiment} --param d_ds --points 7 -o ${WORK_DIR}/profile
    --set estimation.optimizer=lm --set estimation.cost=l2 --set parameters.rho1=1.42855 --quiet)
run("plot_report.py profile" ${PYTHON} ${SOURCE_DIR}/scripts/plot_report.py ${WORK_DIR}/profile -o ${WORK_DIR}/plots --dpi 60)

foreach(name fit residual_ratio cost_history sensitivity_Tds profile)
  set(png ${WORK_DIR}/plots/${name}.png)
  if(NOT EXISTS ${png})
    message(FATAL_ERROR "${png} was not written")
  endif()
  file(SIZE ${png} size)
  file(READ ${png} signature LIMIT 8 HEX)
  if(size LESS 1000 OR NOT signature STREQUAL "89504e470d0a1a0a")
    message(FATAL_ERROR "${png} is not a PNG image (${size} bytes, starts with ${signature})")
  endif()
endforeach()

# Not a report directory: one error line naming the missing file, exit 2, no figure.
file(MAKE_DIRECTORY ${WORK_DIR}/empty)
execute_process(COMMAND ${PYTHON} ${SOURCE_DIR}/scripts/plot_report.py ${WORK_DIR}/empty
  RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT status EQUAL 2 OR NOT err MATCHES "summary.json: not found")
  message(FATAL_ERROR "plot_report.py on an empty folder: exit ${status}, '${err}'")
endif()
if(EXISTS ${WORK_DIR}/empty/plots/fit.png)
  message(FATAL_ERROR "plot_report.py drew a figure from an empty folder")
endif()
message("plot_report.py: 5 PNG figures from ${report} and ${WORK_DIR}/profile")
